"""Floods at the socket, with real loopback sockets: one receive reads a bounded number of datagrams
and bytes, drops oversize datagrams unparsed, counts what the kernel dropped, bounds the peers (and
the link its parsers) a flood of source ports creates, and the real process keeps flying a
legitimate client's commands through a 10,000-datagram-per-second flood. (tests/sitl/test_floods.py
times the heartbeat through floods of each kind of costly request.)"""
from __future__ import annotations

import json
import select
import socket
import threading
import time

import pytest

from firefly.autopilot.io import udp
from firefly.autopilot.io.runner import incoming
from firefly.autopilot.mavlink import link as mavlink_link
from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.mavlink.signing import LinkSigning

from ..sitl.conftest import start_autopilot
from ..sitl.pymav import Gcs
from .frames import FrameSource


def _heartbeat() -> bytes:
    return bytes(new_codec(255, 190).heartbeat_encode(6, 8, 0, 0, 4).pack(new_codec(255, 190)))


def _link(signing_key: bytes | None = None) -> mavlink_link.Link:
    codec = new_codec(1)
    signing = LinkSigning(codec)
    signing.set_key(signing_key)
    return mavlink_link.Link(codec, signing)


def test_one_receive_reads_a_bounded_batch_and_kernel_drops_are_counted():
    endpoint = udp.UdpEndpoint(("127.0.0.1", 0), [])
    endpoint.sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 8192)  # overflow on purpose
    sent = 3000
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as client:
        frame = _heartbeat()
        for _ in range(sent):
            client.sendto(frame, endpoint.address)
        first = endpoint.receive()
        assert 0 < len(first) <= udp.MAX_DATAGRAMS_PER_RECEIVE
        total = len(first)
        while batch := endpoint.receive():
            total += len(batch)
    dropped = endpoint.totals()["kernel_dropped"]
    assert dropped > 0
    assert total + dropped == sent  # every datagram read or counted
    endpoint.close()


def _receive_all(endpoint) -> list[list]:
    """Each receive's datagrams until the socket has nothing left (a receive that only dropped an
    oversize datagram returns none, with more waiting)."""
    batches = []
    while select.select([endpoint.sock], [], [], 0)[0]:
        batches.append(endpoint.receive())
    return batches


def test_one_receive_stops_at_a_bounded_number_of_bytes():
    endpoint = udp.UdpEndpoint(("127.0.0.1", 0), [])
    big = bytes(udp.MAX_DATAGRAM_IN)  # the largest datagram still read
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as client:
        for _ in range(8):
            client.sendto(big, endpoint.address)
        client.sendto(_heartbeat(), endpoint.address)
        sizes = [sum(len(d) for d, _ in batch) for batch in _receive_all(endpoint)]
    assert sum(sizes) == 8 * len(big) + len(_heartbeat())  # all of it, in several receives ...
    assert max(sizes) < udp.MAX_BYTES_PER_RECEIVE + udp.MAX_DATAGRAM_IN  # ... each bounded
    assert len(sizes) >= 8 * len(big) // (udp.MAX_BYTES_PER_RECEIVE + udp.MAX_DATAGRAM_IN)
    endpoint.close()


def test_an_oversize_datagram_is_dropped_unread_and_counted_and_the_next_one_read():
    endpoint = udp.UdpEndpoint(("127.0.0.1", 0), [])
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as client:
        client.sendto(b"\xfd" * 65507, endpoint.address)  # the largest UDP datagram
        client.sendto(bytes(udp.MAX_DATAGRAM_IN + 1), endpoint.address)
        client.sendto(_heartbeat(), endpoint.address)
        received = [d for batch in _receive_all(endpoint) for d, _ in batch]
    assert received == [_heartbeat()]
    assert endpoint.counters["oversize_dropped"] == 2 and endpoint.counters["datagrams"] == 3
    endpoint.close()


def test_a_flood_of_source_ports_cannot_grow_peers_or_parsers_without_bound():
    out = ("127.0.0.1", 9)
    endpoint = udp.UdpEndpoint(("127.0.0.1", 0), [out])
    link = _link()
    clients = [socket.socket(socket.AF_INET, socket.SOCK_DGRAM) for _ in range(150)]
    for c in clients:
        c.bind(("127.0.0.1", 0))
    try:
        for c in clients:
            c.sendto(_heartbeat(), endpoint.address)
            assert len(list(incoming(endpoint.receive(), link, endpoint.answer))) == 1
        assert len(endpoint.peers) == 1 + udp.MAX_PEERS and endpoint.peers[0] == out  # outputs stay
        assert clients[-1].getsockname() in endpoint.peers  # the latest sender is answered
        assert clients[0].getsockname() not in endpoint.peers
        assert endpoint.counters["peers_evicted"] == 150 - udp.MAX_PEERS
        assert link.counters["parsers_evicted"] == 150 - mavlink_link.MAX_PARSERS
    finally:
        for c in clients:
            c.close()
        endpoint.close()


class Flood(threading.Thread):
    def __init__(self, address, rate: float):
        super().__init__(daemon=True)
        self.address, self.rate, self.stop, self.sent = address, rate, threading.Event(), 0
        self.source = FrameSource(9, target_system=2, others=(3,))  # hostile, for other systems only

    def run(self):
        frames = [self.source.frame()[1] for _ in range(2000)]
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
            t0 = time.monotonic()
            while not self.stop.is_set():
                s.sendto(frames[self.sent % len(frames)], self.address)
                self.sent += 1
                if self.sent % 100 == 0:
                    ahead = self.sent / self.rate - (time.monotonic() - t0)
                    if ahead > 0:
                        time.sleep(ahead)  # pacing the flood itself, not waiting for a result


@pytest.mark.sitl
@pytest.mark.serial  # the flood is paced in wall time
def test_the_vehicle_flies_a_clients_commands_through_a_10khz_flood(tmp_path):
    from ..sitl.conftest import free_udp_port
    listen = free_udp_port()
    stats = tmp_path / "stats.json"
    ap = start_autopilot(tmp_path, "5", ("--listen", f"udp:127.0.0.1:{listen}", "--stats", str(stats)))
    flood = Flood(("127.0.0.1", listen), 10_000)
    try:
        gcs = Gcs(ap.pymavlink_url)
        flood.start()
        assert gcs.command(176, 1, 4) == 0  # GUIDED
        assert gcs.command(400, 1) == 0  # arm
        assert gcs.command(22, 0, 0, 0, 0, 0, 0, 10.0) == 0  # takeoff 10 m
        climbed = gcs.recv("GLOBAL_POSITION_INT", 30, lambda m: m.relative_alt > 9000)
        assert climbed is not None, "no climb to 9 m during the flood"
        assert flood.sent > 5000
    finally:
        flood.stop.set()
        flood.join()
        ap.stop()
    report = json.loads(stats.read_text())
    counters = report["vehicles"][0]["counters"]
    assert report["exception"] is None and counters["handler_errors"] == 0
    # Read or counted as dropped; a few may still have been queued when the process stopped.
    assert counters["udp_datagrams"] + counters["udp_kernel_dropped"] >= 0.95 * flood.sent
    assert counters["ignored_other_system"] + counters["bad_data"] > flood.sent // 2
    # the socket's counters and the link's, under the udp_ names the report has always used
    assert {"udp_send_errors", "udp_peers_evicted", "udp_decode_errors", "udp_parsers_evicted"} <= set(counters)


def test_unsigned_radio_status_from_many_ports_cannot_push_the_signed_gcs_off_the_peers():
    """RADIO_STATUS passes signing unsigned (radios inject it), but its sender is not answered."""
    import hashlib

    from firefly.autopilot.mavlink.signing import signing_time
    key = hashlib.sha256(b"soak").digest()
    endpoint = udp.UdpEndpoint(("127.0.0.1", 0), [])
    link = _link(key)
    link.advance(time.time(), 0.0)
    gcs_codec = new_codec(255, 190)
    gcs_codec.signing.secret_key, gcs_codec.signing.sign_outgoing = key, True
    gcs_codec.signing.timestamp = signing_time(time.time())
    plain = new_codec(255, 190)
    radio = bytes(plain.radio_status_encode(200, 180, 90, 50, 40, 0, 0).pack(plain))
    gcs = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    gcs.bind(("127.0.0.1", 0))
    noisy = [socket.socket(socket.AF_INET, socket.SOCK_DGRAM) for _ in range(2 * udp.MAX_PEERS)]
    try:
        gcs.sendto(bytes(gcs_codec.heartbeat_encode(6, 8, 0, 0, 4).pack(gcs_codec)), endpoint.address)
        assert len(list(incoming(endpoint.receive(), link, endpoint.answer))) == 1 and gcs.getsockname() in endpoint.peers
        for s in noisy:
            s.sendto(radio, endpoint.address)
        assert len(list(incoming(endpoint.receive(), link, endpoint.answer))) == len(noisy)  # they reach the session ...
        assert endpoint.peers == [gcs.getsockname()]  # ... but are not answered
    finally:
        for s in [gcs, *noisy]:
            s.close()
        endpoint.close()

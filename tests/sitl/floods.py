"""Floods for the process-level flood tests: a sender run as its own process (so that it competes
for the machine as an outside attacker does, not for the test's interpreter), and a listener that
times the vehicle's HEARTBEATs and counts the answers to a legitimate client's probes.

    python -m tests.sitl.floods KIND HOST PORT --rate R --seconds S --ports N

KIND is one of KINDS. Every datagram comes from one of N sockets in turn (N source ports).
"""
from __future__ import annotations

import argparse
import socket
import struct
import subprocess
import sys
import threading
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
PROBE = 31999  # a command the vehicle answers UNSUPPORTED
HEARTBEAT_ID, COMMAND_ACK_ID = 0, 77


def _codec(system=250, component=1):
    from firefly.autopilot.mavlink.dialect import new_codec
    return new_codec(system, component)


def _frame(encode) -> bytes:
    c = _codec()
    return bytes(encode(c).pack(c))


def _ftp(seq: int, opcode: int, session: int = 1, data: bytes = b"", size: int | None = None) -> bytes:
    payload = struct.pack("<HBBBBBxI", seq & 0xFFFF, session, opcode, len(data) if size is None else size,
                          0, 0, 0) + data
    return _frame(lambda c: c.file_transfer_protocol_encode(0, 1, 1, list(payload.ljust(251, b"\0"))))


def datagrams(kind: str):
    """The first datagrams to send once, and a function of n giving the n-th flood datagram."""
    if kind == "param_list":
        frame = _frame(lambda c: c.param_request_list_encode(1, 1))
        return [], lambda n: frame
    if kind == "junk64k":  # the largest datagram UDP carries, of MAVLink 2 start bytes
        junk = b"\xfd" * 65507
        return [], lambda n: junk
    if kind == "junk2k":  # the costliest bytes for pymavlink's parser: an empty MAVLink 1 frame in 8
        junk = b"\xfe\x00" * 1024
        return [], lambda n: junk
    if kind == "ftp_burst":  # the file opened once, then burst reads of all of it, again and again
        return [_ftp(0, 4, data=b"@PARAM/param.pck")], lambda n: _ftp(n + 1, 15, size=239)
    if kind == "mission_list":  # a ground station's download requests, list and item 0, alternately
        items = [_frame(lambda c: c.mission_request_list_encode(1, 1, 0)),
                 _frame(lambda c: c.mission_request_int_encode(1, 1, 0, 0))]
        return [], lambda n: items[n % 2]
    if kind == "param_set":  # a value that changes every time, so each one is stored
        return [], lambda n: _frame(lambda c: c.param_set_encode(1, 1, b"WPNAV_SPEED", 500.0 + n % 500, 9))
    if kind == "mission_clear":
        frame = _frame(lambda c: c.mission_clear_all_encode(1, 1, 0))
        return [], lambda n: frame
    raise ValueError(f"unknown flood {kind}")


KINDS = ("param_list", "junk64k", "junk2k", "ftp_burst", "mission_list", "param_set", "mission_clear")


def send(kind: str, address: tuple, rate: float, seconds: float, ports: int) -> int:
    first, nth = datagrams(kind)
    socks = []
    for _ in range(ports):
        s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        s.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 1 << 20)
        s.bind(("127.0.0.1", 0))
        socks.append(s)
    for d in first:
        socks[0].sendto(d, address)
    sent, t0 = 0, time.monotonic()
    while (elapsed := time.monotonic() - t0) < seconds:
        ahead = sent / rate - elapsed
        if ahead > 0:
            time.sleep(min(ahead, 0.01))  # pacing the flood itself
            continue
        try:
            socks[sent % ports].sendto(nth(sent), address)
        except OSError:
            pass
        sent += 1
    for s in socks:
        s.close()
    return sent


def start_flood(kind: str, address: tuple, rate: float, seconds: float, ports: int) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "tests.sitl.floods", kind, address[0], str(address[1]),
                             "--rate", str(rate), "--seconds", str(seconds), "--ports", str(ports)],
                            cwd=REPO, stdout=subprocess.PIPE, text=True)


def _frames(datagram: bytes):
    """(message id, payload) of each MAVLink 2 frame of one of the vehicle's datagrams."""
    i = 0
    while i + 12 <= len(datagram) and datagram[i] == 0xFD:
        length, flags = datagram[i + 1], datagram[i + 2]
        msg_id = datagram[i + 7] | datagram[i + 8] << 8 | datagram[i + 9] << 16
        yield msg_id, datagram[i + 10:i + 10 + length]
        i += 12 + length + (13 if flags & 1 else 0)


class Listener:
    """Listens where the vehicle sends (its --out port): HEARTBEAT arrival times (wall, monotonic)
    and the COMMAND_ACKs of PROBE."""

    def __init__(self, port: int):
        self.heartbeats: list[float] = []
        self.probe_acks = 0
        self._changed = threading.Condition()
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 1 << 22)
        self.sock.bind(("127.0.0.1", port))
        self.sock.settimeout(0.1)  # how soon close() is noticed
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self):
        while not self._stop.is_set():
            try:
                data = self.sock.recv(65535)
            except socket.timeout:
                continue
            except OSError:
                return
            now = time.monotonic()
            with self._changed:
                for msg_id, payload in _frames(data):
                    if msg_id == HEARTBEAT_ID:
                        self.heartbeats.append(now)
                    elif (msg_id == COMMAND_ACK_ID and len(payload) >= 2
                          and struct.unpack_from("<H", payload)[0] == PROBE):
                        self.probe_acks += 1
                self._changed.notify_all()

    def wait(self, predicate, timeout: float) -> bool:
        """Whether predicate(self) came true within `timeout` (checked at each datagram)."""
        with self._changed:
            return self._changed.wait_for(lambda: predicate(self), timeout)

    def longest_gap(self, start: float, end: float) -> float:
        """The longest time without a HEARTBEAT between wall times start and end."""
        with self._changed:
            beats = [t for t in self.heartbeats if start <= t <= end]
        edges = [start] + beats + [end]
        return max(b - a for a, b in zip(edges, edges[1:]))

    def close(self):
        self._stop.set()
        self._thread.join()
        self.sock.close()


class Prober:
    """A legitimate client: a PROBE command every `every_s`, sent from the Listener's socket as a
    ground station listening on the --out port sends (the vehicle answers the link that asked)."""

    def __init__(self, address: tuple, sock: socket.socket, every_s: float = 0.25):
        self.address, self.every_s, self.sent = address, every_s, 0
        self.sock = sock
        self._stop = threading.Event()
        c = _codec(255, 190)
        self._codec = c
        self._thread = threading.Thread(target=self._run, daemon=True)

    def start(self):
        self._thread.start()

    def _run(self):
        c = self._codec
        while not self._stop.wait(self.every_s):  # the client's own pace, not a synchronisation
            probe = c.command_long_encode(1, 1, PROBE, 0, 0, 0, 0, 0, 0, 0, 0)
            self.sock.sendto(bytes(probe.pack(c)), self.address)
            self.sent += 1

    def stop(self):
        self._stop.set()
        self._thread.join()


def main(argv=None) -> int:
    p = argparse.ArgumentParser()
    p.add_argument("kind", choices=KINDS)
    p.add_argument("host")
    p.add_argument("port", type=int)
    p.add_argument("--rate", type=float, default=8000)
    p.add_argument("--seconds", type=float, default=5)
    p.add_argument("--ports", type=int, default=300)
    a = p.parse_args(argv)
    print(send(a.kind, (a.host, a.port), a.rate, a.seconds, a.ports), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""MAVLink FTP through the vehicle's session, sans-IO: the answers the reference ArduCopter gives
(recorded in tests/parity/recorded/ftp_reference.json), in sim time."""
from __future__ import annotations

import struct
import zlib

import pytest
from pymavlink.mavftp import MAVFTP

from firefly.autopilot.mavlink import ftp
from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.params import SPEC_BY_NAME

from ._session_link import SYSTEM_ID, Link, gcs, link  # noqa: F401 - link is a fixture
from ._util import wire

PARAMS = b"@PARAM/param.pck"


ROUND_TRIP_S = 0.01  # link time between a client's requests


class Client:
    """A ground station's FTP side: numbered requests, replies decoded; each request ROUND_TRIP_S
    of link time after the one before, so in an exchange of its own, as a client that waits for
    each answer sends them."""

    def __init__(self, link, codec=None):
        self.link = link
        self.codec = codec or gcs()
        self.seq = 0
        self.now = 0.0

    def request(self, opcode, session=1, data=b"", size=None, offset=0, seq=None, target=SYSTEM_ID):
        self.now += ROUND_TRIP_S
        seq = self.seq if seq is None else seq
        self.seq = (seq + 1) & 0xFFFF
        size = len(data) if size is None else size
        payload = ftp.Packet(seq, session, opcode, size, offset=offset, data=data).encode()
        out = self.link.send(wire(self.codec.file_transfer_protocol_encode(0, target, 1, payload), self.codec),
                             self.now)
        replies = [m for m in out if m.get_type() == "FILE_TRANSFER_PROTOCOL"]
        for m in replies:
            assert (m.target_system, m.target_component) == (self.codec.srcSystem, self.codec.srcComponent)
        return [ftp.Packet.parse(bytes(m.payload)) for m in replies]

    def one(self, *a, **kw) -> ftp.Packet:
        replies = self.request(*a, **kw)
        assert len(replies) == 1, replies
        return replies[0]


def nak(reply: ftp.Packet) -> bytes:
    assert reply.opcode == ftp.NAK, reply
    return reply.data[:reply.size]


@pytest.fixture
def client(link):
    return Client(link)


def _assemble(replies, start: int = 0) -> bytes:
    """The data of a burst's ACKs, which must follow each other from offset `start`."""
    data = bytearray()
    for r in replies:
        if r.opcode == ftp.ACK:
            assert r.offset == start + len(data)
            data += r.data[:r.size]
    return bytes(data)


def _decoded(data: bytes) -> dict:
    parsed = MAVFTP.ftp_param_decode(data)
    assert parsed is not None
    return {name.decode(): value for name, value, _ in parsed.params}


def _f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


# ----- download ---------------------------------------------------------------------------------
def test_burst_download_of_every_parameter(client, link):
    params = link.vehicle.params
    assert client.one(ftp.RESET_SESSIONS, session=0).opcode == ftp.ACK
    opened = client.one(ftp.OPEN_FILE_RO, data=PARAMS)
    assert (opened.opcode, opened.seq, opened.req_opcode, opened.size) == (ftp.ACK, 2, ftp.OPEN_FILE_RO, 4)
    assert struct.unpack("<I", opened.data[:4])[0] == 12 * len(params)  # ArduPilot's estimate
    replies = client.request(ftp.BURST_READ_FILE, size=0)
    acks, end = replies[:-1], replies[-1]
    assert [r.seq for r in replies] == list(range(3, 3 + len(replies)))  # one seq per reply
    assert all(r.size == 239 and not r.burst_complete for r in acks[:-1])
    assert acks[-1].burst_complete == 1 and acks[-1].size < 239
    data = _assemble(acks)
    assert nak(end) == bytes([ftp.END_OF_FILE]) and end.offset == len(data) and end.burst_complete == 1
    values = _decoded(data)
    assert list(values) == params.names()
    assert all(values[n] == _f32(params[n]) for n in params.names())
    assert client.one(ftp.TERMINATE_SESSION).opcode == ftp.ACK


def _burst_all(client, size: int, session: int = 1, start: int = 0) -> bytes:
    """The open file from `start` by bursts, each from where the last ended, until EndOfFile (as
    MAVFTP and QGroundControl ask again after a burst_complete that is not the end)."""
    data = bytearray()
    for _ in range(20):
        replies = client.request(ftp.BURST_READ_FILE, session=session, size=size, offset=start + len(data))
        assert replies
        data += _assemble(replies, start + len(data))
        if replies[-1].opcode == ftp.NAK:
            assert nak(replies[-1]) == bytes([ftp.END_OF_FILE])
            return bytes(data)
        assert replies[-1].burst_complete == 1
    raise AssertionError("no EndOfFile after 20 bursts")


def test_sequential_reads_give_the_burst_bytes_and_end_in_eof(client):
    client.one(ftp.OPEN_FILE_RO, data=PARAMS)
    burst = _burst_all(client, 80)
    data = bytearray()
    while True:
        r = client.one(ftp.READ_FILE, size=80, offset=len(data))
        if r.opcode == ftp.NAK:
            assert nak(r) == bytes([ftp.END_OF_FILE]) and r.offset == 0
            break
        assert r.offset == len(data) and r.req_opcode == ftp.READ_FILE
        data += r.data[:r.size]
    assert bytes(data) == burst
    # every read of one open file must be of one size (the padding depends on it): errno EINVAL
    assert nak(client.one(ftp.READ_FILE, size=239, offset=0)) == bytes([ftp.FAIL_ERRNO, 22])
    assert nak(client.one(ftp.BURST_READ_FILE, size=80, offset=len(data) + 5000)) == bytes([ftp.END_OF_FILE])


def test_the_file_is_a_snapshot_taken_at_open(client, link):
    client.one(ftp.OPEN_FILE_RO, data=PARAMS)
    link.vehicle.params.set("WPNAV_SPEED", 1500)
    assert _decoded(_assemble(client.request(ftp.BURST_READ_FILE)))["WPNAV_SPEED"] == 1000


def test_with_defaults_and_a_slice(client, link):
    link.vehicle.params.set("RTL_ALT", 3000)
    client.one(ftp.OPEN_FILE_RO, data=PARAMS + b"?withdefaults=1")
    parsed = MAVFTP.ftp_param_decode(_assemble(client.request(ftp.BURST_READ_FILE)))
    defaults = {n.decode(): v for n, v, _ in parsed.defaults}
    assert defaults["RTL_ALT"] == SPEC_BY_NAME["RTL_ALT"].default
    client.one(ftp.TERMINATE_SESSION)
    client.one(ftp.OPEN_FILE_RO, data=PARAMS + b"?start=3&count=2")
    data = _assemble(client.request(ftp.BURST_READ_FILE))
    total = len(link.vehicle.params)
    assert struct.unpack_from("<HHH", data) == (0x671B, 2, total)
    assert list(_decoded(data)) == link.vehicle.params.names()[3:5]


def test_a_lost_reply_is_sent_again_for_a_repeated_request(client):
    client.one(ftp.OPEN_FILE_RO, data=PARAMS)
    first = client.one(ftp.READ_FILE, size=239, offset=0)
    again = client.one(ftp.READ_FILE, size=239, offset=0, seq=client.seq - 1)
    assert again == first


# ----- refusals -----------------------------------------------------------------------------------
@pytest.mark.parametrize("request_kw, expected", [
    (dict(opcode=ftp.OPEN_FILE_RO, data=b"@PARAM/nope.pck"), bytes([ftp.FILE_NOT_FOUND])),
    (dict(opcode=ftp.OPEN_FILE_RO, data=b"/no/such/file"), bytes([ftp.FILE_NOT_FOUND])),
    (dict(opcode=ftp.OPEN_FILE_RO, data=PARAMS, size=0), bytes([ftp.INVALID_DATA_SIZE])),
    (dict(opcode=ftp.OPEN_FILE_RO, data=PARAMS, size=5), bytes([ftp.INVALID_DATA_SIZE])),
    (dict(opcode=ftp.OPEN_FILE_RO, data=PARAMS + b"?start=70000"), bytes([ftp.FAIL_ERRNO, 22])),
    (dict(opcode=ftp.OPEN_FILE_RO, data=PARAMS + b"?withdefaults=2"), bytes([ftp.FAIL_ERRNO, 22])),
    (dict(opcode=ftp.READ_FILE, size=239), bytes([ftp.FILE_NOT_FOUND])),
    (dict(opcode=ftp.BURST_READ_FILE, size=239), bytes([ftp.FILE_NOT_FOUND])),
    (dict(opcode=ftp.WRITE_FILE, data=b"abc"), bytes([ftp.FILE_NOT_FOUND])),
    (dict(opcode=ftp.READ_FILE, size=240), bytes([ftp.INVALID_DATA_SIZE])),
    (dict(opcode=ftp.LIST_DIRECTORY, data=b"/nothing"), bytes([ftp.FILE_NOT_FOUND])),
    (dict(opcode=ftp.LIST_DIRECTORY, data=b""), bytes([ftp.INVALID_DATA_SIZE])),
    (dict(opcode=ftp.LIST_DIRECTORY, data=b"@PARAM"), bytes([ftp.FILE_NOT_FOUND])),
    (dict(opcode=ftp.CALC_FILE_CRC32, data=b"@PARAM/x"), bytes([ftp.FILE_NOT_FOUND])),
    (dict(opcode=ftp.REMOVE_FILE, data=PARAMS), bytes([ftp.FILE_NOT_FOUND])),
    (dict(opcode=ftp.CREATE_DIRECTORY, data=b"@PARAM/d"), bytes([ftp.FILE_NOT_FOUND])),
    (dict(opcode=ftp.RENAME, data=PARAMS + b"\0@PARAM/x.pck"), bytes([ftp.FILE_NOT_FOUND])),
    (dict(opcode=ftp.OPEN_FILE_WO, data=b"/tmp_ftp_probe.txt"), bytes([ftp.FILE_NOT_FOUND])),
])
def test_naks_as_the_reference_gives_them(client, request_kw, expected):
    reply = client.one(**request_kw)
    assert nak(reply) == expected
    assert reply.seq == 1 and reply.session == 1 and reply.req_opcode == request_kw["opcode"]


@pytest.mark.parametrize("opcode", [ftp.TRUNCATE_FILE, 99])
def test_unsupported_opcodes_fail_with_a_debug_text(client, link, opcode):
    assert nak(client.one(opcode, data=PARAMS)) == bytes([ftp.FAIL])
    assert link.vehicle.drain_events()[-1] == (7, f"Unsupported FTP: {opcode}")


def test_one_open_file_across_sessions_until_the_holder_goes_silent(link):
    holder, other = Client(link), Client(link)
    assert holder.one(ftp.OPEN_FILE_RO, session=1, data=PARAMS).opcode == ftp.ACK
    assert nak(holder.one(ftp.OPEN_FILE_RO, session=1, data=PARAMS)) == bytes([ftp.FAIL])
    assert nak(other.one(ftp.OPEN_FILE_RO, session=2, data=PARAMS)) == bytes([ftp.INVALID_SESSION])
    assert nak(other.one(ftp.READ_FILE, session=2, size=239)) == bytes([ftp.INVALID_SESSION])
    # ending another session closes nothing
    assert other.one(ftp.TERMINATE_SESSION, session=2).opcode == ftp.ACK
    assert holder.one(ftp.READ_FILE, session=1, size=239).opcode == ftp.ACK
    other.now = holder.now + ftp.SESSION_TIMEOUT_S + 0.1
    assert other.one(ftp.OPEN_FILE_RO, session=2, data=PARAMS).opcode == ftp.ACK
    assert nak(holder.one(ftp.READ_FILE, session=1, size=239)) == bytes([ftp.INVALID_SESSION])


# ----- a session belongs to the client that opened it --------------------------------------------
def _owner_and_stranger(link, stranger_ids):
    owner, stranger = Client(link), Client(link, new_codec(*stranger_ids))
    assert owner.one(ftp.OPEN_FILE_RO, session=1, data=PARAMS).opcode == ftp.ACK
    return owner, stranger


@pytest.mark.parametrize("stranger_ids", [(255, 191), (254, 190)])  # another component, another system
def test_another_client_cannot_use_the_owners_session_number(link, stranger_ids):
    owner, stranger = _owner_and_stranger(link, stranger_ids)
    for opcode, kw in ((ftp.READ_FILE, dict(size=239)), (ftp.BURST_READ_FILE, dict(size=239)),
                       (ftp.OPEN_FILE_RO, dict(data=PARAMS)), (ftp.WRITE_FILE, dict(data=b"x"))):
        reply = stranger.one(opcode, session=1, **kw)
        assert nak(reply) == bytes([ftp.INVALID_SESSION]) and reply.session == 1
    assert link.session.ftp.counters["refused_not_owner"] == 4
    first = owner.one(ftp.READ_FILE, session=1, size=239)
    assert first.opcode == ftp.ACK and first.offset == 0


@pytest.mark.parametrize("opcode", [ftp.TERMINATE_SESSION, ftp.RESET_SESSIONS])
def test_another_clients_terminate_or_reset_is_acked_and_closes_nothing(link, opcode):
    owner, stranger = _owner_and_stranger(link, (255, 191))
    assert stranger.one(opcode, session=1).opcode == ftp.ACK  # as ArduPilot: always acknowledged
    assert owner.one(ftp.READ_FILE, session=1, size=239).opcode == ftp.ACK  # still open
    assert owner.one(opcode, session=1).opcode == ftp.ACK  # the owner's own closes it
    assert nak(owner.one(ftp.READ_FILE, session=1, size=239)) == bytes([ftp.FILE_NOT_FOUND])


def test_another_clients_requests_do_not_keep_a_silent_owners_session_alive(link):
    owner, stranger = _owner_and_stranger(link, (255, 191))
    while stranger.now < owner.now + ftp.SESSION_TIMEOUT_S:  # refused all along ...
        assert nak(stranger.one(ftp.OPEN_FILE_RO, session=1, data=PARAMS)) == bytes([ftp.INVALID_SESSION])
        stranger.now += 0.5
    # ... and once the owner has been silent for the timeout, the session is the stranger's
    assert stranger.one(ftp.OPEN_FILE_RO, session=1, data=PARAMS).opcode == ftp.ACK
    owner.now = stranger.now
    assert nak(owner.one(ftp.READ_FILE, session=1, size=239)) == bytes([ftp.INVALID_SESSION])
    assert stranger.one(ftp.READ_FILE, session=1, size=239).opcode == ftp.ACK


def test_a_repeated_seq_from_another_client_does_not_get_the_owners_last_reply(link):
    owner, stranger = _owner_and_stranger(link, (255, 191))
    data = owner.one(ftp.READ_FILE, session=1, size=239)
    assert data.opcode == ftp.ACK
    again = stranger.one(ftp.READ_FILE, session=1, size=239, seq=data.seq - 1)
    assert nak(again) == bytes([ftp.INVALID_SESSION])  # a refusal, not the owner's data


# ----- bounded work -------------------------------------------------------------------------------
def test_requests_read_together_are_answered_within_one_exchanges_allowance_the_rest_dropped(link):
    client = Client(link)
    answered = 0
    for _ in range(50):  # fifty CRCs of the parameter file (each packs it) in one exchange
        client.now -= ROUND_TRIP_S  # the same link time: read together
        answered += len(client.request(ftp.CALC_FILE_CRC32, data=PARAMS))
    assert answered == ftp.EXCHANGE_WORK // (2 * ftp.FILE_WORK + 1) < 50
    assert link.session.ftp.counters["dropped_busy"] == 50 - answered
    # a client that waits for each answer (each request in a later exchange) is always answered
    assert all(client.one(ftp.CALC_FILE_CRC32, data=PARAMS).opcode == ftp.ACK for _ in range(5))


def test_over_time_the_work_is_bounded_by_the_rate_whatever_the_exchanges(link):
    client = Client(link)
    served, per_crc, exchanges, dt = 0, 2 * ftp.FILE_WORK + 1, 400, 1e-4
    for _ in range(exchanges):  # one CRC an exchange, ten thousand exchanges a second
        client.now += dt - ROUND_TRIP_S
        served += len(client.request(ftp.CALC_FILE_CRC32, data=PARAMS))
    bound = (ftp.WORK_ALLOWANCE + ftp.WORK_PER_S * exchanges * dt) / per_crc
    assert bound - 2 <= served <= bound + 1  # all the allowance and the rate allow, no more


def test_a_burst_the_allowance_cannot_cover_ends_early_and_the_client_asks_for_the_rest(link):
    client = Client(link)
    client.one(ftp.OPEN_FILE_RO, data=PARAMS)
    first = client.request(ftp.BURST_READ_FILE, size=80)  # 80-byte blocks: some 190 of them
    covered = ftp.EXCHANGE_WORK - ftp.FILE_WORK  # what the packing leaves of the allowance
    assert len(first) == covered and all(r.opcode == ftp.ACK for r in first)
    assert first[-1].burst_complete == 1 and not any(r.burst_complete for r in first[:-1])
    data = _assemble(first) + _burst_all(client, 80, start=covered * 80)
    assert len(data) > covered * 80 and list(_decoded(data)) == link.vehicle.params.names()


def test_ftp_addressed_to_another_system_is_ignored_and_replies_are_never_answered(client):
    assert client.request(ftp.OPEN_FILE_RO, data=PARAMS, target=SYSTEM_ID + 1) == []
    for reply_opcode in (ftp.ACK, ftp.NAK):
        assert client.request(reply_opcode) == []
    assert client.one(ftp.NONE, target=0).opcode == ftp.ACK  # broadcast is ours
    assert client.one(ftp.RESET_SESSIONS, seq=0xFFFF).seq == 0  # seq wraps


def test_crc_of_the_parameter_file_is_over_64_byte_reads(client):
    reply = client.one(ftp.CALC_FILE_CRC32, data=PARAMS)
    assert reply.opcode == ftp.ACK and reply.size == 4
    client.one(ftp.OPEN_FILE_RO, data=PARAMS)
    data = bytearray()
    while (r := client.one(ftp.READ_FILE, size=64, offset=len(data))).opcode == ftp.ACK:
        data += r.data[:r.size]
    assert struct.unpack("<I", reply.data[:4])[0] == zlib.crc32(bytes(data), 0xFFFFFFFF) ^ 0xFFFFFFFF


# ----- upload -----------------------------------------------------------------------------------
def _upload_file(values: dict) -> bytes:
    body = b""
    for name, (ptype, value) in values.items():
        fmt = {3: "<i", 4: "<f"}[ptype]
        body += bytes([ptype, (len(name) - 1) << 4]) + name.encode() + struct.pack(fmt, value)
    return struct.pack("<HHH", 0x671B, len(values), 6 + len(body)) + body


@pytest.mark.parametrize("open_opcode", [ftp.CREATE_FILE, ftp.OPEN_FILE_WO])
def test_upload_sets_the_parameters_when_the_session_ends(client, link, open_opcode):
    params = link.vehicle.params
    f = _upload_file({"WPNAV_SPEED": (4, 1234.0), "RTL_ALT": (3, 2345), "NOT_A_PARAM": (4, 1.0),
                      "LAND_SPEED": (4, 5.0)})  # 5 cm/s is below LAND_SPEED's range: refused
    assert client.one(open_opcode, data=PARAMS).opcode == ftp.ACK
    first = client.one(ftp.WRITE_FILE, offset=0, data=f[:20])
    assert (first.opcode, first.offset, first.size) == (ftp.ACK, 0, 0)
    assert client.one(ftp.WRITE_FILE, offset=20, data=f[20:]).offset == 20
    assert nak(client.one(ftp.READ_FILE, size=239)) == bytes([ftp.FAIL])
    assert params["WPNAV_SPEED"] == 1000  # nothing set before the file is complete
    assert client.one(ftp.TERMINATE_SESSION).opcode == ftp.ACK
    assert (params["WPNAV_SPEED"], params["RTL_ALT"], params["LAND_SPEED"]) == (1234, 2345, 50)
    assert any("LAND_SPEED" in text for _, text in link.vehicle.drain_events())


def test_a_bad_upload_changes_nothing_and_a_huge_offset_is_refused(client, link):
    f = _upload_file({"WPNAV_SPEED": (4, 1234.0)})
    client.one(ftp.OPEN_FILE_WO, data=PARAMS)
    assert nak(client.one(ftp.WRITE_FILE, offset=2 ** 31, data=b"x")) == bytes([ftp.FAIL_ERRNO, 12])
    client.one(ftp.WRITE_FILE, offset=0, data=b"\x00\x11" + f[2:])
    assert client.one(ftp.TERMINATE_SESSION).opcode == ftp.ACK
    assert link.vehicle.params["WPNAV_SPEED"] == 1000

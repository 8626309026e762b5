"""LOG_REQUEST_* through the vehicle's session with real log files, sans sockets: the answers
ArduCopter 4.7 SITL gives (measured: listing, 90-byte LOG_DATA chunks, the hostile requests, armed),
and FTP's listing of the root and logs/."""
from __future__ import annotations

import struct
import zlib

import pytest

from firefly.autopilot.io.dataflash_files import LogFiles
from firefly.autopilot.mavlink import ftp
from firefly.autopilot.mavlink.log_service import CHUNK, DATA_PER_POLL

from ._session_link import Link
from ._util import client_codec, of_type, statustexts, wire

LOG_BYTES = bytes(range(256)) * 20  # 5120 bytes: 56 full chunks and one of 80


@pytest.fixture
def logs_link(tmp_path):
    link = Link()
    files = LogFiles(tmp_path / "logs", link.vehicle.params)
    for payload in (b"first log", LOG_BYTES):
        files.start()
        files.write(payload)
        files.stop()
    link.session.logs.store = files
    link.session.ftp.tree.logs = files
    link.files = files
    return link


def request_list(start=0, end=0xFFFF):
    return wire(client_codec().log_request_list_encode(1, 1, start, end))


def request_data(log_id, ofs=0, count=0xFFFFFFFF):
    return wire(client_codec().log_request_data_encode(1, 1, log_id, ofs, count))


def drain(link, kind, most=1000) -> list:
    out = []
    for _ in range(most):
        got = of_type(link.poll(), kind)
        if not got and not link.session.logs.activity:
            break
        out.extend(got)
    return out


def test_list_names_every_log(logs_link):
    out = of_type(logs_link.send(request_list()), "LOG_ENTRY") + drain(logs_link, "LOG_ENTRY")
    assert [(e.id, e.num_logs, e.last_log_num, e.size) for e in out] == [(1, 2, 2, 9), (2, 2, 2, len(LOG_BYTES))]
    assert all(e.time_utc > 1_600_000_000 for e in out)


def test_no_logs_lists_one_empty_entry(tmp_path):
    link = Link()
    link.session.logs.store = LogFiles(tmp_path / "none", link.vehicle.params)
    out = of_type(link.send(request_list()), "LOG_ENTRY")
    assert [(e.id, e.num_logs, e.last_log_num, e.size) for e in out] == [(0, 0, 0, 0)]
    assert not link.session.logs.activity


def test_download_is_the_file_in_90_byte_chunks(logs_link):
    first = of_type(logs_link.send(request_data(2)), "LOG_DATA")
    assert len(first) == DATA_PER_POLL
    chunks = first + drain(logs_link, "LOG_DATA")
    assert [c.ofs for c in chunks] == list(range(0, len(LOG_BYTES), CHUNK))
    assert b"".join(bytes(c.data[:c.count]) for c in chunks) == LOG_BYTES
    assert chunks[-1].count == len(LOG_BYTES) % CHUNK and not logs_link.session.logs.activity


@pytest.mark.parametrize("ofs, count, expected", [
    (0xFFFFFFF0, 900, [(0xFFFFFFF0, 0)]),  # past the end: one empty chunk (measured)
    (0, 0, [(0, 0)]),
    (5, 7, [(5, 7)]),
])
def test_partial_and_hostile_ranges(logs_link, ofs, count, expected):
    out = of_type(logs_link.send(request_data(2, ofs, count)), "LOG_DATA") + drain(logs_link, "LOG_DATA")
    assert [(c.ofs, c.count) for c in out] == expected


@pytest.mark.parametrize("log_id", [0, 3, 99, 0xFFFF])
def test_missing_log_is_not_answered(logs_link, log_id):
    assert logs_link.send(request_data(log_id)) == [] and drain(logs_link, "LOG_DATA") == []


def test_list_with_start_past_end_counts_up_and_end_stops_it(logs_link):
    out = of_type(logs_link.send(request_list(5, 3)), "LOG_ENTRY")
    out += of_type(logs_link.poll(), "LOG_ENTRY")
    assert [e.id for e in out] == list(range(5, 5 + len(out))) and all(e.size == 0 for e in out)
    assert statustexts(logs_link.send(request_list())) == ["Log download in progress"]
    logs_link.send(wire(client_codec().log_request_end_encode(1, 1)))
    assert not logs_link.session.logs.activity


def test_armed_requests_get_one_warning_and_change_nothing(logs_link):
    v = logs_link.vehicle
    assert v.arm() == 0
    assert statustexts(logs_link.send(request_list())) == ["Disarm for log download"]
    assert logs_link.send(request_list()) == []
    assert logs_link.send(wire(client_codec().log_erase_encode(1, 1))) == []
    assert logs_link.files.count() == 2
    v.disarm(force=True)
    logs_link.send(wire(client_codec().log_erase_encode(1, 1)))
    assert logs_link.files.count() == 0


def ftp_list(link, path: bytes, offset=0) -> ftp.Packet:
    link.ftp_seq = getattr(link, "ftp_seq", 0) + 2
    payload = ftp.Packet(link.ftp_seq, 0, ftp.LIST_DIRECTORY, len(path), offset=offset, data=path).encode()
    msg = wire(client_codec().file_transfer_protocol_encode(0, 1, 1, payload))
    reply = of_type(link.send(msg, link.vehicle.time_s + link.ftp_seq), "FILE_TRANSFER_PROTOCOL")[0]
    return ftp.Packet.parse(reply.payload)


def test_ftp_lists_the_root_and_logs_as_the_reference(logs_link):
    root = ftp_list(logs_link, b"/")
    assert root.opcode == ftp.ACK and root.data[:root.size] == b"D.\0\0Dlogs\0\0D..\0\0Dterrain\0\0D@ROMFS\0\0D@SYS\0\0"
    assert ftp_list(logs_link, b"/", 5).data[:7] == b"D@SYS\0\0"
    assert ftp_list(logs_link, b"/", 6).data[0] == ftp.END_OF_FILE
    logs = ftp_list(logs_link, b"logs")
    assert logs.data[:logs.size].split(b"\0\0")[:-1] == [
        b"D.", b"D..", b"F00000001.BIN\t9", f"F00000002.BIN\t{len(LOG_BYTES)}".encode(), b"FLASTLOG.TXT\t3"]
    not_dir = ftp_list(logs_link, b"logs/00000001.BIN")
    assert not_dir.opcode == ftp.NAK and not_dir.data[:2] == bytes([ftp.FAIL_ERRNO, 20])
    for empty in (b"@SYS", b"@ROMFS"):
        assert ftp_list(logs_link, empty).data[0] == ftp.END_OF_FILE


def test_ftp_crc_of_a_log_is_arducopters(logs_link):
    logs_link.ftp_seq = 100
    path = b"logs/00000002.BIN"
    payload = ftp.Packet(logs_link.ftp_seq, 0, ftp.CALC_FILE_CRC32, len(path), data=path).encode()
    msg = wire(client_codec().file_transfer_protocol_encode(0, 1, 1, payload))
    reply = ftp.Packet.parse(of_type(logs_link.send(msg), "FILE_TRANSFER_PROTOCOL")[0].payload)
    expected = zlib.crc32(LOG_BYTES, 0xFFFFFFFF) ^ 0xFFFFFFFF  # no initial or final inversion
    assert reply.opcode == ftp.ACK and struct.unpack("<I", reply.data[:4])[0] == expected


def ftp_request(link, opcode, data=b"", size=None, offset=0) -> list[ftp.Packet]:
    link.ftp_seq = getattr(link, "ftp_seq", 0) + 2
    size = len(data) if size is None else size
    payload = ftp.Packet(link.ftp_seq, 1, opcode, size, offset=offset, data=data).encode()
    msg = wire(client_codec().file_transfer_protocol_encode(0, 1, 1, payload))
    replies = of_type(link.send(msg, link.vehicle.time_s + link.ftp_seq), "FILE_TRANSFER_PROTOCOL")
    return [ftp.Packet.parse(r.payload) for r in replies]


def test_ftp_reads_a_log(logs_link):
    opened = ftp_request(logs_link, ftp.OPEN_FILE_RO, b"/logs/00000002.BIN")[0]
    assert opened.opcode == ftp.ACK and struct.unpack("<I", opened.data[:4])[0] == len(LOG_BYTES)
    got = b""
    while True:
        reply = ftp_request(logs_link, ftp.READ_FILE, size=ftp.DATA_SIZE, offset=len(got))[0]
        if reply.opcode == ftp.NAK:
            assert reply.data[0] == ftp.END_OF_FILE
            break
        got += reply.data[:reply.size]
    assert got == LOG_BYTES
    assert ftp_request(logs_link, ftp.TERMINATE_SESSION)[0].opcode == ftp.ACK
    for missing in (b"logs/00000009.BIN", b"logs/../params.json", b"logs/", b"terrain/x"):
        reply = ftp_request(logs_link, ftp.OPEN_FILE_RO, missing)[0]
        assert reply.opcode == ftp.NAK and reply.data[0] == ftp.FILE_NOT_FOUND, missing


def test_a_download_goes_to_the_link_that_asked(logs_link):
    session = logs_link.session
    first = session.receive(request_data(2), logs_link.vehicle.time_s, link="tcp-1")
    assert len(first) == DATA_PER_POLL  # the answer itself goes where the request came from
    assert not of_type(session.poll(logs_link.vehicle.time_s), "LOG_DATA")  # the rest is not for every link
    directed = session.take_directed()
    assert set(directed) == {"tcp-1"} and all(m.get_type() == "LOG_DATA" for m in directed["tcp-1"])

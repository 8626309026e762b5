"""MAVLink FTP as a ground station uses it to fetch parameters: the packed parameter file
(`@PARAM/param.pck`, plain, `?withdefaults=1` and `?start=&count=`) read by burst and by
sequential reads, and the answers to requests made in the wrong state (another session, a file
that is not there, reading past the end, a closed session).

Facts are the reply's opcode and NAK code, whether the file decodes as pymavlink's MAVFTP decodes
it, and a sample of parameters' values and defaults from it. The file's bytes are not compared:
they hold each vehicle's own values (see the params area for those that differ on purpose).
"""
from __future__ import annotations

import struct

from pymavlink.mavftp import MAVFTP

from ..client import Client
from ..facts import Tol, Trace

AREA = "ftp"
HEADER = struct.Struct("<HBBBBBxI")  # seq, session, opcode, size, req_opcode, burst_complete, offset
DATA_SIZE = 239
TERMINATE, RESET, LIST_DIR, OPEN_RO, READ, CALC_CRC, BURST = 1, 2, 3, 4, 5, 14, 15
ACK, NAK = 128, 129
PARAMS = b"@PARAM/param.pck"
VALUE = Tol(abs=1e-6, rel=1e-6, why="float32 in the file")
FILE_SIZE = Tol(rel=0.15, why="each vehicle packs its own values, and Firefly serves its own parameters and "
                               "the groups ArduCopter hides until enabled (PLND_, MNT1_, FOLL_, RNGFND1_, ADSB_, "
                               "CAM1_, AVD_, VISO_, OA_, CHUTE_, GRIP_, SPRAY_, WINCH_: params_differences.FIREFLY_ONLY), "
                               "149 more: 17,976 bytes against 16,188")
# Parameters a ground station's first screens read, whose defaults Firefly keeps as ArduCopter's.
SAMPLE = ("ARMING_CHECK", "WPNAV_SPEED", "WPNAV_RADIUS", "RTL_ALT", "LAND_SPEED", "FLTMODE1",
          "FS_GCS_ENABLE", "BATT_MONITOR", "SERIAL1_PROTOCOL", "PSC_POSXY_P", "ATC_RAT_RLL_P",
          "FENCE_ENABLE", "DISARM_DELAY", "MIS_RESTART", "PILOT_SPEED_UP")


class Ftp:
    """Raw FILE_TRANSFER_PROTOCOL requests; each returns the replies to it, in order."""

    def __init__(self, client: Client):
        self.c = client
        self.seq = 0
        self.replies: list[tuple] = []
        client.listeners.append(self.take)  # for the probe's whole life: it ends with the vehicle

    def take(self, msg) -> None:
        if msg.get_type() == "FILE_TRANSFER_PROTOCOL":
            payload = bytes(msg.payload)
            head = HEADER.unpack_from(payload, 0)
            self.replies.append((*head, payload[HEADER.size:HEADER.size + head[3]]))

    def request(self, opcode: int, session: int = 0, data: bytes = b"", size: int | None = None,
                offset: int = 0, until_burst_end: bool = False, sim_s: float = 5.0) -> list[tuple]:
        # Numbered after the last reply seen, as clients do: a burst's replies count up the seq.
        seq = max([self.seq] + [r[0] + 1 for r in self.replies])
        self.seq = seq + 1
        size = len(data) if size is None else size
        payload = HEADER.pack(seq, session, opcode, size, 0, 0, offset) + data
        self.replies.clear()
        self.c.conn.mav.file_transfer_protocol_send(0, 1, 1, list(payload.ljust(251, b"\0")))

        def answers():  # a late reply to an earlier request is not an answer to this one
            return [r for r in self.replies if r[4] == opcode and r[0] > seq]

        def done():
            if until_burst_end:
                return any(r[2] == NAK or r[5] for r in answers())
            return bool(answers())
        self.c.try_wait(done, sim_s)
        return answers()

    def one(self, *args, **kwargs) -> tuple:
        replies = self.request(*args, **kwargs)
        return replies[0] if replies else None


def outcome(reply) -> str:
    """ACK, NAK <code> (errno too where the code is FailErrno), or none."""
    if reply is None:
        return "none"
    _, _, opcode, size, _, _, _, data = reply
    if opcode == NAK:
        return "NAK " + " ".join(str(b) for b in data[:size])
    return "ACK" if opcode == ACK else f"opcode {opcode}"


def listing(reply) -> str:
    """A ListDirectory answer: its outcome, and the entries of an ACK ("D@PARAM", "F name\tsize")."""
    if reply is None or reply[2] != ACK:
        return outcome(reply)
    entries = [e.decode(errors="replace") for e in reply[7].split(b"\0") if e]
    return "ACK " + " | ".join(entries)


def burst_file(ftp: Ftp, session: int) -> bytes | None:
    """Burst-read an open file from offset 0, asking again from the first gap until EndOfFile."""
    data = bytearray()
    for _ in range(100):
        replies = ftp.request(BURST, session, size=DATA_SIZE, offset=len(data), until_burst_end=True)
        for _, _, opcode, size, _, _, offset, chunk in replies:
            if opcode == ACK and offset == len(data):
                data += chunk
            elif opcode == NAK:
                return bytes(data) if chunk[:1] == b"\x06" else None
        if not replies:
            return None
    return None


def read_file(ftp: Ftp, session: int) -> bytes | None:
    """Sequential ReadFile requests until EndOfFile."""
    data = bytearray()
    for _ in range(1000):
        reply = ftp.one(READ, session, size=DATA_SIZE, offset=len(data))
        if reply is None:
            return None
        if reply[2] == NAK:
            return bytes(data) if reply[7][:1] == b"\x06" else None
        data += reply[7]
    return None


def decoded(data: bytes | None) -> dict | None:
    """name -> (value, default or None), as pymavlink's MAVFTP decodes the file."""
    parsed = MAVFTP.ftp_param_decode(data) if data else None
    if parsed is None:
        return None
    defaults = {n: v for n, v, _ in parsed.defaults} if parsed.defaults else {}
    return {n.decode(): (v, defaults.get(n)) for n, v, _ in parsed.params}


def fetch(ftp: Ftp, trace: Trace, name: str, path: bytes, reader) -> dict | None:
    ftp.one(RESET)
    opened = ftp.one(OPEN_RO, 1, path)
    trace.fact(f"{name}.open", outcome(opened))
    if opened is not None and opened[2] == ACK:
        trace.fact(f"{name}.file_size", struct.unpack("<I", opened[7][:4])[0], FILE_SIZE)
    params = decoded(reader(ftp, 1))
    trace.fact(f"{name}.decodes", params is not None)
    trace.fact(f"{name}.terminate", outcome(ftp.one(TERMINATE, 1)))
    return params


def run(target) -> dict[str, Trace]:
    client = target.boot()
    ftp = Ftp(client)
    traces = {}
    try:
        t = traces["download"] = Trace()
        by_burst = fetch(ftp, t, "burst", PARAMS, burst_file)
        by_read = fetch(ftp, t, "read", PARAMS, read_file)
        with_defaults = fetch(ftp, t, "withdefaults", PARAMS + b"?withdefaults=1", burst_file)
        window = fetch(ftp, t, "start10_count5", PARAMS + b"?start=10&count=5", burst_file)
        t.fact("burst_and_read_agree", by_burst is not None and by_burst == by_read)
        for name in SAMPLE:
            value, _ = (by_burst or {}).get(name, (None, None))
            t.fact(f"value.{name}", value, VALUE)
            value, default = (with_defaults or {}).get(name, (None, None))
            t.fact(f"default.{name}", default, VALUE)
        t.fact("start10_count5.names", sorted(window or {}))

        t = traces["wrong_state"] = Trace()
        t.fact("reset", outcome(ftp.one(RESET)))
        t.fact("read_without_session", outcome(ftp.one(READ, 1, size=DATA_SIZE)))
        t.fact("open_missing_file", outcome(ftp.one(OPEN_RO, 1, b"@PARAM/nothing.pck")))
        t.fact("open", outcome(ftp.one(OPEN_RO, 1, PARAMS)))
        t.fact("open_again_other_session", outcome(ftp.one(OPEN_RO, 2, PARAMS)))
        t.fact("open_again_same_session", outcome(ftp.one(OPEN_RO, 1, PARAMS)))
        t.fact("read_other_session", outcome(ftp.one(READ, 2, size=DATA_SIZE)))
        t.fact("read_past_end", outcome(ftp.one(READ, 1, size=DATA_SIZE, offset=1_000_000)))
        t.fact("crc32", outcome(ftp.one(CALC_CRC, 1, PARAMS)))
        t.fact("terminate", outcome(ftp.one(TERMINATE, 1)))
        t.fact("read_after_terminate", outcome(ftp.one(READ, 1, size=DATA_SIZE)))
        t.fact("list_root", listing(ftp.one(LIST_DIR, 0, b"/")))
        t.fact("list_missing_dir", outcome(ftp.one(LIST_DIR, 0, b"/nothing")))
        t.fact("unknown_opcode", outcome(ftp.one(99, 0)))
    finally:
        target.close()
    return traces

"""MAVLink FTP (FILE_TRANSFER_PROTOCOL), sans-IO, answering as ArduCopter's GCS_FTP does.

One FTP state per vehicle, as in the reference ArduPilot (one open file over all clients). The
session belongs to the client that opened it, as ArduPilot's GCS_FTP now keys each session by the
sysid, compid (and channel) of its client besides the session number: while a file is open, a
request that is not its owner's for that session number (another number, or another client with
any number) is refused (InvalidSession) unless the session has been silent for SESSION_TIMEOUT_S,
after which it is closed and the request served. TerminateSession and ResetSessions close the
session only when they are its owner's for its number; otherwise they are acknowledged and close
nothing (ArduPilot acknowledges another client's ResetSessions and closes only that client's own
sessions; the reference does the same for another session number of the same client). Only the
owner's exchanges keep the session alive. Replies go to the requesting system/component with
seq = request seq + 1; a request that repeats its client's last answered seq gets that reply again
(a lost reply, not a new operation).

Work is bounded, as ArduPilot's one FTP worker thread bounds it: it serves requests one at a
time at the link's pace, and requests that find its five-slot queue full are dropped as lost
data. Every reply, and each snapshot or packing of the parameter file (an open, its first read, a
CRC, applying an upload), is work counted in replies' worth. One exchange (the messages the loop
reads at once, handled at one link time) does at most EXCHANGE_WORK of it, and all exchanges
together draw on an allowance that refills at WORK_PER_S over link time, up to WORK_ALLOWANCE. A
request that what is left cannot cover is dropped unanswered (its client asks again) and
counted; a BurstReadFile sends as many blocks as is left for and flags the last burst_complete,
as ArduPilot does at its burst size, so the client asks for the next burst. A flood thus costs at
most a few milliseconds an exchange and a fraction of the loop's time, while a client that waits
for each answer (one request an exchange) is served: the allowance holds several downloads.

Served: `@PARAM/param.pck` (param_files.py) read by ReadFile and BurstReadFile, written by
CreateFile/OpenFileWO + WriteFile (applied at TerminateSession or ResetSessions); the root and
`logs/` (the dataflash logs, read-only) listed and read as ftp_tree.py describes. ListDirectory
packs whole entries from the `offset`-th on, each followed by two zero bytes as ArduPilot's are,
and answers EndOfFile when none is left. The rest answers what the reference answers for a
vehicle with no files: remove/rename/mkdir find nothing, TruncateFile and unknown opcodes fail
(with ArduPilot's "Unsupported FTP" debug text).

Time: the session timeout runs on the link clock (wall seconds) handed in, as every link timeout
in Firefly does; ArduPilot's SITL counts it in sim milliseconds. The I/O edge reads that clock
once per exchange, so a request at a later link time is in a later exchange.
"""
from __future__ import annotations

import struct
from dataclasses import dataclass, replace

from ..results import Severity
from . import param_files
from .ftp_tree import FtpTree, is_tree_path
from .param_files import FsError

# opcodes
NONE, TERMINATE_SESSION, RESET_SESSIONS, LIST_DIRECTORY, OPEN_FILE_RO, READ_FILE = 0, 1, 2, 3, 4, 5
CREATE_FILE, WRITE_FILE, REMOVE_FILE, CREATE_DIRECTORY, REMOVE_DIRECTORY = 6, 7, 8, 9, 10
OPEN_FILE_WO, TRUNCATE_FILE, RENAME, CALC_FILE_CRC32, BURST_READ_FILE = 11, 12, 13, 14, 15
ACK, NAK = 128, 129
# NAK codes
FAIL, FAIL_ERRNO, INVALID_DATA_SIZE, INVALID_SESSION, END_OF_FILE = 1, 2, 3, 4, 6
FILE_NOT_FOUND = 10

HEADER = struct.Struct("<HBBBBBxI")  # seq, session, opcode, size, req_opcode, burst_complete, offset
PAYLOAD_SIZE = 251
DATA_SIZE = PAYLOAD_SIZE - HEADER.size  # 239
SESSION_TIMEOUT_S = 3.0
PARAM_FILE_BANNER_PREFIX = "@PARAM/param.pck"  # opening it (with or without ?withdefaults=1) sends the banner
MAX_BURST = 500  # replies to one BurstReadFile (ArduPilot's: enough for a full parameter file)
NO_SESSION = -1
# Work in replies' worth (a reply: 30-40 µs of encoding and packing).
FILE_WORK = 50  # snapshotting or packing the parameter file, 1.5-2 ms
EXCHANGE_WORK = 150  # ~5 ms: the costliest request (a CRC), or an open and a whole first burst
WORK_PER_S = 6000.0  # ~20 % of the loop's time at most, under any flood
WORK_ALLOWANCE = 1000.0  # some five downloads of the parameter file back to back


@dataclass(frozen=True)
class Packet:
    seq: int
    session: int
    opcode: int
    size: int = 0
    req_opcode: int = 0
    burst_complete: int = 0
    offset: int = 0
    data: bytes = b""

    @classmethod
    def parse(cls, payload: bytes) -> Packet:
        payload = bytes(payload[:PAYLOAD_SIZE]).ljust(PAYLOAD_SIZE, b"\0")
        seq, session, opcode, size, req_opcode, burst_complete, offset = HEADER.unpack_from(payload, 0)
        return cls(seq, session, opcode, size, req_opcode, burst_complete, offset, data=payload[HEADER.size:])

    def encode(self) -> list:
        header = HEADER.pack(self.seq & 0xFFFF, self.session, self.opcode, self.size,
                             self.req_opcode, self.burst_complete, self.offset & 0xFFFFFFFF)
        return list((header + self.data[:DATA_SIZE]).ljust(PAYLOAD_SIZE, b"\0"))


def _nak(reply: Packet, code: int, errno: int | None = None) -> Packet:
    if code == FAIL_ERRNO and errno == param_files.ENOENT:
        code, errno = FILE_NOT_FOUND, None
    data = bytes([code]) if errno is None else bytes([code, errno & 0xFF])
    return replace(reply, opcode=NAK, size=len(data), data=data)


def _path(request: Packet) -> str | None:
    """The path a request names, or None when its size does not fit the name (ArduPilot's check:
    size is the name's length, or one more when the data ends in a zero)."""
    data = request.data
    length = data.find(b"\0")
    length = len(data) if length < 0 else length
    if request.size == 0 or not (request.size == length
                                 or (request.size - length == 1 and data[-1] == 0)):
        return None
    return data[:min(length, DATA_SIZE - 1)].decode("latin-1")


class FtpServer:
    def __init__(self, params, notify):
        self.banner_due = False  # an open of the parameter file: the session sends the banner after its reply
        """`params`: the vehicle's ParamStore; `notify(text, severity)`: status texts."""
        self.params = params
        self.notify = notify
        self.tree = FtpTree()  # the I/O edge gives it the vehicle's logs (tree.logs)
        self.file = None  # a ParamFile or log reader (read) or a ParamUpload (write)
        self.session = NO_SESSION
        self.owner: tuple | None = None  # (system, component) that opened the session
        self.last_send_s = float("-inf")  # the open session's last reply
        self._last: tuple | None = None  # (sender, last reply) for a repeated request
        self._allowance = WORK_ALLOWANCE  # refilled over link time
        self._allowance_s = float("-inf")
        self._exchange_left = EXCHANGE_WORK  # what is left for the exchange at link time _exchange_s
        self._exchange_s = float("nan")
        self.counters = {"dropped_busy": 0, "refused_not_owner": 0}

    def _owns(self, sender: tuple, session: int) -> bool:
        """Whether (sender, session) is the open session: its client and its number."""
        return self.file is not None and sender == self.owner and session == self.session

    def handle(self, payload, sender: tuple, now_s: float) -> list[Packet]:
        """Replies to one request from `sender` = (system, component), in order; none for a
        request the work allowance cannot cover (dropped, as a full request queue drops it)."""
        request = Packet.parse(payload)
        if request.opcode in (ACK, NAK):
            return []  # someone else's reply: never answered
        if not self._afford(1, now_s):
            return []
        if self._last is not None:
            last_sender, last = self._last
            if (last_sender == sender and last.session == request.session
                    and request.seq + 1 == last.seq):
                return self._sent([last], sender, now_s)
        reply = Packet((request.seq + 1) & 0xFFFF, request.session, NONE, req_opcode=request.opcode)
        mine = self._owns(sender, request.session)
        work = 0
        if request.size > DATA_SIZE:
            replies = [_nak(reply, INVALID_DATA_SIZE)]
        elif not mine and request.opcode in (TERMINATE_SESSION, RESET_SESSIONS):
            replies = [replace(reply, opcode=ACK)]  # another session's end: nothing of its own to close
        elif self.file is not None and not mine and now_s - self.last_send_s < SESSION_TIMEOUT_S:
            if sender != self.owner:
                self.counters["refused_not_owner"] += 1
            replies = [_nak(reply, INVALID_SESSION)]
        else:
            work = self._work(request, mine)
            if not self._afford(work + 1, now_s):
                return []
            if self.file is not None and not mine:
                self._close()  # the open session went silent: a new client takes over
            replies = self._dispatch(request, reply, sender, now_s, max(1, int(self._left(now_s)) - work))
        return self._sent(replies, sender, now_s, work)

    def _work(self, request: Packet, mine: bool) -> int:
        """The file work (beyond one reply each) that serving `request` may cost, in replies'
        worth; `mine`: it is for the open session."""
        op = request.opcode
        if op == OPEN_FILE_RO:
            return FILE_WORK  # the snapshot
        if op == CALC_FILE_CRC32:
            return 2 * FILE_WORK  # a snapshot, packed
        if not mine:
            return 0
        if op in (READ_FILE, BURST_READ_FILE):
            return FILE_WORK if getattr(self.file, "read_size", 1) == 0 else 0  # packed at the first read
        if op in (TERMINATE_SESSION, RESET_SESSIONS) and isinstance(self.file, param_files.ParamUpload):
            return FILE_WORK  # the upload is applied
        return 0

    def _left(self, now_s: float) -> float:
        """The work that may still be done at link time `now_s`."""
        if now_s != self._exchange_s:  # a later exchange
            self._exchange_s, self._exchange_left = now_s, EXCHANGE_WORK
            refill = max(0.0, now_s - self._allowance_s) * WORK_PER_S
            self._allowance, self._allowance_s = min(WORK_ALLOWANCE, self._allowance + refill), now_s
        return min(self._allowance, self._exchange_left)

    def _afford(self, work: int, now_s: float) -> bool:
        """Whether `work` may be done now; a request it may not is counted as dropped."""
        if self._left(now_s) >= work:
            return True
        self.counters["dropped_busy"] += 1
        return False

    def _sent(self, replies: list[Packet], sender: tuple, now_s: float, work: int = 0) -> list[Packet]:
        spent = work + len(replies)
        self._allowance -= spent
        self._exchange_left -= spent
        if replies:
            if self._owns(sender, replies[-1].session):
                self.last_send_s = now_s  # only the owner's exchanges keep its session alive
            self._last = (sender, replies[-1])
            if replies[-1].req_opcode == TERMINATE_SESSION and self.file is None:
                self.last_send_s = float("-inf")
        return replies

    def _close(self) -> None:
        file, self.file, self.session, self.owner = self.file, None, NO_SESSION, None
        if isinstance(file, param_files.ParamUpload):
            file.close()

    # ----- opcodes ----------------------------------------------------------------------------
    def _dispatch(self, request: Packet, reply: Packet, sender: tuple, now_s: float,
                  budget: int) -> list[Packet]:
        """The replies to a request the open session (if any) may serve; `budget`: the replies
        the allowance covers (at least one)."""
        op = request.opcode
        if op == NONE:
            return [replace(reply, opcode=ACK)]
        if op in (TERMINATE_SESSION, RESET_SESSIONS):
            self._close()
            return [replace(reply, opcode=ACK)]
        if op == OPEN_FILE_RO:
            return [self._open_read(request, reply, sender, now_s)]
        if op in (READ_FILE, BURST_READ_FILE, WRITE_FILE):
            if self.file is None:
                return [_nak(reply, FILE_NOT_FOUND)]
            writing = isinstance(self.file, param_files.ParamUpload)
            if writing != (op == WRITE_FILE):
                return [_nak(reply, FAIL)]
            if op == READ_FILE:
                return [self._read(request, reply)]
            if op == BURST_READ_FILE:
                return self._burst(request, reply, min(MAX_BURST, budget))
            return [self._write(request, reply)]
        if op in (CREATE_FILE, OPEN_FILE_WO):
            return [self._open_write(request, reply, sender)]
        if op in (LIST_DIRECTORY, REMOVE_FILE, CREATE_DIRECTORY, REMOVE_DIRECTORY, CALC_FILE_CRC32):
            return [self._by_path(request, reply)]
        if op == RENAME:
            return [self._rename(request, reply)]
        self.notify(f"Unsupported FTP: {op}", Severity.DEBUG)
        return [_nak(reply, FAIL)]

    def _open_read(self, request: Packet, reply: Packet, sender: tuple, now_s: float) -> Packet:
        if self.file is not None and now_s - self.last_send_s > SESSION_TIMEOUT_S:
            self._close()  # its client never saw our open reply and gave up
        refused = self._open(request, reply, sender, self._open_path)
        if refused is not None:
            return refused
        # As ArduPilot: the parameter file's download starts with the banner a PARAM_REQUEST_LIST gets
        self.banner_due = (_path(request) or "").startswith(PARAM_FILE_BANNER_PREFIX)
        assert self.file is not None  # just opened for reading
        return replace(reply, opcode=ACK, size=4, data=struct.pack("<I", self.file.size_estimate))

    def _open_path(self, path: str):
        return self.tree.open(path) if is_tree_path(path) else param_files.open_read(self.params, path)

    def _open_write(self, request: Packet, reply: Packet, sender: tuple) -> Packet:
        refused = self._open(request, reply, sender,
                             lambda path: param_files.open_write(self.params, path, self.notify))
        return refused or replace(reply, opcode=ACK)

    def _open(self, request: Packet, reply: Packet, sender: tuple, open_path) -> Packet | None:
        """Open the file the request names for its session, owned by `sender`; the NAK when
        that fails."""
        if self.file is not None:
            return _nak(reply, FAIL)  # one open file at a time
        path = _path(request)
        if path is None:
            return _nak(reply, INVALID_DATA_SIZE)
        try:
            self.file = open_path(path)
        except FsError as exc:
            return _nak(reply, FAIL_ERRNO, exc.errno)
        self.session, self.owner = request.session, sender
        return None

    def _read(self, request: Packet, reply: Packet) -> Packet:
        assert self.file is not None  # _dispatch checked
        try:
            data = self.file.read(request.offset, min(DATA_SIZE, request.size))
        except FsError as exc:
            return _nak(reply, FAIL_ERRNO, exc.errno)
        if not data:
            return _nak(reply, END_OF_FILE)
        return replace(reply, opcode=ACK, offset=request.offset, size=len(data), data=data)

    def _burst(self, request: Packet, reply: Packet, limit: int) -> list[Packet]:
        """Blocks from the requested offset to the end of the file (at most `limit`), then the
        EndOfFile NAK; the last block is flagged burst_complete. The NAK keeps the last block's
        flag and the offset after it, as ArduPilot's reuse of one reply buffer gives."""
        assert self.file is not None  # _dispatch checked
        block = request.size or DATA_SIZE
        out = []
        for i in range(limit):
            try:
                data = self.file.read(request.offset + i * block, block)
            except FsError as exc:
                out.append(_nak(reply, FAIL_ERRNO, exc.errno))
                break
            if not data:
                out.append(_nak(reply, END_OF_FILE))
                break
            short = len(data) < block
            reply = replace(reply, opcode=ACK, offset=request.offset + i * block, size=len(data),
                            data=data, burst_complete=int(short or i == limit - 1))
            out.append(reply)
            reply = replace(reply, seq=(reply.seq + 1) & 0xFFFF,
                            offset=reply.offset + (len(data) if short else 0))
        return out

    def _write(self, request: Packet, reply: Packet) -> Packet:
        assert isinstance(self.file, param_files.ParamUpload)  # _dispatch checked
        try:
            self.file.write(request.offset, request.data[:request.size])
        except FsError as exc:
            return _nak(reply, FAIL_ERRNO, exc.errno)
        return replace(reply, opcode=ACK, offset=request.offset)

    def _by_path(self, request: Packet, reply: Packet) -> Packet:
        path = _path(request)
        if path is None:
            return _nak(reply, INVALID_DATA_SIZE)
        if request.opcode == CALC_FILE_CRC32:
            try:
                crc = param_files.file_crc32(self._open_path(path))
            except FsError as exc:
                return _nak(reply, FAIL_ERRNO, exc.errno)
            return replace(reply, opcode=ACK, size=4, data=struct.pack("<I", crc))
        if request.opcode == LIST_DIRECTORY:
            return self._list(path, replace(reply, offset=request.offset))
        return _nak(reply, FILE_NOT_FOUND)

    def _list(self, path: str, reply: Packet) -> Packet:
        try:
            entries = self.tree.list(path)
        except FsError as exc:
            return _nak(reply, FAIL_ERRNO, exc.errno)
        data = b""
        for entry in entries[reply.offset:]:
            packed = entry.encode("latin-1") + b"\0\0"
            if len(data) + len(packed) > DATA_SIZE:
                break
            data += packed
        if not data:
            return _nak(reply, END_OF_FILE)
        return replace(reply, opcode=ACK, size=len(data), data=data)

    def _rename(self, request: Packet, reply: Packet) -> Packet:
        first_end = request.data.find(b"\0", 0, DATA_SIZE - 2)
        second = request.data[first_end + 1:] if first_end >= 0 else b""
        second_end = second.find(b"\0")
        length = first_end + (len(second) if second_end < 0 else second_end)
        well_formed = first_end >= 0 and request.size != 0 and (
            length + 1 == request.size or (request.size - length == 2 and request.data[-1] == 0))
        return _nak(reply, FILE_NOT_FOUND if well_formed else INVALID_DATA_SIZE)

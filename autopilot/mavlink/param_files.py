"""The files MAVLink FTP serves: ArduPilot's `@PARAM` directory, whose one file `param.pck` is the
parameter table packed (param_pack.py). There is no other filesystem: any other path is not found.

`@PARAM/param.pck` takes ArduPilot's query string: `?withdefaults=1` adds defaults that differ from
the value, `?start=N&count=C` a slice of the table. Reading packs a snapshot of the values taken at
open, so a download is consistent even if a parameter changes meanwhile. Writing (an upload of a
packed file) buffers the bytes and sets the parameters when the file is closed, as ArduPilot does.
Errors carry the errno ArduPilot's filesystem would set.
"""
from __future__ import annotations

import re
import zlib

from ..params import SERVED_BY_NAME, ParamError
from ..results import Severity
from . import param_pack

ENOENT, ENOMEM, EINVAL = 2, 12, 22
PREFIX = "@PARAM"
PACKED_NAME = "param.pck"
SIZE_ESTIMATE_PER_PARAM = 12  # what ArduPilot reports as the file's size at open, per parameter
MAX_UPLOAD = 0xFFFF  # an upload's header holds the file length in 16 bits
CRC_READ_SIZE = 64  # ArduPilot's CRC reads the file in blocks of this size (which sets its padding)


class FsError(Exception):
    def __init__(self, errno: int):
        super().__init__(errno)
        self.errno = errno


def _packed_query(path: str) -> str | None:
    """The text from `param.pck` on when `path` names the packed file (ArduPilot matches the
    `@PARAM` prefix, after an optional leading '/', then one optional '/'), else None."""
    path = path[1:] if path.startswith("/") else path
    if not path.startswith(PREFIX):
        return None
    rest = path[len(PREFIX):]
    rest = rest[1:] if rest.startswith("/") else rest
    if rest == PACKED_NAME or rest.startswith(PACKED_NAME + "?"):
        return rest[len(PACKED_NAME):]
    return None


def _strtoul(text: str) -> int:
    """C strtoul, truncated to 32 bits as ArduPilot stores it: leading digits, 0 if none."""
    m = re.match(r"\s*([+-]?)(\d*)", text)
    assert m is not None  # every text matches: both groups may be empty
    value = min(int(m.group(2) or 0), 2 ** 64 - 1)
    if m.group(1) == "-":
        value = -value % 2 ** 64
    return value & 0xFFFFFFFF


def _options(query: str) -> tuple[int, int, bool]:
    """(start, count, with_defaults) from `?start=N&count=C&withdefaults=1`; EINVAL when out of
    range. Like ArduPilot, the scan moves one character at a time past anything it does not know."""
    start, count, with_defaults = 0, 0, False
    i = 0 if query.startswith("?") else -1
    while 0 <= i < len(query):
        i += 1
        rest = query[i:]
        for key in ("start=", "count=", "withdefaults="):
            if rest.startswith(key):
                value = _strtoul(rest[len(key):])
                if key == "withdefaults=":
                    if value > 1:
                        raise FsError(EINVAL)
                    with_defaults = value == 1
                elif value >= 0xFFFF:
                    raise FsError(EINVAL)
                elif key == "start=":
                    start = value
                else:
                    count = value
                i = query.find("&", i + len(key))
                break
    return start, count, with_defaults


def _snapshot(params) -> list[param_pack.Entry]:
    return [param_pack.Entry(name, param_pack.packed_type(params.mav_type(name)), float(params[name]),
                             SERVED_BY_NAME[name].default) for name in params.names()]


class ParamFile:
    """`@PARAM/param.pck` open for reading. Every read of one open file must ask for the same size
    (ArduPilot's rule: the padding depends on it); another size is EINVAL."""

    def __init__(self, entries: list[param_pack.Entry], total: int, with_defaults: bool = False,
                 start: int = 0):
        """`entries`: the parameters sent, from number `start` of the vehicle's `total`."""
        self.entries = entries
        self.total = total
        self.with_defaults = with_defaults
        self.start = start
        self.read_size = 0
        self._data = b""

    @property
    def size_estimate(self) -> int:
        """The size ArduPilot reports at open (an estimate: the file is packed at the first read)."""
        return self.total * SIZE_ESTIMATE_PER_PARAM

    def read(self, offset: int, count: int) -> bytes:
        if count == 0:
            return b""
        if not self.read_size:
            self.read_size = count
            self._data = param_pack.pack(self.entries, self.total, count, self.with_defaults)
        elif count != self.read_size:
            raise FsError(EINVAL)
        if offset < param_pack.HEADER.size and self.total <= self.start:
            raise FsError(EINVAL)  # ArduPilot refuses the header of an empty slice
        return self._data[offset:offset + count]


class ParamUpload:
    """`@PARAM/param.pck` open for writing: the bytes are set parameters when closed."""

    def __init__(self, params, notify):
        self.params = params
        self.notify = notify
        self._buf = bytearray()

    def write(self, offset: int, data: bytes) -> None:
        end = offset + len(data)
        if end > MAX_UPLOAD:
            raise FsError(ENOMEM)
        if end > len(self._buf):
            self._buf.extend(bytes(end - len(self._buf)))
        self._buf[offset:end] = data

    def close(self) -> int:
        """Apply the file; the number of parameters set. A malformed file sets nothing and, as in
        ArduPilot, is not reported on the wire (the TerminateSession is acknowledged anyway)."""
        data = bytes(self._buf)
        try:
            magic, length, entries = param_pack.unpack(data)
        except param_pack.PackError as exc:
            self.notify(f"Param upload ignored: {exc}", Severity.WARNING)
            return 0
        if magic != param_pack.MAGIC or length != len(data) or any(e.default is not None for e in entries):
            self.notify("Param upload ignored: not an upload file", Severity.WARNING)
            return 0
        applied = 0
        for entry in entries:
            if entry.name not in SERVED_BY_NAME:
                continue  # as ArduPilot: a name this vehicle does not have is skipped
            try:
                self.params.set(entry.name, entry.value)
                applied += 1
            except ParamError as exc:
                self.notify(f"Param set failed: {exc}", Severity.WARNING)
        return applied


def open_read(params, path: str) -> ParamFile:
    query = _packed_query(path)
    if query is None:
        raise FsError(ENOENT)
    start, count, with_defaults = _options(query)
    entries = _snapshot(params)
    chosen = entries[start:start + count] if count else entries[start:]
    return ParamFile(chosen, len(entries), with_defaults, start)


def open_write(params, path: str, notify) -> ParamUpload:
    query = _packed_query(path)
    if query is None:
        raise FsError(ENOENT)
    _options(query)  # ArduPilot parses (and may refuse) the query on any open
    return ParamUpload(params, notify)


def file_crc32(f: ParamFile) -> int:
    """ArduPilot's file CRC: the CRC-32 table without the initial and final inversion, over the
    file read in CRC_READ_SIZE blocks."""
    crc, offset = 0, 0
    while True:
        block = f.read(offset, CRC_READ_SIZE)
        if not block:
            return crc
        crc = zlib.crc32(block, crc ^ 0xFFFFFFFF) ^ 0xFFFFFFFF
        offset += len(block)

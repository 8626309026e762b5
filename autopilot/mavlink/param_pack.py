"""ArduPilot's packed parameter file (`@PARAM/param.pck` over MAVLink FTP): encoder and decoder.

Layout, little-endian: a 6-byte header (magic, num_params, total_params), then one record per
parameter:
    byte 0   type (low nibble: 1 INT8, 2 INT16, 3 INT32, 4 FLOAT) | flags << 4 (bit 0: a default
             value follows the value)
    byte 1   common_len (low nibble: leading name bytes shared with the previous record's name)
             | (name_len - 1) << 4 (name bytes that follow)
    name[name_len], value[type size], default[type size] if flagged
Zero bytes before a record are padding. The encoder pads so that no value is split across two
FTP reads of `read_size` bytes: a lost block re-read later can then never give a value half old and
half new. That is why every read of one open file must use one size.

In an upload (a GCS writing the file) the header's total_params holds the file's length instead.
"""
from __future__ import annotations

import math
import struct
from dataclasses import dataclass

from .dialect import mavlink as mav

MAGIC = 0x671B
MAGIC_WITH_DEFAULTS = 0x671C
HEADER = struct.Struct("<HHH")
MAX_NAME = 16

INT8, INT16, INT32, FLOAT = 1, 2, 3, 4
_FORMAT = {INT8: "<b", INT16: "<h", INT32: "<i", FLOAT: "<f"}
_SIZE = {t: struct.calcsize(f) for t, f in _FORMAT.items()}
FLT_EPSILON = 1.1920929e-07  # ArduPilot's is_equal(): values this close count as equal

# MAVLink's MAV_PARAM_TYPE -> the packed file's (AP_Param's) type number
_FROM_MAV = {mav.MAV_PARAM_TYPE_UINT8: INT8, mav.MAV_PARAM_TYPE_INT8: INT8,
             mav.MAV_PARAM_TYPE_UINT16: INT16, mav.MAV_PARAM_TYPE_INT16: INT16,
             mav.MAV_PARAM_TYPE_UINT32: INT32, mav.MAV_PARAM_TYPE_INT32: INT32,
             mav.MAV_PARAM_TYPE_REAL32: FLOAT}


class PackError(ValueError):
    pass


@dataclass(frozen=True)
class Entry:
    name: str
    ptype: int  # INT8, INT16, INT32 or FLOAT
    value: float
    default: float | None = None  # None: no default to send


def packed_type(mav_param_type: int) -> int:
    """The packed type for a MAV_PARAM_TYPE (unknown types go as FLOAT, as a value never breaks)."""
    return _FROM_MAV.get(mav_param_type, FLOAT)


def _encode_value(ptype: int, value: float) -> bytes:
    if ptype == FLOAT:
        try:
            return struct.pack("<f", value)
        except OverflowError:  # beyond float32: the nearest float32 is infinity
            return struct.pack("<f", math.copysign(math.inf, value))
    # Truncated and wrapped to the type's width, as C's float-to-integer conversion does on the
    # reference (an INT16 whose default is 65535 goes as -1).
    bits = 8 * _SIZE[ptype]
    whole = int(value) if math.isfinite(value) else 0
    return (whole % (1 << bits)).to_bytes(_SIZE[ptype], "little")


def _shared_prefix(a: str, b: str) -> int:
    n = 0
    for x, y in zip(a, b):
        if x != y:
            break
        n += 1
    return n


def _record(entry: Entry, last_name: str, with_default: bool) -> tuple[bytes, bytes]:
    """(record head: type, lengths and name bytes; value bytes) for one entry."""
    name = entry.name
    common = min(_shared_prefix(name, last_name), 15)
    if common == len(name):  # the name is a prefix of the last one: send at least its last byte
        common -= 1
    tail = name[common:].encode("ascii")
    default = entry.default if with_default else None  # pack() asks only for an entry's default
    flags = 1 if default is not None else 0
    head = bytes([entry.ptype | flags << 4, common | (len(tail) - 1) << 4]) + tail
    value = _encode_value(entry.ptype, entry.value)
    if default is not None:
        value += _encode_value(entry.ptype, default)
    return head, value


def pack(entries: list[Entry], total: int, read_size: int, with_defaults: bool = False) -> bytes:
    """The file for `entries` (the parameters sent, `total` the vehicle has), padded for reads of
    `read_size` bytes. With `with_defaults`, an entry whose value differs from its default carries
    the default too."""
    out = bytearray(HEADER.pack(MAGIC_WITH_DEFAULTS if with_defaults else MAGIC, len(entries), total))
    last_name = ""
    for entry in entries:
        if not 0 < len(entry.name) <= MAX_NAME:
            raise PackError(f"parameter name {entry.name!r} is not 1..{MAX_NAME} characters")
        add_default = (with_defaults and entry.default is not None
                       and not abs(entry.value - entry.default) < FLT_EPSILON)
        head, value = _record(entry, last_name, add_default)
        type_len = _SIZE[entry.ptype]
        if type_len > 1 and read_size > 0:
            into_block = (len(out) + len(head) + len(value)) % read_size
            if 0 < into_block < type_len:  # the value's first bytes would end a read block
                out += bytes(type_len - into_block)
        out += head + value
        last_name = entry.name
    return bytes(out)


def unpack(data: bytes) -> tuple[int, int, list[Entry]]:
    """(magic, header's total_params field, entries) of a packed file; PackError if malformed.
    A default, when flagged, is in the entry's `default`."""
    if len(data) < HEADER.size:
        raise PackError("shorter than the header")
    magic, count, total = HEADER.unpack_from(data, 0)
    if magic not in (MAGIC, MAGIC_WITH_DEFAULTS):
        raise PackError(f"bad magic 0x{magic:04x}")
    pos, last_name = HEADER.size, b""
    entries: list[Entry] = []
    while len(entries) < count:
        while pos < len(data) and data[pos] == 0:
            pos += 1
        if pos + 2 > len(data):
            raise PackError(f"ends after {len(entries)} of {count} parameters")
        ptype, flags = data[pos] & 0x0F, data[pos] >> 4
        common, name_len = data[pos + 1] & 0x0F, (data[pos + 1] >> 4) + 1
        if ptype not in _FORMAT:
            raise PackError(f"bad type {ptype} at byte {pos}")
        if common > len(last_name) or common + name_len > MAX_NAME:
            raise PackError(f"bad name lengths at byte {pos}")
        size = _SIZE[ptype]
        n_values = 2 if flags & 1 else 1
        end = pos + 2 + name_len + size * n_values
        if end > len(data):
            raise PackError(f"record at byte {pos} runs past the end")
        name = last_name[:common] + data[pos + 2:pos + 2 + name_len]
        try:
            text = name.decode("ascii")
        except UnicodeDecodeError:
            raise PackError(f"parameter name at byte {pos} is not ASCII") from None
        values = struct.unpack_from("<" + _FORMAT[ptype][1] * n_values, data, pos + 2 + name_len)
        entries.append(Entry(text, ptype, float(values[0]), float(values[1]) if n_values == 2 else None))
        last_name, pos = name, end
    return magic, total, entries

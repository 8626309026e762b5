"""The dataflash binary format: each record is HEAD (0xA3 0x95), a one-byte message type, then
the fields packed little-endian with no padding. The log describes itself: an FMT record per
message type (its id, length, name, format characters and column names), UNIT and MULT records
naming the unit and multiplier characters, and an FMTU record per type giving each column's unit
and multiplier. pymavlink's DFReader, MAVExplorer and UAV Log Viewer read nothing else.

Each message type packs with one precompiled struct (header included), so a record costs one
struct.pack call. Fields with a scaled format character are handed over already scaled, as
ArduPilot's writers hand them: 'c'/'C'/'e'/'E' in hundredths, 'L' in degrees * 1e7.
"""
from __future__ import annotations

import struct
from dataclasses import dataclass, field

HEAD = b"\xa3\x95"
# ArduPilot's format characters and the struct codes they pack as.
STRUCT_CODES = {
    "a": "64s",  # int16[32], written as raw bytes
    "b": "b", "B": "B", "h": "h", "H": "H", "i": "i", "I": "I", "f": "f", "d": "d",
    "n": "4s", "N": "16s", "Z": "64s",
    "c": "h", "C": "H", "e": "i", "E": "I",  # hundredths
    "L": "i",  # degrees * 1e7
    "M": "B",  # flight mode number
    "q": "q", "Q": "Q",
    "g": "e",  # half-precision float
}
TEXT_CODES = frozenset("nNZ")
MAX_COLUMNS_TEXT = 64


@dataclass(frozen=True)
class LogFormat:
    """One message type: its id, name, format characters, column names, and each column's unit
    and multiplier character (UNITS and MULTS in messages.py)."""
    type_id: int
    name: str
    fmt: str
    columns: str
    units: str
    mults: str
    packer: struct.Struct = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not (len(self.fmt) == len(self.units) == len(self.mults) == len(self.columns.split(","))):
            raise ValueError(f"{self.name}: format, units, multipliers and columns differ in length")
        codes = "".join(STRUCT_CODES[c] for c in self.fmt)
        object.__setattr__(self, "packer", struct.Struct("<2sB" + codes))

    @property
    def length(self) -> int:
        """The record's length in bytes, header included (FMT's Length field)."""
        return self.packer.size

    @property
    def text_fields(self) -> tuple[int, ...]:
        return tuple(i for i, c in enumerate(self.fmt) if c in TEXT_CODES)

    def pack(self, *values) -> bytes:
        """A record of this type; text fields given as bytes (or str, encoded here)."""
        return self.packer.pack(HEAD, self.type_id, *values)

    def pack_text(self, *values) -> bytes:
        """As pack, for records with text fields given as str (not on the fast path)."""
        return self.packer.pack(HEAD, self.type_id,
                                *(v.encode("latin-1", "replace") if isinstance(v, str) else v for v in values))


FMT = LogFormat(128, "FMT", "BBnNZ", "Type,Length,Name,Format,Columns", "-b---", "-----")


def fmt_record(message: LogFormat) -> bytes:
    """The FMT record that describes `message`."""
    return FMT.pack_text(message.type_id, message.length, message.name, message.fmt, message.columns)

"""A float parameter as ArduPilot's C++ takes it into an integer field (x86 SITL): commands and
mission items carry floats, and the vehicle acts on what the conversion leaves."""
from __future__ import annotations

import math
import struct


def as_uint16(value: float) -> int:
    """Its integer part, modulo 2^16 (a value an int32 cannot hold, NaN included, becomes 0)."""
    if not (math.isfinite(value) and -2**31 <= value < 2**31):
        return 0
    return int(value) & 0xFFFF


def as_uint32(value: float) -> int:
    """Its integer part, modulo 2^32, as x86 converts a double to uint32_t (through an int64: a
    value an int64 cannot hold, NaN included, becomes 0)."""
    if not (math.isfinite(value) and -2**63 <= value < 2**63):
        return 0
    return int(value) & 0xFFFFFFFF


def as_int32(value: float) -> int:
    """Its integer part, as a signed 32-bit number (a value an int32 cannot hold, NaN included,
    becomes 0)."""
    if not (math.isfinite(value) and -2**31 <= value < 2**31):
        return 0
    return int(value)


def as_uint8(value: float) -> int:
    """As as_uint16, modulo 2^8: x86 takes the low byte of the int32 (NaN: 0)."""
    return as_uint16(value) & 0xFF


def as_int16(value: float) -> int:
    """As as_uint16, read as a signed 16-bit number."""
    unsigned = as_uint16(value)
    return unsigned - 0x10000 if unsigned >= 0x8000 else unsigned


def param5_int(p5: float, is_int: bool) -> int:
    """A command's param 5 as the int32 `x` ArduPilot reads: a COMMAND_INT's x (held in degrees,
    x * 1e-7), a COMMAND_LONG's param 5 cut to an integer (0 if an int32 cannot hold it)."""
    if is_int:
        return round(p5 * 1e7)
    return int(p5) if math.isfinite(p5) and abs(p5) < 2**31 else 0


def float32(value: float) -> float:
    """The nearest float32, as ArduPilot holds its floats (built with single-precision constants,
    its arithmetic is float32 too: a product of two float32s is this of the exact product)."""
    try:
        return struct.unpack("<f", struct.pack("<f", value))[0]
    except OverflowError:
        return math.copysign(math.inf, value)

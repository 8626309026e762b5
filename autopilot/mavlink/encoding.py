"""Unit conversions MAVLink fields share."""
from __future__ import annotations

from ..views import SimClock


def time_boot_ms(v: SimClock) -> int:
    """Vehicle time as a uint32 millisecond field."""
    return int(v.time_s * 1000.0) & 0xFFFFFFFF


def deg_e7(x: float) -> int:
    return int(round(x * 1e7))


def u16(x: float) -> int:
    """A reading in an unsigned 16-bit field: cut to 0..65535 (a hostile parameter or a fault can
    push a simulated reading out of the field's range; the message still goes out)."""
    return max(0, min(int(x), 65535))

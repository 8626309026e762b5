"""Unit conversions MAVLink fields share."""
from __future__ import annotations

from ..views import SimClock


def time_boot_ms(v: SimClock) -> int:
    """Vehicle time as a uint32 millisecond field."""
    return int(v.time_s * 1000.0) & 0xFFFFFFFF


def deg_e7(x: float) -> int:
    return int(round(x * 1e7))

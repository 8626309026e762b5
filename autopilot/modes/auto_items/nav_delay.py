"""NAV_DELAY: the mission waits here, param 1 seconds or, with param 1 not positive, until the
UTC time of day params 2..4 give (hour, minute, second; -1 leaves a field out), as ArduCopter's
do_nav_delay, which says "Delaying N sec". The vehicle holds where the item found it."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ..context import ModeContext
from .hold_here import HoldHere

if TYPE_CHECKING:
    from ...mission.store import MissionItem
    from ..auto import Auto

DAY_MS = 86_400_000
UINT32_MAX_S = 4_294_967.0  # the longest delay ArduCopter's uint32 of ms holds


def _int8(value: float) -> int:
    """A param as AP_Mission stores it in an int8 field (the UTC fields)."""
    return (int(value) + 128) % 256 - 128 if math.isfinite(value) else 0


def ms_until_utc(now_ms_of_day: int, hour: int, minute: int, second: int) -> int:
    """AP_RTC::get_time_utc: ms from now to the next time of day matching the fields given; the
    largest field given sets the period it wraps over (hour: a day, minute: an hour, second: a
    minute); 0 when none is."""
    cur_h, rest = divmod(now_ms_of_day, 3_600_000)
    cur_m, rest = divmod(rest, 60_000)
    cur_s, cur_ms = divmod(rest, 1000)
    fields = ((hour, cur_h, 3_600_000, DAY_MS), (minute, cur_m, 60_000, 3_600_000), (second, cur_s, 1000, 60_000))
    largest = next((i for i, (value, *_) in enumerate(fields) if value != -1), None)
    if largest is None:
        return 0
    total = -cur_ms  # the target's ms field is 0
    for value, current, unit, _ in fields[largest:]:
        total += (value - current) * unit
    if total < 0:
        total += fields[largest][3]
    return total % (1 << 32)


class NavDelay(HoldHere):
    resets_heading = False  # ArduCopter's delay leaves the flight as it was
    _delay_s: float

    def start(self, auto: Auto, ctx: ModeContext, index: int, item: MissionItem) -> bool:
        super().start(auto, ctx, index, item)
        if item.p1 > 0:  # NaN is not: it waits for the time of day instead
            delay_ms = int(min(item.p1, UINT32_MAX_S) * 1000)
        else:
            ms_of_day = (ctx.unix_time_us() // 1000) % DAY_MS
            delay_ms = ms_until_utc(ms_of_day, _int8(item.p2), _int8(item.p3), _int8(item.p4))
        self._delay_s = delay_ms / 1000.0
        ctx.notify(f"Delaying {delay_ms // 1000} sec")
        return True

    def done(self, ctx: ModeContext) -> bool:
        return ctx.time_s - self.start_s > self._delay_s

"""DO_GUIDED_LIMITS: the limits a later NAV_GUIDED_ENABLE ends at (ArduCopter keeps them in its
GUIDED mode, for as long as the vehicle runs, until the next DO_GUIDED_LIMITS). Params: 1 the
time [s], 2 the lowest and 3 the highest altitude [m above the origin], 4 the farthest from where
the guided item began [m, horizontally]; 0 turns that limit off."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ...c_casts import as_uint16
from ..context import ModeContext
from . import AutoItem

if TYPE_CHECKING:
    from ...mission.store import MissionItem
    from ..auto import Auto


@dataclass(frozen=True)
class GuidedLimits:
    timeout_s: float = 0.0
    alt_range_m: tuple[float, float] = (0.0, 0.0)  # (lowest, highest)
    horiz_max_m: float = 0.0

    def broken(self, ctx: ModeContext, start_s: float, start_ne: tuple[float, float]) -> bool:
        """ArduCopter's limit_check, from the time and place the guided item began."""
        if self.timeout_s > 0 and ctx.time_s - start_s >= self.timeout_s:
            return True
        b = ctx.body
        alt = -b.d_m  # above the local origin, as ArduCopter's position estimate is
        low, high = self.alt_range_m
        if (low != 0 and alt < low) or (high != 0 and alt > high):
            return True
        return self.horiz_max_m > 0 and math.hypot(b.n_m - start_ne[0], b.e_m - start_ne[1]) > self.horiz_max_m


def _finite(value: float) -> float:
    return value if math.isfinite(value) else 0.0


class DoGuidedLimits(AutoItem):
    def start(self, auto: Auto, ctx: ModeContext, index: int, item: MissionItem) -> bool:
        seconds = as_uint16(item.p1)  # AP_Mission keeps the time as its uint16 p1
        auto.guided_limits = GuidedLimits(float(seconds), (_finite(item.p2), _finite(item.p3)), _finite(item.p4))
        return True

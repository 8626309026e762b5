"""The condition items (ArduCopter's "may" commands): each holds back the "do" items after it
until it is met, while the navigation item goes on. AP_Mission verifies the condition loaded with
the navigation item every tick and reports it reached when met (MISSION_ITEM_REACHED).

  CONDITION_DELAY     param 1 seconds after it started
  CONDITION_DISTANCE  within param 1 metres (horizontally) of the navigation item's point
  CONDITION_YAW       the nose turned (condition_yaw.py)
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ..context import ModeContext
from . import AutoItem

if TYPE_CHECKING:
    from ...mission.store import MissionItem
    from ..auto import Auto


class ConditionDelay(AutoItem):
    """Met once more than param 1 seconds have passed (a negative or NaN delay: at once)."""
    _until_s: float

    def start(self, auto: Auto, ctx: ModeContext, index: int, item: MissionItem) -> bool:
        seconds = item.p1 if math.isfinite(item.p1) else 0.0
        self._until_s = ctx.time_s + max(seconds, 0.0)
        return True

    def done(self, ctx: ModeContext) -> bool:
        return ctx.time_s > self._until_s


class ConditionDistance(AutoItem):
    """Met once the vehicle is nearer than param 1 metres to the point being flown to."""
    _auto: Auto
    _within_m: float

    def start(self, auto: Auto, ctx: ModeContext, index: int, item: MissionItem) -> bool:
        self._auto = auto
        self._within_m = max(item.p1, 0.0) if math.isfinite(item.p1) else 0.0
        return True

    def done(self, ctx: ModeContext) -> bool:
        destination = self._auto.destination()
        if destination is None:  # no navigation item: ArduCopter's distance is then 0
            return self._within_m > 0.0
        b = ctx.body
        return math.hypot(destination[0] - b.n_m, destination[1] - b.e_m) < self._within_m

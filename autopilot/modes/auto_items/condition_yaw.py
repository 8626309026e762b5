"""CONDITION_YAW in a mission: the nose turns (ArduCopter's auto_yaw FIXED) and the condition is
met once the turn is done and the heading is within 2 degrees of it.

Params: 1 the angle [deg], 2 the rate [deg/s] (0: ATC_SLEW_YAW), 3 the direction (-1 counter-
clockwise, 1 clockwise, 0 the shorter way for an absolute angle), 4 relative (> 0) or absolute.
The turn holds while the leg goes on: ArduCopter's waypoint start sets its yaw back to the
default, and its check of this condition sets it to FIXED again, every tick until met; after that
the heading stays until the next navigation item.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ...control.attitude import wrap_pi
from ..context import ModeContext
from ..guided_yaw import FIXED, SLEW_YAW_DEFAULT_CDEG_S
from . import AutoItem

if TYPE_CHECKING:
    from ...mission.store import MissionItem
    from ..auto import Auto

REACHED_RAD = math.radians(2.0)


def _finite(value: float) -> float:
    return value if math.isfinite(value) else 0.0


class ConditionYaw(AutoItem):
    _auto: Auto

    def start(self, auto: Auto, ctx: ModeContext, index: int, item: MissionItem) -> bool:
        self._auto = auto
        slew_max = math.radians(ctx.params.get("ATC_SLEW_YAW", SLEW_YAW_DEFAULT_CDEG_S) / 100.0)
        # AP_Mission keeps the direction as an int8 and "relative" as a uint8 (> 0: relative)
        direction = max(-128, min(127, int(_finite(item.p3))))
        heading = auto.heading
        heading.angle = auto.heading_target(ctx)
        heading.kind = FIXED  # from the heading AUTO steers to, as ArduCopter's FIXED starts
        heading.set_fixed(heading.angle, math.radians(_finite(item.p1)), math.radians(_finite(item.p2)),
                          direction, int(_finite(item.p4)) & 0xFF > 0, slew_max)
        return True

    def done(self, ctx: ModeContext) -> bool:
        heading = self._auto.heading
        heading.kind = FIXED  # a waypoint started since took the heading back: FIXED again
        if heading.offset != 0.0:
            return False
        return abs(wrap_pi(heading.angle - ctx.attitude[2])) <= REACHED_RAD

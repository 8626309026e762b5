"""A navigation item during which AUTO is GUIDED: ArduCopter's NAV_GUIDED_ENABLE and NAV_SCRIPT_TIME
start its GUIDED mode's controller inside AUTO (ModeGuided::init: stop, and hold where the vehicle
comes to rest), and while the item runs AUTO is "in guided mode": a companion computer's
SET_POSITION_TARGET_*, SET_ATTITUDE_TARGET and guided waypoints steer it, with GUIDED's sub-modes,
its GUID_TIMEOUT and its heading rules. What ends the item is each subclass's (the limits of
DO_GUIDED_LIMITS, a script's timeout)."""
from __future__ import annotations

from typing import TYPE_CHECKING

from ..base import Setpoint
from ..context import ModeContext
from ..guided import Guided
from . import AutoItem

if TYPE_CHECKING:
    from ...mission.store import MissionItem
    from ..auto import Auto


class GuidedInside(AutoItem):
    guided: Guided  # always, from start()
    start_s: float
    start_ne: tuple[float, float]

    def start(self, auto: Auto, ctx: ModeContext, index: int, item: MissionItem) -> bool:
        b = ctx.body
        self.start_s = ctx.time_s
        self.start_ne = (b.n_m, b.e_m)  # where the limits are counted from
        self.guided = Guided()
        self.guided.begin(ctx)
        return True

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        self.guided.update(ctx, sp, dt)

    def landed_state_hint(self, ctx: ModeContext) -> str | None:
        return self.guided.landed_state_hint(ctx)

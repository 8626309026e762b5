"""AUTO RTL: ArduCopter's AUTO flying the end of its mission, reported as mode 27.

Entered by number (DO_SET_MODE 27: the nearest return path, else the nearest landing sequence),
by MAV_CMD_DO_LAND_START (a landing sequence only) or MAV_CMD_DO_RETURN_PATH_START (a return
path only): the mission jumps there and AUTO flies it from that item, resumed whatever
MIS_RESTART says (ArduCopter forces the resume). Refused with ArduCopter's texts when the mission
has no such place; arming is refused in it.
"""
from __future__ import annotations

from ..mission.commands import is_takeoff
from ..mission.landing import closest_return_leg, landing_sequence_start
from ..mission.progress import MissionState
from ..mission.store import MissionItem
from ..results import Severity
from ..views import Vector3
from .auto import Auto
from .base import Setpoint, stopping_point
from .context import ModeContext
from .numbers import ModeNumber

EITHER, LAND_START, RETURN_PATH = "either", "land_start", "return_path"
REFUSALS = {EITHER: "No return path or landing sequence found", LAND_START: "No landing sequence found",
            RETURN_PATH: "No return path found"}


class AutoRtl(Auto):
    number = ModeNumber.AUTO_RTL
    text_name = "AUTO RTL"
    allows_arming = False

    def __init__(self) -> None:
        super().__init__()
        self.via = EITHER  # how the next entry was asked for (set by the command, used once)

    def enter(self, ctx: ModeContext) -> str | None:
        via, self.via = self.via, EITHER
        mission = ctx.mission_progress
        items = mission.items()
        (n, e), d = stopping_point(ctx)

        def where(item: MissionItem) -> Vector3 | None:
            return None if item.x == 0 and item.y == 0 else self._target_ned(ctx, item)
        index = closest_return_leg(items, (n, e, d), where) if via != LAND_START else None
        joined_return_path = index is not None
        if index is None and via != RETURN_PATH:
            index = landing_sequence_start(items, (n, e, d), where)
            if index is None:
                ctx.notify("Unable to start landing sequence", Severity.WARNING)
        if index is None:
            return REFUSALS[via]
        reason = super().enter(ctx)
        if reason is not None:
            return reason
        # As AP_Mission's jump: the new item made current and the mission resumed at once (its
        # items started, "Mission: 4 LandStart"...); AUTO then resumes it again as it begins.
        mission.stop()
        mission.set_current(index + 1)
        mission.resume()
        ctx.notify("Return path started" if joined_return_path else "Landing sequence start")
        self.number, self.name = ModeNumber.AUTO_RTL, ModeNumber.AUTO_RTL.name
        return None

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        super().update(ctx, sp, dt)
        if self.number == ModeNumber.AUTO_RTL and not self._in_sequence(ctx):
            # No longer "AUTO in disguise": ArduCopter reports AUTO from here on (after the
            # disarm that ends the landing, which resets the mission; or a takeoff item).
            self.number, self.name = ModeNumber.AUTO, ModeNumber.AUTO.name

    @staticmethod
    def _in_sequence(ctx: ModeContext) -> bool:
        """Still in the landing sequence or return path (or the mission completed)."""
        mission = ctx.mission_progress
        if mission.state is MissionState.COMPLETE:
            return True
        index = mission.nav_index
        return index is not None and not is_takeoff(mission.items()[index].command)

    def _restart(self, ctx: ModeContext) -> bool:  # type: ignore[override]
        return False  # ArduCopter forces the resume: the mission goes on from the jump

"""The payload's mission items, as AP_Mission hands them on: done as they start (RUN_BY_MISSION).

DO_PARACHUTE (param 1: 0 disable, 1 enable, 2 release) releases at once, with none of the checks
the command's release makes (landed, CHUTE_ALT_MIN: measured, a mission's release at 8 m with
CHUTE_ALT_MIN 10 disarms and releases); DO_SPRAYER (param 1: 1 on, anything else off);
DO_GRIPPER (param 2: 0 release, 1 grab; param 1, the gripper, ignored) acts and then says
"Gripper Released" / "Gripper Grabbed", gripper or none. DO_WINCH (param 2 the action: 0 relax,
1 let out param 3 metres, 2 run at param 4 m/s; param 1, the winch, ignored) is ArduCopter's own
AUTO's, done as it starts: it acts whether or not a winch was made, silently (a length with no
winch does nothing, a rate or relax is remembered). Parameters are cut to AP_Mission's integer
fields.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

from ...c_casts import as_uint8, as_uint16
from ...results import Severity
from . import AutoItem

if TYPE_CHECKING:
    from ...mission.store import MissionItem
    from ..auto import Auto
    from ..context import ModeContext

DO_GRIPPER, DO_PARACHUTE, DO_SPRAYER, DO_WINCH = 211, 208, 216, 42600
DISABLE, ENABLE, RELEASE = 0, 1, 2  # DO_PARACHUTE's param 1 (PARACHUTE_ACTION)
GRIPPER_RELEASE, GRIPPER_GRAB = 0, 1  # DO_GRIPPER's param 2 (GRIPPER_ACTIONS)


class PayloadItem(AutoItem):
    def start(self, auto: Auto, ctx: ModeContext, index: int, item: MissionItem) -> bool:
        if item.command == DO_GRIPPER:
            _gripper(ctx, as_uint16(item.p2))
            return True
        if item.command == DO_WINCH:
            _winch(ctx, as_uint8(item.p2), item.p3, item.p4)
            return True
        action = as_uint16(item.p1)
        if item.command == DO_SPRAYER:
            ctx.sprayer.run(action == 1, ctx.time_s)
        elif action in (DISABLE, ENABLE):
            ctx.parachute.enable(action == ENABLE)
        elif action == RELEASE:
            ctx.parachute.release(ctx.time_s)
        return True


def _gripper(ctx: ModeContext, action: int) -> None:
    if action == GRIPPER_RELEASE:
        ctx.gripper.release(ctx.time_s)
        ctx.notify("Gripper Released", Severity.INFO)
    elif action == GRIPPER_GRAB:
        ctx.gripper.grab(ctx.time_s)
        ctx.notify("Gripper Grabbed", Severity.INFO)


def _winch(ctx: ModeContext, action: int, length_m: float, rate_m_s: float) -> None:
    if action == 0:
        ctx.winch.relax()
    elif action == 1:
        ctx.winch.release_length(length_m)
    elif action == 2:
        ctx.winch.set_rate(rate_m_s)

"""Mission items AUTO runs with a runner of their own: one class per item, joined in ITEMS.

AUTO (modes/auto.py) flies its first items (takeoff, waypoints, loiters, land, RTL) itself; every
other item it can run is an AutoItem registered here by its MAV_CMD number. A navigation item is
flown by update() until done() says so; a "do" or condition item acts in start() and its done()
tells the mission when the items after it may start (AP_Mission's verify_command).
"""
from __future__ import annotations

from typing import TYPE_CHECKING

from ..base import Setpoint
from ..context import ModeContext

if TYPE_CHECKING:
    from ...mission.store import MissionItem
    from ..auto import Auto


class AutoItem:
    """One mission item as AUTO runs it; a new instance for every start."""

    # A navigation item sets AUTO's heading back to its default when it starts, as ArduCopter's
    # waypoint, circle and guided starts do; False: it leaves a CONDITION_YAW's turn as it is.
    resets_heading = True

    def start(self, auto: Auto, ctx: ModeContext, index: int, item: MissionItem) -> bool:
        """Begin the item; False: this vehicle cannot run it (it is passed over)."""
        return True

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        """Fly one tick (navigation items only): fill the setpoint."""

    def done(self, ctx: ModeContext) -> bool:
        """Whether the item is complete (verified): the mission moves on."""
        return True

    def landed_state_hint(self, ctx: ModeContext) -> str | None:
        """EXTENDED_SYS_STATE's landed state while this item is flown (None: from the vehicle)."""
        return None


# MAV_CMD number -> the class that runs it. A new item joins here, in one line.
ITEMS: dict[int, type[AutoItem]] = {}


def _register() -> None:
    # imported here: each item's module imports AutoItem from this one
    from .condition_yaw import ConditionYaw
    from .conditions import ConditionDelay, ConditionDistance
    from .guided_limits import DoGuidedLimits
    from .nav_attitude_time import NavAttitudeTime
    from .nav_delay import NavDelay
    from .nav_guided_enable import NavGuidedEnable
    from .nav_script_time import NavScriptTime
    from .payload_place import PayloadPlace
    ITEMS.update({
        92: NavGuidedEnable, 93: NavDelay, 94: PayloadPlace, 42702: NavScriptTime, 42703: NavAttitudeTime,
        112: ConditionDelay, 114: ConditionDistance, 115: ConditionYaw, 222: DoGuidedLimits,
    })


_register()

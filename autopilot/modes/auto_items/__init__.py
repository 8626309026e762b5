"""Mission items AUTO runs with a runner of their own: one class per item, joined in ITEMS.

AUTO (modes/auto.py) flies its first items (takeoff, waypoints, loiters, land, RTL) itself; every
other item it can run is an AutoItem registered here by its MAV_CMD number. A navigation item is
flown by update() until done() says so; a "do" or condition item acts in start() and its done()
tells the mission when the items after it may start (AP_Mission's verify_command).
"""
from __future__ import annotations

from typing import TYPE_CHECKING

from ...views import Vector3
from ..base import Setpoint
from ..context import ModeContext

if TYPE_CHECKING:
    from ...mission.store import MissionItem
    from ..auto import Auto
    from ..guided import Guided


class AutoItem:
    """One mission item as AUTO runs it; a new instance for every start."""
    reports_reached = True  # done: MISSION_ITEM_REACHED is sent (ArduCopter's LOITER_TO_ALT sends none)

    # A navigation item sets AUTO's heading back to its default when it starts, as ArduCopter's
    # waypoint, circle and guided starts do; False: it leaves a CONDITION_YAW's turn as it is.
    resets_heading = True

    # GUIDED's controller while the item runs (guided_inside.py): AUTO takes a companion's targets
    # into it, as ArduCopter's in_guided_mode() says of NAV_GUIDED_ENABLE and NAV_SCRIPT_TIME.
    guided: Guided | None = None

    def start(self, auto: Auto, ctx: ModeContext, index: int, item: MissionItem) -> bool:
        """Begin the item; False: this vehicle cannot run it (it is passed over)."""
        return True

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        """Fly one tick (navigation items only): fill the setpoint."""

    def done(self, ctx: ModeContext) -> bool:
        """Whether the item is complete (verified): the mission moves on."""
        return True

    def hand_over(self) -> tuple[Vector3, Vector3] | None:
        """(point, velocity) of a target this navigation item left moving, for a straight leg
        after it to start from at that speed (a spline flown through); None: it stopped."""
        return None

    def landed_state_hint(self, ctx: ModeContext) -> str | None:
        """EXTENDED_SYS_STATE's landed state while this item is flown (None: from the vehicle)."""
        return None


# The items subclass AutoItem: imported once it is defined.
from .camera import CameraItem  # noqa: E402
from .condition_yaw import ConditionYaw  # noqa: E402
from .conditions import ConditionDelay, ConditionDistance  # noqa: E402
from .fence_enable import FenceEnable  # noqa: E402
from .guided_limits import DoGuidedLimits  # noqa: E402
from .loiter_to_alt import LoiterToAlt  # noqa: E402
from .loiter_turns import LoiterTurns  # noqa: E402
from .mount import MountItem  # noqa: E402
from .nav_attitude_time import NavAttitudeTime  # noqa: E402
from .nav_delay import NavDelay  # noqa: E402
from .nav_guided_enable import NavGuidedEnable  # noqa: E402
from .nav_script_time import NavScriptTime  # noqa: E402
from .payload import PayloadItem  # noqa: E402
from .payload_place import PayloadPlace  # noqa: E402
from .roi import SetRoi  # noqa: E402
from .spline_waypoint import SplineWaypoint  # noqa: E402

# MAV_CMD number -> the class that runs it. A new item joins here, in one line.
ITEMS: dict[int, type[AutoItem]] = {
    18: LoiterTurns,  # NAV_LOITER_TURNS
    31: LoiterToAlt,  # NAV_LOITER_TO_ALT
    82: SplineWaypoint,  # NAV_SPLINE_WAYPOINT
    92: NavGuidedEnable,  # NAV_GUIDED_ENABLE
    93: NavDelay,  # NAV_DELAY
    94: PayloadPlace,  # NAV_PAYLOAD_PLACE
    112: ConditionDelay,  # CONDITION_DELAY
    114: ConditionDistance,  # CONDITION_DISTANCE
    115: ConditionYaw,  # CONDITION_YAW
    195: SetRoi,  # DO_SET_ROI_LOCATION
    197: SetRoi,  # DO_SET_ROI_NONE
    201: SetRoi,  # DO_SET_ROI
    202: CameraItem,  # DO_DIGICAM_CONFIGURE
    203: CameraItem,  # DO_DIGICAM_CONTROL
    205: MountItem,  # DO_MOUNT_CONTROL
    206: CameraItem,  # DO_SET_CAM_TRIGG_DIST
    207: FenceEnable,  # DO_FENCE_ENABLE
    208: PayloadItem,  # DO_PARACHUTE
    211: PayloadItem,  # DO_GRIPPER
    216: PayloadItem,  # DO_SPRAYER
    222: DoGuidedLimits,  # DO_GUIDED_LIMITS
    531: CameraItem,  # SET_CAMERA_ZOOM
    532: CameraItem,  # SET_CAMERA_FOCUS
    534: CameraItem,  # SET_CAMERA_SOURCE
    1000: MountItem,  # DO_GIMBAL_MANAGER_PITCHYAW
    2000: CameraItem,  # IMAGE_START_CAPTURE
    2001: CameraItem,  # IMAGE_STOP_CAPTURE
    42600: PayloadItem,  # DO_WINCH
    42702: NavScriptTime,  # NAV_SCRIPT_TIME
    42703: NavAttitudeTime,  # NAV_ATTITUDE_TIME
}

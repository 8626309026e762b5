"""The heading AUTO and GUIDED fly with when nothing else sets it: ArduCopter's default auto-yaw
(WP_YAW_BEHAVIOR), which faces the way the position controller is taking the vehicle.

ArduCopter takes that heading from its position controller's desired velocity, and keeps the last
one while that velocity is under 5 % of the navigation speed (so a stop or a vertical move does
not swing the nose). Measured on ArduCopter SITL: a GUIDED target to the east and an AUTO leg to
the east both turn the nose to 90°.
"""
from __future__ import annotations

import math

from .context import ModeContext

NEVER_CHANGE_YAW = 0  # WP_YAW_BEHAVIOR 0; 1, 2 (not in RTL) and 3 (along the course) face the way
MIN_SPEED_SHARE = 0.05  # of WPNAV_SPEED: AC_PosControl updates its yaw only above it


class AutoYaw:
    __slots__ = ("yaw",)

    def __init__(self) -> None:
        self.yaw: float | None = None  # None: hold the heading the vehicle has

    def facing(self, ctx: ModeContext, vn: float, ve: float) -> float | None:
        """The heading to fly for a desired horizontal velocity (vn, ve) [m/s], or None to hold."""
        params = ctx.params
        if params["WP_YAW_BEHAVIOR"] == NEVER_CHANGE_YAW:
            return None
        if math.hypot(vn, ve) > MIN_SPEED_SHARE * params["WPNAV_SPEED"] * 0.01:
            self.yaw = math.atan2(ve, vn)
        return self.yaw

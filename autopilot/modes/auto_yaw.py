"""The heading AUTO and GUIDED fly with when nothing else sets it: ArduCopter's default auto-yaw
(WP_YAW_BEHAVIOR), which faces the way the position controller is taking the vehicle.

ArduCopter takes that heading from its position controller's desired velocity, and keeps the last
one while that velocity is under 5 % of the navigation speed (so a stop or a vertical move does
not swing the nose). Measured on ArduCopter SITL: a GUIDED target to the east and an AUTO leg to
the east both turn the nose to 90°.

A region of interest (DO_SET_ROI and its kin) takes over from that: the nose points at it from
wherever the vehicle is, whatever WP_YAW_BEHAVIOR says, until it is cleared (ArduCopter's AutoYaw
mode ROI; measured: a leg flown east with an ROI to the west arrives at 270°).
"""
from __future__ import annotations

import math

from .context import ModeContext

NEVER_CHANGE_YAW = 0  # WP_YAW_BEHAVIOR 0; 1, 2 (not in RTL) and 3 (along the course) face the way
MIN_SPEED_SHARE = 0.05  # of WPNAV_SPEED: AC_PosControl updates its yaw only above it


def bearing_to(ctx: ModeContext, target_ne: tuple[float, float]) -> float:
    """The heading [rad] from the vehicle to a point (north, east) of the local frame."""
    b = ctx.body
    return math.atan2(target_ne[1] - b.e_m, target_ne[0] - b.n_m)


class AutoYaw:
    __slots__ = ("yaw", "roi")

    def __init__(self) -> None:
        self.yaw: float | None = None  # None: hold the heading the vehicle has
        self.roi: tuple[float, float] | None = None  # (north, east) the nose points at

    def facing(self, ctx: ModeContext, vn: float, ve: float) -> float | None:
        """The heading to fly for a desired horizontal velocity (vn, ve) [m/s], or None to hold."""
        if self.roi is not None:
            self.yaw = bearing_to(ctx, self.roi)
            return self.yaw
        params = ctx.params
        if params["WP_YAW_BEHAVIOR"] == NEVER_CHANGE_YAW:
            return None
        if math.hypot(vn, ve) > MIN_SPEED_SHARE * params["WPNAV_SPEED"] * 0.01:
            self.yaw = math.atan2(ve, vn)
        return self.yaw

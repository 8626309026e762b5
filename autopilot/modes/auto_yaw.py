"""The heading AUTO and GUIDED fly with when nothing else sets it: ArduCopter's default auto-yaw
(WP_YAW_BEHAVIOR), which faces the way the position controller is taking the vehicle.

ArduCopter takes that heading from its position controller's desired velocity, and keeps the last
one while that velocity is under 5 % of the navigation speed (so a stop or a vertical move does
not swing the nose). Measured on ArduCopter SITL: a GUIDED target to the east and an AUTO leg to
the east both turn the nose to 90°.

WP_YAW_BEHAVIOR (ArduCopter's AutoYaw::default_mode): 0 holds the heading; 1 faces the way the
target moves, also on an RTL's way home; 2 the same but holds the heading in an RTL (`rtl`); 3
looks along the ground course, the vehicle's own velocity, from 1 m/s (its LOOK_AHEAD, which
ArduCopter also flies in RTL). Measured (tests/parity/probes/mission_wpyaw.py): legs east then
north-east face 90° and 45° for 1, 2 and 3; the way home from there faces 242.5° for 1 and 3 and
stays at 45° for 2; 0 keeps the armed heading throughout.

A region of interest (DO_SET_ROI and its kin) takes over from that: the nose points at it from
wherever the vehicle is, whatever WP_YAW_BEHAVIOR says, until it is cleared (ArduCopter's AutoYaw
mode ROI; measured: a leg flown east with an ROI to the west arrives at 270°).
"""
from __future__ import annotations

import math

from .context import ModeContext

NEVER_CHANGE_YAW, EXCEPT_RTL, LOOK_AHEAD = 0, 2, 3  # WP_YAW_BEHAVIOR values; 1 faces the way everywhere
MIN_SPEED_SHARE = 0.05  # of WPNAV_SPEED: AC_PosControl updates its yaw only above it
LOOK_AHEAD_MIN_SPEED_M_S = 1.0  # ground speed LOOK_AHEAD follows the course from (YAW_LOOK_AHEAD_MIN_SPEED)


def holds_in_rtl(params) -> bool:
    """Whether WP_YAW_BEHAVIOR leaves the heading alone in an RTL (ArduCopter's default_mode(rtl)
    is HOLD): then RTL does not turn back to the armed heading over home either."""
    behaviour = params["WP_YAW_BEHAVIOR"]
    return behaviour == NEVER_CHANGE_YAW or behaviour == EXCEPT_RTL


def bearing_to(ctx: ModeContext, target_ne: tuple[float, float]) -> float:
    """The heading [rad] from the vehicle to a point (north, east) of the local frame."""
    b = ctx.body
    return math.atan2(target_ne[1] - b.e_m, target_ne[0] - b.n_m)


class AutoYaw:
    __slots__ = ("yaw", "roi", "rtl")

    def __init__(self, rtl: bool = False) -> None:
        self.yaw: float | None = None  # None: hold the heading the vehicle has
        self.roi: tuple[float, float] | None = None  # (north, east) the nose points at
        self.rtl = rtl  # the legs of an RTL (WP_YAW_BEHAVIOR 2 holds there)

    def facing(self, ctx: ModeContext, vn: float, ve: float) -> float | None:
        """The heading to fly for a desired horizontal velocity (vn, ve) [m/s], or None to hold."""
        if self.roi is not None:
            self.yaw = bearing_to(ctx, self.roi)
            return self.yaw
        params = ctx.params
        behaviour = params["WP_YAW_BEHAVIOR"]
        if behaviour == NEVER_CHANGE_YAW or (self.rtl and behaviour == EXCEPT_RTL):
            return None
        if behaviour == LOOK_AHEAD:
            b = ctx.body
            if b.vn_m_s * b.vn_m_s + b.ve_m_s * b.ve_m_s > LOOK_AHEAD_MIN_SPEED_M_S * LOOK_AHEAD_MIN_SPEED_M_S:
                self.yaw = math.atan2(b.ve_m_s, b.vn_m_s)
        elif math.hypot(vn, ve) > MIN_SPEED_SHARE * params["WPNAV_SPEED"] * 0.01:
            self.yaw = math.atan2(ve, vn)
        return self.yaw

"""The heading GUIDED flies: what its last target or CONDITION_YAW asked for, else the default
(auto_yaw.AutoYaw: face the way it flies). ArduCopter's AutoYaw modes as GUIDED uses them:

  DEFAULT     face the way the position controller takes the vehicle (WP_YAW_BEHAVIOR)
  HOLD        keep the heading it has
  FIXED       turn by an offset at a slew rate (CONDITION_YAW; a body-frame yaw of a setpoint)
  ANGLE_RATE  a heading that moves on at a rate (a setpoint's yaw, with its yaw rate or 0)
  RATE        turn at a rate (a setpoint's yaw rate alone)
  ROI         face a point (DO_SET_ROI and its kin) from wherever the vehicle is

A setpoint's rate (ANGLE_RATE, RATE) stops when its stream stops (GUID_TIMEOUT): the heading
is held where it got to, as ArduCopter's falls back to HOLD.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ..control.attitude import wrap_pi
from .base import Setpoint

if TYPE_CHECKING:
    from firefly.sim.rigid_body import BodyState

DEFAULT, HOLD, FIXED, ANGLE_RATE, RATE, ROI = "default", "hold", "fixed", "angle_rate", "rate", "roi"
TURNING = (ANGLE_RATE, RATE)  # the kinds a stopped stream stops
SLEW_YAW_DEFAULT_CDEG_S = 6000.0  # ATC_SLEW_YAW: the fastest a FIXED turn goes


class GuidedYaw:
    __slots__ = ("kind", "angle", "rate", "offset", "slew", "roi")

    def __init__(self) -> None:
        self.kind = DEFAULT
        self.angle = 0.0  # the heading target [rad] (HOLD, FIXED, ANGLE_RATE)
        self.rate = 0.0  # [rad/s] (ANGLE_RATE, RATE)
        self.offset = 0.0  # what a FIXED turn has still to turn [rad]
        self.slew = 0.0  # a FIXED turn's rate [rad/s]
        self.roi = (0.0, 0.0)  # the point (north, east) an ROI faces

    def set_angle_rate(self, angle: float, rate: float) -> None:
        self.kind, self.angle, self.rate = ANGLE_RATE, wrap_pi(angle), rate

    def set_roi(self, roi_ne: tuple[float, float]) -> None:
        self.kind, self.roi = ROI, roi_ne

    def set_rate(self, rate: float) -> None:
        self.kind, self.rate = RATE, rate

    def set_fixed(self, heading_now: float, angle: float, rate: float, direction: int, relative: bool,
                  slew_max: float) -> None:
        """CONDITION_YAW's turn: by `angle` (relative; direction -1 counter-clockwise) or to the
        heading `angle` (the way round `direction` says, 0 the shorter), at `rate` (0: slew_max)."""
        if self.kind not in (HOLD, FIXED, ANGLE_RATE):  # from the default, a rate or an ROI: from here
            self.angle = heading_now
        if relative:
            self.offset = angle * (1.0 if direction >= 0 else -1.0)
        else:
            offset = wrap_pi(angle - self.angle)
            if direction < 0 < offset:
                offset -= 2.0 * math.pi
            elif offset < 0 < direction:
                offset += 2.0 * math.pi
            self.offset = offset
        self.slew = min(slew_max, rate) if rate > 0 else slew_max
        self.kind = FIXED

    def hold(self, heading_now: float) -> None:
        self.kind, self.angle = HOLD, heading_now

    def stop_turning(self, heading_now: float) -> None:
        """The stream that set a rate stopped: the heading stays where the rate took it."""
        if self.kind == RATE:
            self.hold(heading_now)
        elif self.kind == ANGLE_RATE:
            self.kind = HOLD

    def fly(self, sp: Setpoint, dt: float, here: BodyState) -> bool:
        """Fill sp.yaw / sp.yaw_rate (`here`: the vehicle, which an ROI is seen from); False for
        DEFAULT (the mode picks the heading)."""
        kind = self.kind
        if kind == DEFAULT:
            return False
        if kind == ROI:
            sp.yaw = math.atan2(self.roi[1] - here.e_m, self.roi[0] - here.n_m)
            return True
        if kind == RATE:
            sp.yaw, sp.yaw_rate = None, self.rate
            return True
        if kind == ANGLE_RATE:
            self.angle = wrap_pi(self.angle + self.rate * dt)
        elif kind == FIXED:
            step = max(-self.slew * dt, min(self.slew * dt, self.offset))
            self.offset -= step
            self.angle = wrap_pi(self.angle + step)
        sp.yaw = self.angle
        return True

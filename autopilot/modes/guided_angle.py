"""GUIDED's attitude target (SET_ATTITUDE_TARGET), flown by GUIDED and GUIDED_NOGPS.

As ArduCopter's ModeGuided angle control: an attitude (roll, pitch, yaw) or, without one, body
rates the attitude target turns at; with it a climb rate (the height is held where the climbs
leave it) or, GUID_OPTIONS bit 3, a thrust (0..1 of full thrust, MOT_THST_HOVER hovers, raised
by 1/cos(tilt) as ArduCopter's angle boost). When the stream stops for GUID_TIMEOUT the target
levels at its heading and holds the height. On the ground nothing happens until a climb rate
or a thrust above zero asks for a takeoff.
"""
from __future__ import annotations

import math

from ..control.attitude import wrap_pi
from .base import Setpoint
from .context import ModeContext

MIN_TIMEOUT_S = 0.1  # GUID_TIMEOUT below this is taken as this (ArduCopter's get_timeout_ms)
MIN_BOOST_COS = 0.1  # the angle boost stops growing past this tilt (ArduCopter's)
# ArduCopter SITL, GUID_OPTIONS 8, level, from a hover: thrust 0.30/0.40/0.45/0.50 gives
# -1.3/+0.7/+1.6/+2.3 m/s/s (hover near 0.37): force/weight = (thrust/hover)^0.6 fits them.
THRUST_CURVE_POWER = 0.6


def guided_timeout_s(ctx: ModeContext) -> float:
    return max(ctx.params["GUID_TIMEOUT"], MIN_TIMEOUT_S)


def stick_for_thrust(ctx: ModeContext, thrust: float, roll: float, pitch: float) -> float:
    """ArduCopter's thrust (0..1, hover at MOT_THST_HOVER) as the manual throttle the cascade
    flies (0.5 = hover, 1 = full thrust), with the angle boost. The force grows as the thrust's
    THRUST_CURVE_POWER, as measured on ArduCopter SITL (its thrust linearisation over its motor
    model): 0.05 above the hover thrust climbs at 0.8 m/s/s, not the 1.3 a linear force would."""
    cos_tilt = max(math.cos(roll) * math.cos(pitch), MIN_BOOST_COS)
    share_of_weight = (max(thrust, 0.0) / ctx.params["MOT_THST_HOVER"]) ** THRUST_CURVE_POWER / cos_tilt
    if share_of_weight <= 1.0:
        return 0.5 * share_of_weight
    hover = ctx.hover_thrust_share
    return min(1.0, 0.5 + 0.5 * (share_of_weight - 1.0) * hover / (1.0 - hover))


class AttitudeTarget:
    __slots__ = ("attitude", "rates", "use_thrust", "thrust", "climb_m_s", "updated_s", "hold_d")
    attitude: tuple[float, float, float]  # (roll, pitch, yaw) [rad]
    rates: tuple[float, float, float]  # body rates [rad/s]
    hold_d: float

    def __init__(self) -> None:
        self.updated_s = -math.inf

    def start(self, ctx: ModeContext, heading: float) -> None:
        """Level at `heading`, holding the height (ArduCopter's angle_control_start)."""
        self.attitude = (0.0, 0.0, heading)
        self.rates = (0.0, 0.0, 0.0)
        self.use_thrust, self.thrust, self.climb_m_s = False, 0.0, 0.0
        self.updated_s = ctx.time_s
        self.hold_d = ctx.body.d_m

    def set(self, ctx: ModeContext, attitude: tuple[float, float, float] | None, rates: tuple[float, float, float],
            climb_or_thrust: float, use_thrust: bool) -> None:
        """attitude None: turn at `rates` from the present target (a zero quaternion)."""
        if not use_thrust and self.use_thrust:  # from thrust back to a climb rate: hold from here
            self.hold_d = ctx.body.d_m
        if attitude is not None:
            self.attitude = attitude
        self.rates = rates
        self.use_thrust = use_thrust
        self.thrust = climb_or_thrust if use_thrust else 0.0
        self.climb_m_s = 0.0 if use_thrust else climb_or_thrust
        self.updated_s = ctx.time_s

    def fly(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        params = ctx.params
        climb = 0.0
        if not self.use_thrust:
            climb = max(-params["WPNAV_SPEED_DN"] / 100.0, min(params["WPNAV_SPEED_UP"] / 100.0, self.climb_m_s))
        if ctx.time_s - self.updated_s > guided_timeout_s(ctx):
            self.attitude = (0.0, 0.0, self.attitude[2])
            self.rates = (0.0, 0.0, 0.0)
            climb = 0.0
            if self.use_thrust:
                self.use_thrust = False
                self.hold_d = ctx.body.d_m
        body = ctx.body
        takes_off = (self.thrust if self.use_thrust else climb) > 0.0
        if ctx.landed and not takes_off:  # ArduCopter's ground handling: idle, level
            self.hold_d = body.d_m
            sp.pos_d, sp.lean = body.d_m, (0.0, 0.0)
            return
        roll, pitch, yaw = self.attitude
        p, q, r = self.rates
        if p or q or r:  # the target turns at the body rates (small angles: as Euler rates)
            roll, pitch, yaw = roll + p * dt, pitch + q * dt, wrap_pi(yaw + r * dt)
            self.attitude = (roll, pitch, yaw)
        sp.lean, sp.yaw = (roll, pitch), yaw
        if self.use_thrust:
            sp.throttle = stick_for_thrust(ctx, self.thrust, *ctx.attitude[:2])
            return
        self.hold_d -= climb * dt
        sp.pos_d, sp.vel_d = self.hold_d, -climb

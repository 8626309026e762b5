"""How GUIDED stops when paused or when its velocity stream stops: ArduCopter's position
controller given a velocity of zero, which shapes the slowing down within WPNAV_ACCEL and its
jerk limit (PSC_JERK_XY) from the acceleration the vehicle has. A vehicle still speeding up
first stops speeding up (measured on ArduCopter SITL: paused at 6.4 m/s it peaks at 8 m/s and
is still after 4.2 s; an instant change of acceleration would stop it a second and 7 m sooner).
"""
from __future__ import annotations

import math

from ..control.position import GRAVITY_M_S2, sqrt_controller
from .base import Setpoint
from .context import ModeContext

JERK_DEFAULT_M_S3 = 5.0  # PSC_JERK_XY's default
# ArduCopter shapes from its trajectory's acceleration; a vehicle speeding up leans further than
# that (the lean also makes up its lag behind the trajectory): about twice as far here. Starting
# from half the lean's acceleration, a pause at 6.5 m/s gains 0.6 m/s before slowing, as
# ArduCopter's does (measured: 0.62-0.87 m/s; from the full lean 1.4 m/s).
TRAJECTORY_SHARE_OF_LEAN = 0.5
STILL_M_S, STILL_M_S2 = 0.02, 0.05  # below both the stop is over


class JerkLimitedStop:
    __slots__ = ("vel", "accel")

    def __init__(self, ctx: ModeContext, steady_vel: tuple[float, float] | None = None) -> None:
        """From a velocity flown steadily (a velocity target), or else from the vehicle's velocity
        and (a share of) the acceleration its lean gives."""
        if steady_vel is not None:
            self.vel, self.accel = steady_vel, (0.0, 0.0)
            return
        b = ctx.body
        roll, pitch, yaw = ctx.attitude
        g = GRAVITY_M_S2 * TRAJECTORY_SHARE_OF_LEAN
        forward = -g * math.tan(pitch)
        right = g * math.tan(roll) / max(math.cos(pitch), 0.1)
        c, s = math.cos(yaw), math.sin(yaw)
        self.vel = (b.vn_m_s, b.ve_m_s)
        self.accel = (forward * c - right * s, forward * s + right * c)

    def fly(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        """The velocity and acceleration of the stop this tick, into sp (followed as they are)."""
        params = ctx.params
        accel_max = params["WPNAV_ACCEL"] / 100.0
        jerk = params.get("PSC_JERK_XY", JERK_DEFAULT_M_S3)
        vn, ve = self.vel
        an, ae = self.accel
        speed = math.sqrt(vn * vn + ve * ve)
        want_n = want_e = 0.0
        if speed > 1e-6:
            slowing = min(accel_max, sqrt_controller(speed, jerk / accel_max, accel_max))
            want_n, want_e = -vn / speed * slowing, -ve / speed * slowing
        dn, de = want_n - an, want_e - ae
        change = math.sqrt(dn * dn + de * de)
        step = jerk * dt
        if change > step:
            dn, de = dn * step / change, de * step / change
        an, ae = an + dn, ae + de
        vn, ve = vn + an * dt, ve + ae * dt
        if vn * self.vel[0] + ve * self.vel[1] <= 0.0 or (vn * vn + ve * ve < STILL_M_S ** 2
                                                          and an * an + ae * ae < STILL_M_S2 ** 2):
            vn = ve = an = ae = 0.0  # through zero, or the shaper's last creep: still
        self.vel, self.accel = (vn, ve), (an, ae)
        sp.vel_ne, sp.accel_ne = self.vel, self.accel

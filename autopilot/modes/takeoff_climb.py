"""The takeoff AUTO's NAV_TAKEOFF and GUIDED's user takeoff fly, as ArduCopter's auto takeoff.

Measured on ArduCopter SITL (parity area `takeoff`): armed on the ground, nothing spins for the
arming delay (the vehicle's business); then the motors spool up to ground idle in MOT_SPOOL_TIME
(and on to full range at once, the throttle asked being zero); then the throttle slews up, all of it in TKOFF_SLEW_TIME, until the
vehicle accelerates upward at half WPNAV_ACCEL_Z (or the throttle reaches TKOFF_THR_MAX, at most
0.9). From there a climb profile runs to the height: jerk-limited (PSC_JERK_Z), at most
WPNAV_ACCEL_Z and WPNAV_SPEED_UP, braking at half the acceleration so it arrives without
overshoot, and the takeoff is done when the profile is within the stopping distance of a tenth of
the climb speed and slower than that tenth. A takeoff started in the air skips straight to the
profile, from the vehicle's own height and climb.
"""
from __future__ import annotations

from ..control.position import GRAVITY_M_S2, stick_for_thrust_share
from ..control.shaping import shape_pos_vel_accel
from .base import Setpoint
from .context import ModeContext

SPOOLING, SLEWING, CLIMBING = "spooling", "slewing", "climbing"
ACCEL_Z_LIMIT_M_S2 = 7.5  # the most the position controller brakes a climb with, whatever WPNAV_ACCEL_Z says
DONE_SHARE = 0.1  # of the climb speed: slower than this and within its stopping distance, done


class TakeoffClimb:
    """One takeoff to a height (down coordinate `target_d`), flown from its construction on: the
    mode calls it every tick until `done`."""

    def __init__(self, ctx: ModeContext, target_d: float) -> None:
        self.target_d = target_d
        b = ctx.body
        self.hold_ne = (b.n_m, b.e_m)
        self.throttle = 0.0  # share of full thrust while slewing
        self.done = False
        params = ctx.params
        self.speed_up = params["WPNAV_SPEED_UP"] / 100.0
        self.speed_dn = params["WPNAV_SPEED_DN"] / 100.0
        self.accel = params["WPNAV_ACCEL_Z"] / 100.0
        self.jerk = params["PSC_JERK_Z"]
        if ctx.landed:
            self.phase = SPOOLING
            # ground idle comes MOT_SPOOL_TIME after the arming delay; from there the motors take
            # the full range at once, as the throttle they are asked for is still zero
            self.spooled_at_s = max(ctx.interlock_at_s + params["MOT_SPOOL_TIME"], ctx.time_s)
        else:
            self._climb_from_here(ctx, 0.0)

    def _climb_from_here(self, ctx: ModeContext, accel_up: float) -> None:
        """The profile starts from the vehicle's state (ArduCopter's init of the height controller)."""
        b = ctx.body
        self.phase = CLIMBING
        self.pos_up, self.vel_up = -b.d_m, -b.vd_m_s
        self.accel_up = max(-self.accel, min(self.accel, accel_up))

    def fly(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        """Fill the setpoint for this tick; `done` turns True when the takeoff is over."""
        sp.pos_ne = self.hold_ne
        phase = self.phase
        if phase == SPOOLING:
            sp.pos_d = ctx.body.d_m  # nothing asks to climb: the motors stay at ground idle
            if ctx.time_s >= self.spooled_at_s:
                self.phase = SLEWING
            return
        if phase == SLEWING:
            self._slew(ctx, sp, dt)
            return
        self._climb(sp, dt)

    def _slew(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        params = ctx.params
        self.throttle = min(1.0, self.throttle + dt / max(params["TKOFF_SLEW_TIME"], 0.25))
        accel_up = -ctx.accel_body[2] - GRAVITY_M_S2  # level on the ground: the pull of the rotors less 1 g
        if self.throttle >= min(params["TKOFF_THR_MAX"], 0.9) or accel_up >= 0.5 * self.accel:
            ctx.restart_position_control()
            self._climb_from_here(ctx, accel_up)
            self._climb(sp, dt)
            return
        sp.pos_ne = None
        sp.lean = (0.0, 0.0)
        sp.yaw = ctx.attitude[2]
        sp.throttle = stick_for_thrust_share(self.throttle, ctx.hover_thrust_share)

    def _climb(self, sp: Setpoint, dt: float) -> None:
        target_up = -self.target_d
        half = 0.5 * dt * dt
        self.pos_up += self.vel_up * dt + self.accel_up * half
        self.vel_up += self.accel_up * dt
        accel = self.accel
        self.accel_up = shape_pos_vel_accel(target_up, 0.0, 0.0, self.pos_up, self.vel_up, self.accel_up,
                                            -self.speed_dn, self.speed_up, -min(accel, ACCEL_Z_LIMIT_M_S2),
                                            accel, self.jerk, dt)
        sp.pos_d, sp.vel_d = -self.pos_up, -self.vel_up
        slow = DONE_SHARE * self.speed_up
        stop = 0.5 * slow * slow / accel
        if self.pos_up >= target_up - stop and self.vel_up < slow:
            self.done = True

"""CIRCLE: orbit a centre at CIRCLE_RADIUS, CIRCLE_RATE degrees a second, nose to the centre; the
pilot's climb stick moves the height, as in LOITER (ArduCopter's ModeCircle with AC_Circle).

As ArduCopter: the centre lies the radius ahead of where the vehicle can stop (or is that point,
CIRCLE_OPTIONS bit 2); the orbit starts on the side the vehicle is on, so the nose already points
at the centre; the angular rate ramps up at the acceleration the position controller allows
(WPNAV_ACCEL / radius, at least 2 deg/s/s), capped where the inward acceleration would take more
than half of WPNAV_ACCEL. With the pilot's sticks (CIRCLE_OPTIONS bit 0) pitch changes the
radius and roll the rate. A radius of 0 is a panorama: the vehicle turns on the spot.
On the ground it does nothing (no take-off in this mode).
"""
from __future__ import annotations

import math

from ..control.attitude import wrap_pi
from .base import Mode, Setpoint, stick_deadzone, stopping_point
from .context import ModeContext
from .manual import pilot_vertical
from .numbers import ModeNumber

ANGULAR_ACCEL_MIN = math.radians(2.0)  # AC_CIRCLE_ANGULAR_ACCEL_MIN
RADIUS_MAX_M = 2000.0  # AC_CIRCLE_RADIUS_MAX
RATE_MAX_DEG_S = 90.0
PILOT_CONTROL, FACE_TRAVEL, START_AT_CENTRE = 1, 2, 4  # CIRCLE_OPTIONS bits


class Circle(Mode):
    number = ModeNumber.CIRCLE
    requires_position = True
    centre: tuple[float, float]
    radius_m: float
    rate_deg_s: float  # the rate asked for (CIRCLE_RATE, or as the pilot changed it)
    angle: float  # of the target point seen from the centre [rad, from north]
    angular_vel: float  # now, ramping towards the allowed rate [rad/s]
    _radius_param: float
    _rate_changing: bool
    _hold_d: float
    _target: tuple[float, float]

    def enter(self, ctx: ModeContext) -> str | None:
        params = ctx.params
        self._radius_param = params["CIRCLE_RADIUS"]
        self.radius_m = min(max(self._radius_param / 100.0, 0.0), RADIUS_MAX_M)
        self.rate_deg_s = params["CIRCLE_RATE"]
        self._rate_changing = False
        (n, e), self._hold_d = stopping_point(ctx)
        yaw = ctx.attitude[2]
        if not int(params["CIRCLE_OPTIONS"]) & START_AT_CENTRE:
            n, e = n + self.radius_m * math.cos(yaw), e + self.radius_m * math.sin(yaw)
        self.centre = (n, e)
        # Behind the centre, where the vehicle is: the nose needs no turn to face the centre.
        self.angle = yaw if self.radius_m <= 0 else wrap_pi(yaw - math.pi)
        self.angular_vel = 0.0
        self._target = (ctx.body.n_m, ctx.body.e_m)
        return None

    def limits(self, ctx: ModeContext) -> tuple[float, float]:
        """(the angular rate to reach [rad/s], the angular acceleration [rad/s/s])."""
        rate = math.radians(self.rate_deg_s)
        if self.radius_m <= 0:
            return rate, max(abs(rate), ANGULAR_ACCEL_MIN)
        params = ctx.params
        accel = params["WPNAV_ACCEL"] / 100.0
        speed = min(params["WPNAV_SPEED"] / 100.0, math.sqrt(max(0.5 * accel * self.radius_m, 0.0)))
        most = speed / self.radius_m
        return min(max(rate, -most), most), max(accel / self.radius_m, ANGULAR_ACCEL_MIN)

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        sp.clear()
        params = ctx.params
        if params["CIRCLE_RADIUS"] != self._radius_param:  # changed in flight: flown at once
            self._radius_param = params["CIRCLE_RADIUS"]
            self.radius_m = min(max(self._radius_param / 100.0, 0.0), RADIUS_MAX_M)
        if int(params["CIRCLE_OPTIONS"]) & PILOT_CONTROL and ctx.pilot.present(ctx.time_s):
            self._pilot_changes(ctx, dt)
        b = ctx.body
        if ctx.landed:  # ArduCopter's circle runs nothing on the ground
            sp.pos_ne = self._target = (b.n_m, b.e_m)
            self._hold_d = b.d_m
            return
        self._advance(ctx, dt)
        r, a, w = self.radius_m, self.angle, self.angular_vel
        cn, ce = self.centre
        cos_a, sin_a = math.cos(a), math.sin(a)
        tn, te = cn + r * cos_a, ce + r * sin_a
        self._target = (tn, te)
        # The point alone, no velocity along the circle: ArduCopter's position controller chases
        # it (input_pos_vel_accel with zero velocity), so the vehicle trails the point and flies
        # a little inside the radius; its nose is set from where its controller is, not the point.
        sp.pos_ne = (tn, te)
        if r > 0:
            yaw = math.atan2(ce - b.e_m, cn - b.n_m)  # the vehicle to the centre
            if int(params["CIRCLE_OPTIONS"]) & FACE_TRAVEL:
                yaw += -math.pi / 2 if self.rate_deg_s > 0 else math.pi / 2
        else:
            yaw = a
        # The nose turns with the orbit: its rate fed forward, as a lead on the heading (the
        # heading loop is P on the error), or the nose would trail the centre by degrees.
        yaw_p = params["ATC_ANG_YAW_P"]
        sp.yaw = wrap_pi(yaw + (w / yaw_p if yaw_p > 0 else 0.0))
        self._hold_d = pilot_vertical(ctx, sp, self._hold_d)

    def _advance(self, ctx: ModeContext, dt: float) -> None:
        """The angular rate ramped towards its limit, and the target angle moved on by it."""
        most, accel = self.limits(ctx)
        w = self.angular_vel
        if w < most:
            w = min(w + accel * dt, most)
        elif w > most:
            w = max(w - accel * dt, most)
        self.angular_vel = w
        self.angle = wrap_pi(self.angle + w * dt)

    def _pilot_changes(self, ctx: ModeContext, dt: float) -> None:
        """Pitch forward shrinks the radius at WPNAV_SPEED; roll changes the rate by up to
        1 deg/s each second, within the direction already flown (from a standstill, either)."""
        pilot = ctx.pilot
        pitch = stick_deadzone(pilot.pitch)
        if pitch:
            speed = ctx.params["WPNAV_SPEED"] / 100.0
            self.radius_m = min(max(self.radius_m - pitch * speed * dt, 0.0), RADIUS_MAX_M)
        roll = stick_deadzone(pilot.roll)
        if not roll:
            self._rate_changing = False
            return
        rate, current = self.rate_deg_s, math.degrees(self.angular_vel)
        if rate > 0:
            self.rate_deg_s = min(max(current + roll * dt, 0.0), RATE_MAX_DEG_S)
        elif rate < 0:
            self.rate_deg_s = min(max(current + roll * dt, -RATE_MAX_DEG_S), 0.0)
        elif not self._rate_changing:
            self.rate_deg_s = roll * dt
        self._rate_changing = True

    def destination(self) -> tuple[float, float, float | None] | None:
        return self._target[0], self._target[1], None

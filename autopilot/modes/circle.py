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
from .circle_nav import RADIUS_MAX_M, CircleNav
from .context import ModeContext
from .manual import pilot_vertical
from .numbers import ModeNumber

RATE_MAX_DEG_S = 90.0
PILOT_CONTROL, FACE_TRAVEL, START_AT_CENTRE = 1, 2, 4  # CIRCLE_OPTIONS bits


class Circle(Mode):
    number = ModeNumber.CIRCLE
    requires_position = True
    nav: CircleNav  # the orbit: centre, radius, the rate asked for (CIRCLE_RATE, or as the pilot changed it)
    _radius_param: float
    _rate_changing: bool
    _hold_d: float
    _target: tuple[float, float]

    @property
    def centre(self) -> tuple[float, float]:
        return self.nav.centre

    @property
    def radius_m(self) -> float:
        return self.nav.radius_m

    @property
    def rate_deg_s(self) -> float:
        return self.nav.rate_deg_s

    @property
    def angular_vel(self) -> float:
        return self.nav.angular_vel

    def enter(self, ctx: ModeContext) -> str | None:
        params = ctx.params
        self._radius_param = params["CIRCLE_RADIUS"]
        radius = min(max(self._radius_param / 100.0, 0.0), RADIUS_MAX_M)
        self._rate_changing = False
        (n, e), self._hold_d = stopping_point(ctx)
        yaw = ctx.attitude[2]
        if not int(params["CIRCLE_OPTIONS"]) & START_AT_CENTRE:
            n, e = n + radius * math.cos(yaw), e + radius * math.sin(yaw)
        # Behind the centre, where the vehicle is: the nose needs no turn to face the centre.
        self.nav = CircleNav((n, e), radius, params["CIRCLE_RATE"], yaw if radius <= 0 else wrap_pi(yaw - math.pi))
        self._target = (ctx.body.n_m, ctx.body.e_m)
        return None

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        sp.clear()
        params = ctx.params
        nav = self.nav
        if params["CIRCLE_RADIUS"] != self._radius_param:  # changed in flight: flown at once
            self._radius_param = params["CIRCLE_RADIUS"]
            nav.radius_m = min(max(self._radius_param / 100.0, 0.0), RADIUS_MAX_M)
        if int(params["CIRCLE_OPTIONS"]) & PILOT_CONTROL and ctx.pilot.present(ctx.time_s):
            self._pilot_changes(ctx, dt)
        b = ctx.body
        if ctx.landed:  # ArduCopter's circle runs nothing on the ground
            sp.pos_ne = self._target = (b.n_m, b.e_m)
            self._hold_d = b.d_m
            return
        nav.advance(params, dt)
        # The point alone, no velocity along the circle: ArduCopter's position controller chases
        # it (input_pos_vel_accel with zero velocity), so the vehicle trails the point and flies
        # a little inside the radius; its nose is set from where its controller is, not the point.
        sp.pos_ne = self._target = nav.point()
        sp.yaw = nav.heading(b.n_m, b.e_m, bool(int(params["CIRCLE_OPTIONS"]) & FACE_TRAVEL),
                             params["ATC_ANG_YAW_P"])
        self._hold_d = pilot_vertical(ctx, sp, self._hold_d, dt)

    def _pilot_changes(self, ctx: ModeContext, dt: float) -> None:
        """Pitch forward shrinks the radius at WPNAV_SPEED; roll changes the rate by up to
        1 deg/s each second, within the direction already flown (from a standstill, either)."""
        pilot, nav = ctx.pilot, self.nav
        pitch = stick_deadzone(pilot.pitch)
        if pitch:
            speed = ctx.params["WPNAV_SPEED"] / 100.0
            nav.radius_m = min(max(nav.radius_m - pitch * speed * dt, 0.0), RADIUS_MAX_M)
        roll = stick_deadzone(pilot.roll)
        if not roll:
            self._rate_changing = False
            return
        rate, current = nav.rate_deg_s, math.degrees(nav.angular_vel)
        if rate > 0:
            nav.rate_deg_s = min(max(current + roll * dt, 0.0), RATE_MAX_DEG_S)
        elif rate < 0:
            nav.rate_deg_s = min(max(current + roll * dt, -RATE_MAX_DEG_S), 0.0)
        elif not self._rate_changing:
            nav.rate_deg_s = roll * dt
        self._rate_changing = True

    def destination(self) -> tuple[float, float, float | None] | None:
        return self._target[0], self._target[1], None

"""The circle navigator both CIRCLE mode and AUTO's NAV_LOITER_TURNS fly (ArduCopter's AC_Circle).

A target point goes round a centre at a radius; its angular rate ramps up at the acceleration the
position controller allows (WPNAV_ACCEL / radius, at least 2 deg/s/s) to the rate asked for,
capped where the inward acceleration would take more than half of WPNAV_ACCEL (and the speed
WPNAV_SPEED). A radius of 0 is a panorama: the point stays at the centre and the nose turns.
The angle is from north towards east (a positive rate is clockwise seen from above); the total
angle flown is kept for counting turns.
"""
from __future__ import annotations

import math

from ..control.attitude import wrap_pi

ANGULAR_ACCEL_MIN = math.radians(2.0)  # AC_CIRCLE_ANGULAR_ACCEL_MIN
RADIUS_MAX_M = 2000.0  # AC_CIRCLE_RADIUS_MAX


class CircleNav:
    __slots__ = ("centre", "radius_m", "rate_deg_s", "angle", "angular_vel", "angle_total")

    def __init__(self, centre: tuple[float, float], radius_m: float, rate_deg_s: float, angle: float) -> None:
        self.centre = centre
        self.radius_m = min(max(radius_m, 0.0), RADIUS_MAX_M)
        self.rate_deg_s = rate_deg_s
        self.angle = angle  # of the target point seen from the centre [rad]; the heading in a panorama
        self.angular_vel = 0.0  # now, ramping towards the allowed rate [rad/s]
        self.angle_total = 0.0  # flown since the start, signed [rad]

    def limits(self, params) -> tuple[float, float]:
        """(the angular rate to reach [rad/s], the angular acceleration [rad/s/s])."""
        rate = math.radians(self.rate_deg_s)
        if self.radius_m <= 0:
            return rate, max(abs(rate), ANGULAR_ACCEL_MIN)
        accel = params["WPNAV_ACCEL"] / 100.0
        speed = min(params["WPNAV_SPEED"] / 100.0, math.sqrt(max(0.5 * accel * self.radius_m, 0.0)))
        most = speed / self.radius_m
        return min(max(rate, -most), most), max(accel / self.radius_m, ANGULAR_ACCEL_MIN)

    def advance(self, params, dt: float) -> None:
        """The angular rate ramped towards its limit, and the target angle moved on by it."""
        most, accel = self.limits(params)
        w = self.angular_vel
        if w < most:
            w = min(w + accel * dt, most)
        elif w > most:
            w = max(w - accel * dt, most)
        self.angular_vel = w
        self.angle = wrap_pi(self.angle + w * dt)
        self.angle_total += w * dt

    def point(self) -> tuple[float, float]:
        """The target on the circle (the centre in a panorama), north and east [m]."""
        r, (cn, ce) = self.radius_m, self.centre
        if r <= 0:
            return cn, ce
        return cn + r * math.cos(self.angle), ce + r * math.sin(self.angle)

    def heading(self, n_m: float, e_m: float, face_travel: bool, yaw_p: float) -> float:
        """The nose: at the centre from where the vehicle is (or along the travel), the angle itself
        in a panorama; the orbit's rate fed forward as a lead (the heading loop is P on the error),
        or the nose would trail by degrees."""
        cn, ce = self.centre
        if self.radius_m > 0:
            yaw = math.atan2(ce - e_m, cn - n_m)
            if face_travel:
                yaw += -math.pi / 2 if self.rate_deg_s > 0 else math.pi / 2
        else:
            yaw = self.angle
        return wrap_pi(yaw + (self.angular_vel / yaw_p if yaw_p > 0 else 0.0))

"""LOITER's answer to the sticks, as ArduCopter's AC_Loiter: a stick is a lean angle (up to
LOIT_ANG_MAX; 0 = two thirds of ANGLE_MAX), which is an acceleration the attitude reaches after
a short lag; a drag in proportion to the speed (the full-stick acceleration at LOIT_SPEED) keeps
the speed under LOIT_SPEED, so a half stick settles at about half of it; with the sticks centred
a braking acceleration (up to LOIT_BRK_ACCEL, after LOIT_BRK_DELAY) joins the drag. The target
point moves with the velocity so made; the position controller follows point, velocity and
acceleration. Simple avoidance cuts the velocity before the point moves on, so the point stops
short of a fence (safety/simple_avoid.py)."""
from __future__ import annotations

import math

from .context import ModeContext

GRAVITY = 9.80665
ATTITUDE_LAG_S = 0.2  # the attitude's input shaping: the acceleration follows the stick this late
STOPPED_M_S = 0.05


class LoiterNav:
    def __init__(self, target_ne: tuple[float, float], vel_ne: tuple[float, float] = (0.0, 0.0)):
        self.target = target_ne
        self.vel = vel_ne
        self.accel = (0.0, 0.0)  # the predicted acceleration (the lean the attitude has reached)
        self._centred_s = 0.0  # how long the sticks have been centred

    @staticmethod
    def angle_max(ctx: ModeContext) -> float:
        p = ctx.params
        loiter = p.get("LOIT_ANG_MAX", 0.0)
        return math.radians(loiter if loiter > 0 else p["ANGLE_MAX"] / 100.0 * 2.0 / 3.0)

    def update(self, ctx: ModeContext, fwd: float, right: float, dt: float) -> None:
        """fwd, right: the sticks (-1..1), in the vehicle's heading frame."""
        p = ctx.params
        angle_max = self.angle_max(ctx)
        yaw = ctx.attitude[2]
        c, s = math.cos(yaw), math.sin(yaw)
        a_fwd, a_right = GRAVITY * math.tan(fwd * angle_max), GRAVITY * math.tan(right * angle_max)
        wanted = (a_fwd * c - a_right * s, a_fwd * s + a_right * c)
        k = min(dt / ATTITUDE_LAG_S, 1.0)
        an, ae = (self.accel[0] + (wanted[0] - self.accel[0]) * k, self.accel[1] + (wanted[1] - self.accel[1]) * k)
        self.accel = (an, ae)
        vn, ve = self.vel[0] + an * dt, self.vel[1] + ae * dt
        speed = math.hypot(vn, ve)
        speed_max = max(p["LOIT_SPEED"] / 100.0, 0.2)
        centred = fwd == 0.0 and right == 0.0
        self._centred_s = self._centred_s + dt if centred else 0.0
        stopped = False
        if speed > 0.0:
            drag = GRAVITY * math.tan(angle_max) * speed / speed_max
            brake = 0.0
            if centred and self._centred_s > p.get("LOIT_BRK_DELAY", 1.0):
                gain = p["PSC_VELXY_P"] * 0.5
                brake = min(p.get("LOIT_BRK_ACCEL", 250.0) / 100.0, gain * speed)
            slowed = max(speed - (drag + brake) * dt, 0.0)
            slowed = min(slowed, speed_max)
            vn, ve = vn * slowed / speed, ve * slowed / speed
            stopped = centred and slowed < STOPPED_M_S
        avoided = ctx.avoid_velocity((vn, ve, 0.0), p["LOIT_ACC_MAX"] / 100.0, dt)
        if avoided[0] != vn or avoided[1] != ve:  # a fence cuts the move or pushes the vehicle back
            vn, ve = avoided[0], avoided[1]
        elif stopped:
            vn = ve = 0.0
        self.vel = (vn, ve)
        self.target = (self.target[0] + vn * dt, self.target[1] + ve * dt)

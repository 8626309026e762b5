"""Thrust allocation: (U1..U4) -> motor speed commands, the inverse of the paper's mixer.

When motors saturate, roll and pitch are kept first (thrust is shifted to make room, then the
attitude demand is scaled only if even the full range cannot hold it), and yaw gets what is left.
"""
from __future__ import annotations

import math

from firefly.sim.airframe import Airframe
from firefly.sim.rotors import unmix


class Allocator:
    def __init__(self, airframe: Airframe):
        self.l = airframe.arm_length_m
        self.c = airframe.torque_ratio_c
        self.b = airframe.thrust_coeff_b
        self.f_max = airframe.max_rotor_thrust_n
        self.f_min = airframe.thrust_coeff_b * airframe.omega_idle_rad_s ** 2
        self.saturated = False

    def forces(self, u1: float, u2: float, u3: float, u4: float) -> tuple:
        f_min, f_max = self.f_min, self.f_max
        exact = unmix(u1, u2, u3, u4, self.l, self.c)
        if min(exact) >= f_min and max(exact) <= f_max:  # feasible: no priorities needed
            self.saturated = False
            return exact
        roll, pitch = u2 / (2.0 * self.l), u3 / (2.0 * self.l)
        rp = (pitch, roll, -pitch, -roll)
        base = u1 * 0.25
        lo, hi = min(rp), max(rp)
        span = hi - lo
        scale = 1.0
        if span > f_max - f_min:
            scale = (f_max - f_min) / span
            lo, hi = lo * scale, hi * scale
        base = min(max(base, f_min - lo), f_max - hi)
        f = [base + scale * x for x in rp]
        yaw = u4 / (4.0 * self.c)
        signs = (1.0, -1.0, 1.0, -1.0)
        # Largest |yaw| that keeps every motor in range.
        room = math.inf
        for fi, s in zip(f, signs):
            room = min(room, (f_max - fi) if s * yaw > 0 else (fi - f_min))
        yaw_used = math.copysign(min(abs(yaw), max(room, 0.0)), yaw)
        self.saturated = scale < 1.0 or yaw_used != yaw or base != u1 * 0.25
        return tuple(fi + s * yaw_used for fi, s in zip(f, signs))

    def omega_commands(self, u1: float, u2: float, u3: float, u4: float) -> tuple:
        b = self.b
        return tuple(math.sqrt(max(fi, 0.0) / b) for fi in self.forces(u1, u2, u3, u4))

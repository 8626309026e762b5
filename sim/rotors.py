"""Rotors: F = b*omega^2, first-order motor lag with saturation, and the paper's mixer (eq. 2).

A motor's speed scale (1 = healthy) multiplies its saturated command: a weak or failed motor
(fault injection) reaches only that fraction of the speed it is asked for, so it delivers the
square of it in thrust, and a scale of 0 stops it.

U1 = F1+F2+F3+F4, U2 = l(F2-F4), U3 = l(F1-F3), U4 = c(F1-F2+F3-F4).
"""
from __future__ import annotations

import math

from .airframe import Airframe


def motor_lag_factor(airframe: Airframe, dt: float) -> float:
    """Exact discretisation of d(omega)/dt = (cmd - omega)/tau over one step."""
    return 1.0 - math.exp(-dt / airframe.motor_time_constant_s)


HEALTHY = (1.0, 1.0, 1.0, 1.0)


def step_motors(omega: tuple, omega_cmd: tuple, lag: float, omega_max: float,
                speed_scale: tuple = HEALTHY) -> tuple:
    """Advance the four motor speeds toward their saturated commands times their speed scales."""
    o1, o2, o3, o4 = omega
    c1, c2, c3, c4 = (min(max(c, 0.0), omega_max) * s for c, s in zip(omega_cmd, speed_scale))
    return (o1 + (c1 - o1) * lag, o2 + (c2 - o2) * lag,
            o3 + (c3 - o3) * lag, o4 + (c4 - o4) * lag)


def rotor_forces(omega: tuple, b: float) -> tuple:
    return tuple(b * w * w for w in omega)


def mix_forces(forces: tuple, l: float, c: float) -> tuple:
    """Rotor forces -> (U1, U2, U3, U4)."""
    f1, f2, f3, f4 = forces
    return (f1 + f2 + f3 + f4, l * (f2 - f4), l * (f1 - f3), c * (f1 - f2 + f3 - f4))


def unmix(u1: float, u2: float, u3: float, u4: float, l: float, c: float) -> tuple:
    """(U1..U4) -> rotor forces, the exact inverse of mix_forces."""
    base = 0.25 * u1
    roll = u2 / (2.0 * l)
    pitch = u3 / (2.0 * l)
    yaw = u4 / (4.0 * c)
    return (base + pitch + yaw, base + roll - yaw, base - pitch + yaw, base - roll - yaw)


def shaft_power_per_thrust_1p5(airframe: Airframe, air_density: float = 1.225) -> float:
    """k in P = k * F^1.5: momentum-theory power of one rotor at thrust F (hover approximation)."""
    disk_area = math.pi * airframe.prop_radius_m ** 2
    return 1.0 / (math.sqrt(2.0 * air_density * disk_area) * airframe.figure_of_merit)


def rotor_shaft_power_w(force_n: float, airframe: Airframe, air_density: float = 1.225) -> float:
    if force_n <= 0.0:
        return 0.0
    return shaft_power_per_thrust_1p5(airframe, air_density) * force_n ** 1.5

"""An attitude target flown by body rates, as ArduCopter's input_rate_bf_roll_pitch_yaw flies ACRO
and FLIP: the target turns at the rates asked for, and the vehicle is asked for those rates plus
a correction towards the target. So a vehicle that lags catches up, and one asked for no rate
holds its attitude instead of drifting with the rate loop's error.

Quaternions are (w, x, y, z), body to NED, as the sim's BodyState holds them.
"""
from __future__ import annotations

import math

from firefly.sim.rigid_body import euler_from_quaternion

Quaternion = tuple[float, float, float, float]


def multiply(a: Quaternion, b: Quaternion) -> Quaternion:
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw)


def normalised(q: Quaternion) -> Quaternion:
    n = math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    return (q[0] / n, q[1] / n, q[2] / n, q[3] / n)


def rotation_vector(q: Quaternion) -> tuple[float, float, float]:
    """The rotation `q` makes, as axis times angle [rad], taking the short way round."""
    w, x, y, z = q if q[0] >= 0.0 else (-q[0], -q[1], -q[2], -q[3])
    s = math.sqrt(x * x + y * y + z * z)
    if s < 1e-12:
        return (2.0 * x, 2.0 * y, 2.0 * z)
    angle = 2.0 * math.atan2(s, w)
    return (x / s * angle, y / s * angle, z / s * angle)


def euler_rates_to_body(roll: float, pitch: float, rates: tuple[float, float, float]) -> tuple[float, float, float]:
    """Earth-frame Euler angle rates (roll, pitch, yaw rates) to body rates (p, q, r)."""
    roll_dot, pitch_dot, yaw_dot = rates
    sr, cr = math.sin(roll), math.cos(roll)
    sp, cp = math.sin(pitch), math.cos(pitch)
    return (roll_dot - sp * yaw_dot, cr * pitch_dot + sr * cp * yaw_dot, -sr * pitch_dot + cr * cp * yaw_dot)


class AttitudeTarget:
    """The attitude a rate-flown mode steers towards (reset to the vehicle's own attitude)."""

    def __init__(self) -> None:
        self.q: Quaternion = (1.0, 0.0, 0.0, 0.0)

    def reset(self, q: Quaternion) -> None:
        self.q = q

    def euler(self) -> tuple[float, float, float]:
        """The target as (roll, pitch, yaw) [rad]."""
        return euler_from_quaternion(*self.q)

    def rate_command(self, rates: tuple[float, float, float], actual: Quaternion, angle_p: tuple[float, float, float],
                     dt: float) -> tuple[float, float, float]:
        """Turn the target by body `rates` [rad/s] for dt; the body rates to ask of the vehicle
        (`actual`): the rates themselves plus angle_p (per axis) times the error to the target."""
        p, q, r = rates
        half = 0.5 * dt
        self.q = normalised(multiply(self.q, (1.0, p * half, q * half, r * half)))
        aw, ax, ay, az = actual
        ex, ey, ez = rotation_vector(multiply((aw, -ax, -ay, -az), self.q))
        return (p + angle_p[0] * ex, q + angle_p[1] * ey, r + angle_p[2] * ez)

"""An attitude target flown by body rates, as ArduCopter's input_rate_bf_roll_pitch_yaw flies ACRO
and FLIP: the target turns at the rates asked for, and the vehicle is asked for those rates plus
a correction towards the target. So a vehicle that lags catches up, and one asked for no rate
holds its attitude instead of drifting with the rate loop's error.

The rates asked for are shaped first, as ArduCopter shapes them: the target's own rate moves
towards them no faster than the axis may accelerate (ATC_ACCEL_R/P/Y_MAX), and with a time
constant if one is set (ACRO_RP_RATE_TC, ACRO_Y_RATE_TC / PILOT_Y_RATE_TC). A flip's 400 deg/s
takes about a third of a second to reach; a rate asked for at once would flip in 0.9 s, not
ArduCopter's 1.3.

Quaternions are (w, x, y, z), body to NED, as the sim's BodyState holds them.
"""
from __future__ import annotations

import math
from typing import NamedTuple

from firefly.sim.rigid_body import euler_from_quaternion

from ..params import ParamStore

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


def shaped_rate(rate: float, asked: float, accel_max: float, tc: float, dt: float) -> float:
    """One step of the target's rate towards the rate asked for: first-order with time constant
    tc (when positive; never past the rate asked for in a step), then at most accel_max [rad/s^2]
    (when positive) of change."""
    if tc > 0.0:
        change = (asked - rate) / max(tc, 0.01) * dt
        asked = rate + (change if abs(change) <= abs(asked - rate) else asked - rate)
    if accel_max > 0.0:
        step = accel_max * dt
        return min(max(asked, rate - step), rate + step)
    return asked


class RateShaping(NamedTuple):
    """Per body axis: the most angular acceleration [rad/s^2] and time constant [s] (0: none)."""
    accel_max: tuple[float, float, float]
    tc: tuple[float, float, float]


def rate_shaping(params: ParamStore, yaw_tc_param: str = "PILOT_Y_RATE_TC") -> RateShaping:
    """ArduCopter's shaping of body rates asked for by a pilot-flown mode; none without its
    rate feed-forward (ATC_RATE_FF_ENAB 0)."""
    if not params["ATC_RATE_FF_ENAB"]:
        return RateShaping((0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    rp_tc = params["ACRO_RP_RATE_TC"]
    return RateShaping((math.radians(params["ATC_ACCEL_R_MAX"] / 100.0), math.radians(params["ATC_ACCEL_P_MAX"] / 100.0),
                        math.radians(params["ATC_ACCEL_Y_MAX"] / 100.0)), (rp_tc, rp_tc, params[yaw_tc_param]))


class AttitudeTarget:
    """The attitude a rate-flown mode steers towards (reset to the vehicle's own attitude), and the
    body rate it turns at."""

    def __init__(self) -> None:
        self.q: Quaternion = (1.0, 0.0, 0.0, 0.0)
        self.rates: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def reset(self, q: Quaternion, rates: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> None:
        self.q = q
        self.rates = rates

    def euler(self) -> tuple[float, float, float]:
        """The target as (roll, pitch, yaw) [rad]."""
        return euler_from_quaternion(*self.q)

    def rate_command(self, rates: tuple[float, float, float], actual: Quaternion, angle_p: tuple[float, float, float],
                     dt: float, shaping: RateShaping | None = None) -> tuple[float, float, float]:
        """Turn the target by body `rates` [rad/s] (shaped, if given) for dt; the body rates to ask
        of the vehicle (`actual`): the target's rates plus angle_p (per axis) times the error to
        the target."""
        if shaping is not None:
            accel, tc, now = shaping.accel_max, shaping.tc, self.rates
            rates = (shaped_rate(now[0], rates[0], accel[0], tc[0], dt), shaped_rate(now[1], rates[1], accel[1], tc[1], dt),
                     shaped_rate(now[2], rates[2], accel[2], tc[2], dt))
        self.rates = rates
        p, q, r = rates
        half = 0.5 * dt
        self.q = normalised(multiply(self.q, (1.0, p * half, q * half, r * half)))
        aw, ax, ay, az = actual
        ex, ey, ez = rotation_vector(multiply((aw, -ax, -ay, -az), self.q))
        return (p + angle_p[0] * ex, q + angle_p[1] * ey, r + angle_p[2] * ez)

"""Jerk-limited kinematic shaping, as ArduPilot's AP_Math/control: a state (position, velocity,
acceleration) moved toward an input one tick at a time, its acceleration changing no faster
than the jerk limit, its velocity correction no faster than the acceleration limit allows to
stop. Used where ArduCopter shapes an estimate rather than a vehicle (the follow target).

Two-dimensional values are (north, east) tuples; everything is SI (m, m/s, m/s^2, rad).
"""
from __future__ import annotations

import math

CORNER_ACCELERATION_RATIO = 1.0 / math.sqrt(2.0)  # share of the acceleration a turn may take from the straight

Vec2 = tuple[float, float]


def sqrt_controller(error: float, p: float, second_order_limit: float, dt: float) -> float:
    """The correction rate for `error`: p*e near zero, sqrt(2*limit*|e|) beyond, and never more
    than would cross zero within dt."""
    if second_order_limit <= 0.0:
        rate = error * p
    elif p == 0.0:
        rate = math.copysign(math.sqrt(2.0 * second_order_limit * abs(error)), error) if error else 0.0
    else:
        linear = second_order_limit / (p * p)
        if abs(error) > linear:
            rate = math.copysign(math.sqrt(2.0 * second_order_limit * (abs(error) - linear / 2.0)), error)
        else:
            rate = error * p
    if dt > 0.0:
        bound = abs(error) / dt
        return max(-bound, min(bound, rate))
    return rate


def sqrt_controller_2d(error: Vec2, p: float, second_order_limit: float, dt: float) -> Vec2:
    """sqrt_controller on the error's length, along the error."""
    length = math.hypot(*error)
    if length <= 0.0:
        return 0.0, 0.0
    scale = sqrt_controller(length, p, second_order_limit, dt) / length
    return error[0] * scale, error[1] * scale


def limit_length(v: Vec2, limit: float) -> Vec2:
    length = math.hypot(*v)
    if limit > 0.0 and length > limit:
        return v[0] * limit / length, v[1] * limit / length
    return v


def shape_accel(accel_input: float, accel: float, jerk_max: float, dt: float) -> float:
    step = jerk_max * dt
    return accel + max(-step, min(step, accel_input - accel))


def shape_accel_2d(accel_input: Vec2, accel: Vec2, jerk_max: float, dt: float) -> Vec2:
    dn, de = limit_length((accel_input[0] - accel[0], accel_input[1] - accel[1]), jerk_max * dt)
    return accel[0] + dn, accel[1] + de


def shape_vel_accel(vel_input: float, accel_input: float, vel: float, accel: float, accel_min: float,
                    accel_max: float, jerk_max: float, dt: float) -> float:
    """The acceleration (jerk-limited) that brings `vel` to `vel_input`."""
    error = vel_input - vel
    kpa = jerk_max / accel_max if error > 0.0 else jerk_max / -accel_min
    target = sqrt_controller(error, kpa, jerk_max, dt)
    target = max(accel_min, min(accel_max, target)) + accel_input
    return shape_accel(target, accel, jerk_max, dt)


def shape_vel_accel_2d(vel_input: Vec2, accel_input: Vec2, vel: Vec2, accel: Vec2, accel_max: float,
                       jerk_max: float, dt: float) -> Vec2:
    """The horizontal acceleration that brings `vel` to `vel_input`: along the wanted velocity
    it may use what a turn leaves of accel_max."""
    error = (vel_input[0] - vel[0], vel_input[1] - vel[1])
    target = sqrt_controller_2d(error, jerk_max / accel_max, jerk_max, dt)
    speed = math.hypot(*vel_input)
    if speed <= 0.0:
        target = limit_length(target, accel_max)
    else:
        un, ue = vel_input[0] / speed, vel_input[1] / speed
        along = un * target[0] + ue * target[1]
        cross = (target[0] - un * along, target[1] - ue * along)
        if along * along <= cross[0] ** 2 + cross[1] ** 2:
            target = limit_length(target, accel_max)
        else:
            cross = limit_length(cross, CORNER_ACCELERATION_RATIO * accel_max)
            along_max = math.sqrt(max(0.0, accel_max * accel_max - cross[0] ** 2 - cross[1] ** 2))
            along = max(-along_max, min(along_max, along))
            target = (cross[0] + un * along, cross[1] + ue * along)
    target = (target[0] + accel_input[0], target[1] + accel_input[1])
    return shape_accel_2d(target, accel, jerk_max, dt)


def shape_pos_vel_accel(pos_input: float, vel_input: float, accel_input: float, pos: float, vel: float,
                        accel: float, vel_min: float, vel_max: float, accel_min: float, accel_max: float,
                        jerk_max: float, dt: float) -> float:
    """The acceleration that brings the state (pos, vel) onto the input's along one axis. The
    approach brakes at half the limit on the side it brakes with, so a target far away is met
    without overshoot; the correcting speed stays within vel_min..vel_max, then vel_input adds."""
    error = pos_input - pos
    brake = -accel_min if error > 0.0 else accel_max
    correction = sqrt_controller(error, 0.5 * jerk_max / brake, 0.5 * brake, dt)
    correction = max(vel_min, min(vel_max, correction))
    return shape_vel_accel(correction + vel_input, accel_input, vel, accel, accel_min, accel_max, jerk_max, dt)


def shape_pos_vel_accel_2d(pos_input: Vec2, vel_input: Vec2, accel_input: Vec2, pos: Vec2, vel: Vec2,
                           accel: Vec2, accel_max: float, jerk_max: float, dt: float, vel_max: float = 0.0) -> Vec2:
    """The horizontal acceleration that brings the state (pos, vel) onto the input's; the speed
    it corrects the position at is at most vel_max (0: no limit), on top of vel_input."""
    error = (pos_input[0] - pos[0], pos_input[1] - pos[1])
    correction = limit_length(sqrt_controller_2d(error, 0.5 * jerk_max / accel_max, 0.5 * accel_max, dt), vel_max)
    vel_target = (correction[0] + vel_input[0], correction[1] + vel_input[1])
    return shape_vel_accel_2d(vel_target, accel_input, vel, accel, accel_max, jerk_max, dt)


def wrap_pi(angle: float) -> float:
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


def shape_angle_vel_accel(angle_input: float, rate_input: float, angle: float, rate: float, accel: float,
                          accel_max: float, jerk_max: float, dt: float) -> float:
    """The angular acceleration that turns `angle` (moving at `rate`) onto the input the short
    way round, allowing for where the present rate carries it before it can stop."""
    coast = rate * abs(rate / accel_max)
    error = wrap_pi(angle_input - angle - coast) + coast
    rate_target = sqrt_controller(error, 0.5 * jerk_max / accel_max, 0.5 * accel_max, dt) + rate_input
    return shape_vel_accel(rate_target, 0.0, rate, accel, -accel_max, accel_max, jerk_max, dt)


def advance_2d(pos: Vec2, vel: Vec2, accel: Vec2, dt: float) -> tuple[Vec2, Vec2]:
    """Position and velocity moved on by dt at constant acceleration."""
    half = 0.5 * dt * dt
    return ((pos[0] + vel[0] * dt + accel[0] * half, pos[1] + vel[1] * dt + accel[1] * half),
            (vel[0] + accel[0] * dt, vel[1] + accel[1] * dt))

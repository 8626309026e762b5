"""A spline leg as ArduCopter flies NAV_SPLINE_WAYPOINT (its SplineCurve): a cubic Hermite curve
from an origin to a destination, leaving along one vector and arriving along another.

The vectors are not speeds but directions with a length (ArduCopter passes the chords of the legs
around: the leg that came in, the one that follows); when together they are longer than four
times the leg, both are scaled down so the curve does not overshoot. The target moves along the
curve at the speed the limits allow: the speed limits along its direction, half the acceleration
limit across it (the curve's bend caps the speed), half the acceleration limit along it to speed
up or slow down, and the speed from which it can still stop (or slow to the speed the next leg
starts with) by the destination. Positions are NED metres; the curve's parameter runs 0 to 1.
"""
from __future__ import annotations

import math

from .scurve import kinematic_limit

SPLINE_FACTOR = 4.0  # how long the end vectors may be, in legs, before they are scaled down
TANGENTIAL_ACCEL_SCALER = 0.5  # the share of the acceleration limit used along the track
LATERAL_ACCEL_SCALER = 0.5  # ... and across it

Vec = tuple[float, float, float]


def _norm(v: Vec) -> float:
    return math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])


def _unit(v: Vec) -> Vec:
    n = _norm(v)
    return (v[0] / n, v[1] / n, v[2] / n) if n > 0 else (0.0, 0.0, 0.0)


def _sum(*terms: tuple[float, Vec]) -> Vec:
    """The sum of coefficient * vector over the terms."""
    n = e = d = 0.0
    for k, v in terms:
        n, e, d = n + k * v[0], e + k * v[1], d + k * v[2]
    return n, e, d


def _limit(direction: Vec, horizontal: float, up: float, down: float) -> float:
    """The kinematic limit along a direction of any length (0 for none)."""
    if _norm(direction) == 0 or horizontal == 0 or up == 0 or down == 0:
        return 0.0
    return kinematic_limit(_unit(direction), horizontal, up, down)


class SplineLeg:
    __slots__ = ("origin", "destination", "origin_vec", "destination_vec", "speed_xy", "speed_up", "speed_down",
                 "accel_xy", "accel_z", "time", "reached", "origin_speed_max", "destination_speed_max",
                 "_zero_length", "_h")

    def __init__(self, origin: Vec, destination: Vec, origin_vec: Vec, destination_vec: Vec,
                 speed_xy: float, speed_up: float, speed_down: float, accel_xy: float, accel_z: float) -> None:
        self.origin, self.destination = origin, destination
        self.speed_xy, self.speed_up, self.speed_down = abs(speed_xy), abs(speed_up), abs(speed_down)
        self.accel_xy, self.accel_z = abs(accel_xy), abs(accel_z)
        chord = (destination[0] - origin[0], destination[1] - origin[1], destination[2] - origin[2])
        self._zero_length = _norm(chord) == 0
        self.time, self.reached = 0.0, False
        self.origin_speed_max = self.destination_speed_max = 0.0
        self._h: tuple[Vec, Vec, Vec, Vec] = (destination, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
        if self._zero_length:
            self.time, self.reached = 1.0, True
            self.origin_vec = self.destination_vec = (0.0, 0.0, 0.0)
            return
        self.origin_vec, self.destination_vec = origin_vec, destination_vec
        ends = _norm(origin_vec) + _norm(destination_vec)
        room = _norm(chord) * SPLINE_FACTOR
        k = room / ends if ends > room else 1.0
        v0 = (origin_vec[0] * k, origin_vec[1] * k, origin_vec[2] * k)
        v1 = (destination_vec[0] * k, destination_vec[1] * k, destination_vec[2] * k)
        o, d = origin, destination
        self._h = (o, v0, _sum((-3.0, o), (-2.0, v0), (3.0, d), (-1.0, v1)),
                   _sum((2.0, o), (1.0, v0), (-2.0, d), (1.0, v1)))
        # Through the destination (a vector to leave along): as fast as the bend there allows.
        # ArduCopter sets it from the next leg's start (or keeps the last leg's); the curves
        # join smoothly, so the bend's own limit is the same figure.
        self.destination_speed_max = math.inf if _norm(destination_vec) > 0 else 0.0
        self.origin_speed_max = self._step(0.0, 0.0)[3]
        if self.destination_speed_max:
            self.destination_speed_max = self._step(1.0, 0.0)[3]

    @property
    def exit_vec(self) -> Vec:
        """The vector the curve leaves its destination along (the next spline's origin vector)."""
        return self.destination_vec

    def _at(self, t: float) -> tuple[Vec, Vec, Vec, Vec]:
        """Position, and its first three derivatives by the parameter, at t."""
        h0, h1, h2, h3 = self._h
        t2 = t * t
        return (_sum((1.0, h0), (t, h1), (t2, h2), (t2 * t, h3)), _sum((1.0, h1), (2.0 * t, h2), (3.0 * t2, h3)),
                _sum((2.0, h2), (6.0 * t, h3)), _sum((6.0, h3)))

    def _step(self, t: float, distance: float) -> tuple[float, Vec, Vec, float, float]:
        """(the parameter step covering `distance`, the position at t, the unit direction there,
        the speed allowed, the acceleration allowed along the track)."""
        pos, vel, acc, jerk = self._at(t)
        speed_len = _norm(vel)
        if speed_len == 0:
            if _norm(acc) == 0:
                if _norm(jerk) == 0:
                    return 0.0, pos, (0.0, 0.0, 0.0), 0.0, 0.0
                direction = _unit(jerk)
                dt = (6.0 * distance / _norm(jerk)) ** (1.0 / 3.0)
            else:
                direction = _unit(acc)
                dt = math.sqrt(max(2.0 * distance / _norm(acc), 0.0))
        else:
            direction = _unit(vel)
            dt = distance / speed_len
        along = acc[0] * direction[0] + acc[1] * direction[1] + acc[2] * direction[2]
        across = (acc[0] - direction[0] * along, acc[1] - direction[1] * along, acc[2] - direction[2] * along)
        across_len = _norm(across)
        speed_limit = _limit(direction, self.speed_xy, self.speed_up, self.speed_down)
        across_max = LATERAL_ACCEL_SCALER * _limit(across, self.accel_xy, self.accel_z, self.accel_z)
        if speed_limit == 0:
            return dt, pos, direction, 0.0, 0.0
        if (across_max > 0 and across_len > 0 and speed_len > 0
                and across_len / across_max > (speed_len / speed_limit) ** 2):
            speed_max = speed_len / math.sqrt(across_len / across_max)
        else:
            speed_max = speed_limit
        accel_max = TANGENTIAL_ACCEL_SCALER * _limit(direction, self.accel_xy, self.accel_z, self.accel_z)
        if accel_max == 0:
            return dt, pos, direction, 0.0, 0.0
        d = self.destination
        left = math.sqrt((d[0] - pos[0]) ** 2 + (d[1] - pos[1]) ** 2 + (d[2] - pos[2]) ** 2)
        speed_max = min(speed_max, math.sqrt(max(2.0 * accel_max * left + self.destination_speed_max ** 2, 0.0)))
        return dt, pos, direction, speed_max, accel_max

    def advance(self, dt: float, speed: float) -> tuple[Vec, Vec]:
        """Move the target on by dt seconds from its present speed; (position, velocity)."""
        if self._zero_length:
            return self.destination, (0.0, 0.0, 0.0)
        step, pos, direction, speed_max, accel_max = self._step(self.time, speed * dt)
        if accel_max == 0:  # no way along (a zero limit): ArduCopter calls the leg done
            self.time, self.reached = 1.0, True
            return pos, (0.0, 0.0, 0.0)
        speed = min(max(speed_max, speed - accel_max * dt), speed + accel_max * dt)
        self.time += step
        if self.time >= 1.0:
            self.time, self.reached = 1.0, True
        return pos, (direction[0] * speed, direction[1] * speed, direction[2] * speed)

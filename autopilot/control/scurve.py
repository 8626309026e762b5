"""One straight leg flown with a jerk-limited ("S-curve") speed profile.

The profile along the leg has seven phases: jerk up, constant acceleration, jerk down (reaching
the cruise speed), cruise, and the mirror image of the first three to stop at the destination.
A leg may also start or end moving (ArduCopter's set_origin_speed_max / set_destination_speed_max:
a spline before or after it): then its first or last three phases change speed from or to that
one, the cruise speed being the one the leg reaches from rest in half its length.
Acceleration is continuous, jerk is bounded by the jerk limit, acceleration by the acceleration
limit and speed by the speed limit; a leg too short to reach the cruise speed peaks lower.
ArduCopter shapes its jerk ramps with a raised cosine (a snap limit); the constant-jerk phases
used here keep every phase a cubic polynomial, which is all a tick has to evaluate.

Everything is computed once when the leg is made: each phase is stored as its start time and its
starting distance, speed, acceleration and (constant) jerk. `at(t)` evaluates one cubic.
"""
from __future__ import annotations

import math

CHANGE_SEARCH_STEPS = 20  # halvings finding the speed a change short of room reaches

def kinematic_limit(unit: tuple, horizontal: float, up: float, down: float) -> float:
    """The largest magnitude along the unit vector `unit` (north, east, down) whose horizontal
    part stays within `horizontal` and whose vertical part within `up` (climbing) or `down`."""
    h = math.sqrt(unit[0] * unit[0] + unit[1] * unit[1])
    v = unit[2]
    limit = math.inf
    if h > 1e-9:
        limit = horizontal / h
    if v < -1e-9:
        limit = min(limit, up / -v)
    elif v > 1e-9:
        limit = min(limit, down / v)
    return limit if math.isfinite(limit) else horizontal


def _ramp(speed: float, accel: float, jerk: float) -> tuple[float, float, float]:
    """(peak acceleration, jerk time, constant-acceleration time) of the phases taking the speed
    from 0 to `speed` within the acceleration and jerk limits."""
    if speed <= 0.0:
        return 0.0, 0.0, 0.0
    peak = min(accel, math.sqrt(speed * jerk))
    t_jerk = peak / jerk
    return peak, t_jerk, max(0.0, speed / peak - t_jerk)


def _ramp_distance(speed: float, accel: float, jerk: float) -> float:
    """Distance covered while speeding up from 0 to `speed` (half the time at half the speed, as
    the speed rises symmetrically about its midpoint)."""
    if speed <= 0.0:
        return 0.0
    _, t_jerk, t_const = _ramp(speed, accel, jerk)
    return speed * (2.0 * t_jerk + t_const) / 2.0


def peak_speed(length: float, speed: float, accel: float, jerk: float) -> float:
    """The highest speed a leg of `length` can reach and still stop at its end."""
    if 2.0 * _ramp_distance(speed, accel, jerk) <= length:
        return speed
    # Too short: the ramps up and down meet. Peak acceleration sqrt(v*j) if below the limit ...
    v = (length / 2.0 * math.sqrt(jerk)) ** (2.0 / 3.0)
    if math.sqrt(v * jerk) <= accel:
        return v
    # ... else v * (a/j + v/a) = length.
    b = accel / jerk
    return accel / 2.0 * (-b + math.sqrt(b * b + 4.0 * length / accel))


class SCurve:
    """A leg from `origin` to `destination` (local NED metres): position, velocity and
    acceleration along it at any time since its start. A zero-length leg is finished at once."""

    __slots__ = ("origin", "destination", "unit", "length", "speed_max", "accel_max", "jerk",
                 "peak", "_starts", "_phases", "duration", "accel_end", "decel_start", "speed_start",
                 "speed_end")

    def __init__(self, origin: tuple, destination: tuple, speed_xy: float, speed_up: float,
                 speed_down: float, accel_xy: float, accel_z: float, jerk: float):
        self.origin = origin
        self.destination = destination
        dn, de, dd = (destination[0] - origin[0], destination[1] - origin[1], destination[2] - origin[2])
        self.length = math.sqrt(dn * dn + de * de + dd * dd)
        self._starts: list[float] = [0.0]
        self._phases: list[tuple] = [(0.0, 0.0, 0.0, 0.0)]
        self.duration = self.accel_end = self.decel_start = 0.0
        self.peak = self.speed_start = self.speed_end = 0.0
        if self.length < 1e-6 or min(speed_xy, accel_xy, jerk) <= 0.0:
            self.unit = (0.0, 0.0, 0.0)
            self.speed_max = self.accel_max = self.jerk = 0.0
            return
        self.unit = (dn / self.length, de / self.length, dd / self.length)
        self.speed_max = kinematic_limit(self.unit, speed_xy, speed_up, speed_down)
        self.accel_max = kinematic_limit(self.unit, accel_xy, accel_z, accel_z)
        self.jerk = jerk
        self._build()

    def _build(self) -> None:
        """Plan the leg between its start and end speeds, cruising at the speed it reaches from
        rest in half its length (so either end speed, no faster, fits in the other half)."""
        a_lim, j = self.accel_max, self.jerk
        v = self.peak = peak_speed(self.length, self.speed_max, a_lim, j)
        v0 = self.speed_start = min(self.speed_start, v)
        v1 = self.speed_end = min(self.speed_end, v)
        _, up_j, up_a = _ramp(v - v0, a_lim, j)
        _, down_j, down_a = _ramp(v - v1, a_lim, j)
        cruise = max(0.0, (self.length - self._change_distance(v0, v) - self._change_distance(v, v1)) / v)
        # (duration, jerk) of the seven phases; cruise is the fourth.
        plan = ((up_j, j), (up_a, 0.0), (up_j, -j), (cruise, 0.0), (down_j, -j), (down_a, 0.0), (down_j, j))
        self._starts, self._phases = [], []
        t = self.duration = self._append(plan, 0.0, 0.0, v0)
        self.accel_end = 2.0 * up_j + up_a
        self.decel_start = t - 2.0 * down_j - down_a

    def set_origin_speed(self, speed: float) -> float:
        """Start the leg moving at `speed` (ArduCopter's SCurve::set_origin_speed_max, for a leg
        after a spline); the speed it starts with: no faster than its cruise speed, 0 if it has
        no length."""
        if self.length < 1e-6 or self.speed_max <= 0.0:
            return 0.0
        self.speed_start = max(speed, 0.0)
        self._build()
        return self.speed_start

    def set_destination_speed(self, speed: float) -> None:
        """End the leg moving at `speed` (ArduCopter's SCurve::set_destination_speed_max, for a
        leg before a spline), no faster than its cruise speed."""
        if self.length < 1e-6 or self.speed_max <= 0.0:
            return
        self.speed_end = max(speed, 0.0)
        self._build()

    def set_speed_max(self, speed_xy: float, speed_up: float, speed_down: float, t: float,
                      change_jerk_time: float) -> None:
        """A new speed limit for a leg flown `t` seconds (ArduCopter's SCurve::set_speed_max): a
        leg not yet begun is planned again; one begun changes speed where it cruises, from the end
        of its acceleration or from now, if its cruise lasts over 12 `change_jerk_time`s at the old
        speed (no room: it keeps its plan, as a short leg does); one slowing down keeps its plan."""
        if self.length < 1e-6:
            return
        new = kinematic_limit(self.unit, speed_xy, speed_up, speed_down)
        if new <= 0.0 or new == self.speed_max:
            return
        self.speed_max = new
        if t <= 0.0:
            self._build()
            return
        if t >= self.decel_start:
            return
        t0 = max(t, self.accel_end)
        s0, v0, _ = self.along(t0)
        v_end = self.speed_end
        cruise_s = self.length - self._change_distance(v0, v_end) - s0
        if v0 <= 0.0 or cruise_s <= 0.0 or cruise_s / v0 <= 12.0 * change_jerk_time:
            return
        target = new if new < v0 else min(new, cruise_s / (12.0 * change_jerk_time))
        # The change takes at most half the cruise left (as ArduCopter sizes it): short of room,
        # the speed goes part of the way.
        if self._change_distance(v0, target) > cruise_s * 0.5:
            reached, missed = v0, target
            for _ in range(CHANGE_SEARCH_STEPS):
                middle = (reached + missed) / 2.0
                if self._change_distance(v0, middle) <= cruise_s * 0.5:
                    reached = middle
                else:
                    missed = middle
            target = reached
        if abs(target - v0) < 1e-3:
            return
        _, t_j, t_a = _ramp(abs(target - v0), self.accel_max, self.jerk)
        left = self.length - s0 - self._change_distance(v0, target) - self._change_distance(target, v_end)
        if left < 0.0:
            return  # no room to change and still stop at the end: the plan stands
        sign = 1.0 if target > v0 else -1.0
        _, d_j, d_a = _ramp(max(target - v_end, 0.0), self.accel_max, self.jerk)
        plan = ((t_j, sign * self.jerk), (t_a, 0.0), (t_j, -sign * self.jerk), (left / target, 0.0),
                (d_j, -self.jerk), (d_a, 0.0), (d_j, self.jerk))
        self._replan_from(t0, plan)

    def _change_distance(self, v0: float, v1: float) -> float:
        """Distance covered changing speed from v0 to v1 within the leg's limits."""
        _, t_j, t_a = _ramp(abs(v1 - v0), self.accel_max, self.jerk)
        return (2.0 * t_j + t_a) * (v0 + v1) / 2.0

    def _replan_from(self, t0: float, plan: tuple) -> None:
        """Keep the phases up to t0 (where the acceleration is zero), then fly `plan`."""
        s, v, _ = self.along(t0)
        kept = [i for i, start in enumerate(self._starts) if start < t0]
        self._starts = [self._starts[i] for i in kept]
        self._phases = [self._phases[i] for i in kept]
        t = self.duration = self._append(plan, t0, s, v)
        self.decel_start = t - sum(d for d, _ in plan[4:])

    def _append(self, plan: tuple, t: float, s: float, v: float) -> float:
        """Add `plan`'s (duration, jerk) phases from time t at distance s and speed v (and no
        acceleration); the time they end."""
        a = 0.0
        for duration, jerk in plan:
            if duration <= 0.0:
                continue
            self._starts.append(t)
            self._phases.append((s, v, a, jerk))
            s += duration * (v + duration * (a / 2.0 + duration * jerk / 6.0))
            v += duration * (a + duration * jerk / 2.0)
            a += duration * jerk
            t += duration
        return t

    def along(self, t: float) -> tuple[float, float, float]:
        """(distance, speed, acceleration) along the leg at time t since its start; before the
        start it is at the origin, after the end at the destination, moving at the leg's start and
        end speeds (0 unless set)."""
        if t >= self.duration:
            return self.length, self.speed_end, 0.0
        if t <= 0.0:
            return 0.0, self.speed_start, 0.0
        starts = self._starts
        i = len(starts) - 1
        while starts[i] > t:
            i -= 1
        s, v, a, j = self._phases[i]
        dt = t - starts[i]
        return (s + dt * (v + dt * (a / 2.0 + dt * j / 6.0)),
                v + dt * (a + dt * j / 2.0),
                a + dt * j)

    def target(self, t: float) -> tuple[tuple, tuple, tuple]:
        """(position, velocity, acceleration) NED vectors at time t since the leg's start."""
        s, v, a = self.along(t)
        u, o = self.unit, self.origin
        return ((o[0] + u[0] * s, o[1] + u[1] * s, o[2] + u[2] * s),
                (u[0] * v, u[1] * v, u[2] * v), (u[0] * a, u[1] * a, u[2] * a))

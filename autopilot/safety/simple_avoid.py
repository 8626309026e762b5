"""Simple avoidance against the geofence, as ArduCopter's AC_Avoid (AVOID_ENABLE bit 0): a velocity
the pilot (LOITER) or a companion (GUIDED velocity targets) asks for is cut so that the vehicle can
stop FENCE_MARGIN inside every enabled fence; AVOID_BEHAVE 0 slides along the boundary, 1 stops
short of it. A vehicle already inside the margin is pushed back out at up to AVOID_BACKUP_SPD, and
a climb or descent slows to stop FENCE_MARGIN short of FENCE_ALT_MAX / FENCE_ALT_MIN (the climb
rate of ALT_HOLD, LOITER, POSHOLD and CIRCLE too), backing off at up to AVOID_BACKZ_SPD.

Fences only slow a vehicle down at 1 m/s/s (AC_AVOID_ACCEL_CMSS_MAX) whatever the mode's own
acceleration, and the change avoidance makes to the wanted velocity is itself limited to
AVOID_ACCEL_MAX. ArduCopter's odd corner is kept: the circle fence pushes back only while a
velocity is asked for (a loiter's drift is one).

Everything is in SI units (m, m/s, m/s/s) in the local frame, north-east-up for velocities; the
shapes are fence_shapes.py's.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

from firefly.autopilot.control.position import stopping_distance as _pos_stopping_distance
from firefly.autopilot.control.shaping import sqrt_controller

from .fence_shapes import Shape, closest_point, point_in_polygon, segment_intersection
from .fence_switch import ALT_MAX, ALT_MIN, CIRCLE, POLYGON

if TYPE_CHECKING:
    from ..params import ParamStore

STOP_AT_FENCE, USE_PROXIMITY = 1, 2  # AVOID_ENABLE bits (AC_AVOID_STOP_AT_FENCE, _USE_PROXIMITY_SENSOR)
SLIDE, STOP = 0, 1  # AVOID_BEHAVE
FENCE_ACCEL_MAX = 1.0  # AC_AVOID_ACCEL_CMSS_MAX [m/s/s]
LOOK_PAST_M = 0.02  # AC_Avoid looks 2 cm past the stopping point so that it reaches the boundary
ACCEL_TIMEOUT_S = 0.2  # AC_AVOID_ACCEL_TIMEOUT_MS: a limit this old starts the change from scratch
ACTIVE_TIMEOUT_S = 0.5  # AC_AVOID_ACTIVE_LIMIT_TIMEOUT_MS
LEAN_SHARE_MAX = 0.75  # AC_AVOID_ANGLE_MAX_PERCENT: the push leaves the pilot a quarter of the lean

Vec2 = tuple[float, float]


def max_speed(kp: float, accel: float, distance: float, dt: float) -> float:
    """The speed from which the vehicle stops in `distance` (AC_Avoid::get_max_speed)."""
    if kp == 0.0:
        return math.sqrt(max(2.0 * distance * accel, 0.0))
    return sqrt_controller(distance, kp, accel, dt)


def stopping_distance(kp: float, accel: float, speed: float) -> float:
    if accel <= 0.0 or speed == 0.0:
        return 0.0
    return _pos_stopping_distance(speed, kp, accel)


def _circle_segment_intersection(start: Vec2, end: Vec2, radius: float) -> Vec2 | None:
    """Where the segment start-end first crosses a circle about the origin."""
    dx, dy = end[0] - start[0], end[1] - start[1]
    a = dx * dx + dy * dy
    b = 2.0 * (dx * start[0] + dy * start[1])
    c = start[0] * start[0] + start[1] * start[1] - radius * radius
    if a == 0.0:
        return None
    delta = b * b - 4.0 * a * c
    if delta < 0.0:
        return None
    root = math.sqrt(delta)
    for t in ((-b + root) / (2.0 * a), (-b - root) / (2.0 * a)):
        if 0.0 <= t <= 1.0:
            return start[0] + dx * t, start[1] + dy * t
    return None


class Quadrants:
    """The largest push back in each quadrant, summed (find_max_quadrant_velocity): two pushes the
    same way count once, opposite ones add up. ArduCopter's test is strict, so a push exactly along
    an axis falls in no quadrant; its float32 sums of measured positions practically never make
    one, where Firefly's exact ones do (a vehicle square to a wall, its heading exactly north), so
    here a zero component counts as positive and such a push is kept, as it is in practice there."""
    __slots__ = ("q",)

    def __init__(self) -> None:
        self.q = [0.0] * 8

    def add(self, x: float, y: float) -> None:
        q = self.q
        if x == 0.0 and y == 0.0:
            return
        if x >= 0.0 and y >= 0.0:
            q[0], q[1] = max(q[0], x), max(q[1], y)
        elif x < 0.0 <= y:
            q[2], q[3] = min(q[2], x), max(q[3], y)
        elif x < 0.0 and y < 0.0:
            q[4], q[5] = min(q[4], x), min(q[5], y)
        else:
            q[6], q[7] = max(q[6], x), min(q[7], y)

    def total(self) -> Vec2:
        q = self.q
        return q[0] + q[2] + q[4] + q[6], q[1] + q[3] + q[5] + q[7]


def _back_away(quads: Quadrants, kp: float, accel: float, breach: float, toward: Vec2, dt: float) -> None:
    """Away from a boundary `breach` metres inside the margin, `toward` pointing at it
    (calc_backup_velocity_2D): 40 % of the acceleration."""
    length = math.hypot(*toward)
    if length == 0.0:
        return
    speed = max_speed(kp, 0.4 * accel, abs(breach), dt)
    quads.add(-toward[0] / length * speed, -toward[1] / length * speed)


def _limit_along(kp: float, accel: float, vel: Vec2, direction: Vec2, distance: float, dt: float) -> Vec2:
    """The velocity's part along the unit `direction` cut to what stops in `distance`."""
    top = max_speed(kp, accel, distance, dt)
    speed = vel[0] * direction[0] + vel[1] * direction[1]
    if speed > top:
        return vel[0] + direction[0] * (top - speed), vel[1] + direction[1] * (top - speed)
    return vel


class FenceGeometry:
    """What avoidance reads of the vehicle, its fences and its proximity sensor (obstacles in the
    body frame, forward and right, and the room above), gathered once per call."""
    __slots__ = ("position_ne", "home_ne", "height_above_home_m", "enabled_fences", "shapes", "margin_m",
                 "radius_m", "alt_max_m", "alt_min_m", "obstacles", "yaw_rad", "upward_m")

    def __init__(self, position_ne: Vec2, home_ne: Vec2, height_above_home_m: float, enabled_fences: int,
                 shapes: Sequence[Shape], params: ParamStore, obstacles: Sequence[Vec2] = (), yaw_rad: float = 0.0,
                 upward_m: float | None = None):
        self.obstacles = obstacles
        self.yaw_rad = yaw_rad
        self.upward_m = upward_m
        self.position_ne = position_ne
        self.home_ne = home_ne
        self.height_above_home_m = height_above_home_m
        self.enabled_fences = enabled_fences
        self.shapes = shapes
        self.margin_m = params["FENCE_MARGIN"]
        self.radius_m = params["FENCE_RADIUS"]
        self.alt_max_m = params["FENCE_ALT_MAX"]
        self.alt_min_m = params["FENCE_ALT_MIN"]


class SimpleAvoid:
    __slots__ = ("params", "_prev_vel", "_last_limit_s")

    def __init__(self, params: ParamStore):
        self.params = params
        self._prev_vel = (0.0, 0.0, 0.0)
        self._last_limit_s = -math.inf

    def wanted(self, enabled_fences: int, proximity: bool = False) -> bool:
        """Whether avoidance has anything to do: a fence on and AVOID_ENABLE's fence bit, or a
        proximity sensor with data and its bit."""
        enabled = int(self.params["AVOID_ENABLE"])
        return bool(enabled_fences and enabled & STOP_AT_FENCE or proximity and enabled & USE_PROXIMITY)

    def limits_active(self, now_s: float) -> bool:
        return now_s - self._last_limit_s < ACTIVE_TIMEOUT_S

    # ----- the whole adjustment ------------------------------------------------------------------
    def adjust_velocity(self, g: FenceGeometry, vel: tuple[float, float, float], kp: float, accel: float,
                        kp_z: float, accel_z: float, now_s: float, dt: float) -> tuple[float, float, float]:
        """The velocity (north, east, up) cut to stay inside the fences (AC_Avoid::adjust_velocity)."""
        p = self.params
        if int(p["AVOID_ENABLE"]) == 0:
            return vel
        original = vel
        quads = Quadrants()
        back_up = back_down = 0.0
        if g.obstacles:
            vel, (bn, be, bu) = self._proximity(g, vel, kp, min(accel, FENCE_ACCEL_MAX), dt)
            quads.add(bn, be)
            back_up, back_down = max(bu, 0.0), min(bu, 0.0)
        vn, ve, vu = vel
        fence_quads = Quadrants()
        accel_l = min(accel, FENCE_ACCEL_MAX)
        if int(p["AVOID_ENABLE"]) & STOP_AT_FENCE:
            behave = int(p["AVOID_BEHAVE"])
            for adjust in (self._circle_fence, self._polygons, self._inclusion_circles, self._exclusion_circles):
                (vn, ve), back = adjust(g, (vn, ve), kp, accel_l, behave, dt)
                fence_quads.add(*back)
        vu, back_z = self.adjust_climb(g, vu, kp_z, accel_z, dt)
        quads.add(*fence_quads.total())
        back_n, back_e = quads.total()
        back_u = max(back_up, back_z, 0.0) + min(back_down, back_z, 0.0)  # the largest up plus the largest down
        limit_xy = p["AVOID_BACKUP_SPD"]
        if (back_n or back_e) and limit_xy > 0.0:
            length = math.hypot(back_n, back_e)
            if length > limit_xy:
                back_n, back_e = back_n * limit_xy / length, back_e * limit_xy / length
            if back_n:
                vn = max(vn, back_n) if back_n > 0.0 else min(vn, back_n)
            if back_e:
                ve = max(ve, back_e) if back_e > 0.0 else min(ve, back_e)
        limit_z = p["AVOID_BACKZ_SPD"]
        if back_u and limit_z > 0.0:
            back_u = max(-limit_z, min(limit_z, back_u))
            vu = max(vu, back_u) if back_u > 0.0 else min(vu, back_u)
        adjusted = self._limit_accel(original, (vn, ve, vu), now_s, dt)
        if adjusted != original:
            self._last_limit_s = now_s
        return adjusted

    def _limit_accel(self, original: tuple[float, float, float], adjusted: tuple[float, float, float],
                     now_s: float, dt: float) -> tuple[float, float, float]:
        """The change avoidance makes, at most AVOID_ACCEL_MAX (AC_Avoid::limit_accel)."""
        accel_max = self.params["AVOID_ACCEL_MAX"]
        if original == adjusted or accel_max == 0.0 or dt <= 0.0:
            return adjusted
        if now_s - self._last_limit_s > ACCEL_TIMEOUT_S:
            self._prev_vel = original
        prev = self._prev_vel
        an, ae, au = ((adjusted[i] - prev[i]) / dt for i in range(3))
        size = math.sqrt(an * an + ae * ae + au * au)
        if size > accel_max:
            k = accel_max * dt / size
            adjusted = (prev[0] + an * k, prev[1] + ae * k, prev[2] + au * k)
        self._prev_vel = adjusted
        return adjusted

    # ----- the vertical fences --------------------------------------------------------------------
    def adjust_climb(self, g: FenceGeometry, climb: float, kp_z: float, accel_z: float,
                     dt: float) -> tuple[float, float]:
        """The climb rate cut to stop short of the altitude fences, and the rate that backs off
        one already crossed (AC_Avoid::adjust_velocity_z): (climb, push back)."""
        p = self.params
        enabled = int(p["AVOID_ENABLE"])
        if enabled == 0 or climb == 0.0:
            return climb, 0.0
        accel = min(accel_z, FENCE_ACCEL_MAX)
        above_max = above_min = None  # metres below the safe ceiling, above the safe floor
        if enabled & STOP_AT_FENCE:
            if g.enabled_fences & ALT_MIN:
                above_min = g.height_above_home_m - (g.alt_min_m + g.margin_m)
            if g.enabled_fences & ALT_MAX:
                above_max = (g.alt_max_m - g.margin_m) - g.height_above_home_m
        if g.upward_m is not None and enabled & USE_PROXIMITY:  # the room above, less AVOID_MARGIN
            room = g.upward_m - p["AVOID_MARGIN"]
            if above_max is None or room < above_max:
                above_max = room
        limit_z = p["AVOID_BACKZ_SPD"]
        if above_max is not None and above_max <= 0.0:
            back = max(-max_speed(kp_z, accel, -above_max, dt), -limit_z) if limit_z > 0.0 else 0.0
            return min(climb, 0.0), back
        if above_min is not None and above_min <= 0.0:
            back = min(max_speed(kp_z, accel, -above_min, dt), limit_z) if limit_z > 0.0 else 0.0
            return max(climb, 0.0), back
        if above_max is not None:
            climb = min(max_speed(kp_z, accel, above_max, dt), climb)
        if above_min is not None:
            climb = max(-max_speed(kp_z, accel, above_min, dt), climb)
        return climb, 0.0

    def adjust_climb_rate(self, g: FenceGeometry, climb: float, kp_z: float, accel_z: float, dt: float) -> float:
        """The pilot's climb rate with the push back folded in (Mode::get_avoidance_adjusted_climbrate)."""
        climb, back = self.adjust_climb(g, climb, kp_z, accel_z, dt)
        if back < 0.0:
            return min(climb, back)
        if back > 0.0:
            return max(climb, back)
        return climb

    # ----- the proximity sensor ---------------------------------------------------------------------
    def adjust_lean(self, objects: Sequence[tuple[float, float]], lean: tuple[float, float],
                    angle_max_rad: float) -> tuple[float, float]:
        """ALT_HOLD's lean (roll, pitch) with a push away from what the sensor sees within
        AVOID_DIST_MAX, the nearer the harder, up to AVOID_ANGLE_MAX and never more than 75 % of
        the vehicle's limit, so the pilot can still override (adjust_roll_pitch_rad)."""
        p = self.params
        dist_max, avoid_max = p["AVOID_DIST_MAX"], math.radians(p["AVOID_ANGLE_MAX"] / 100.0)
        if avoid_max <= 0.0 or angle_max_rad <= 0.0 or dist_max <= 0.0:
            return lean
        roll_hi = roll_lo = pitch_hi = pitch_lo = 0.0
        for angle_deg, distance in objects:
            if not 0.0 <= distance < dist_max:
                continue
            share = 1.0 - distance / dist_max
            roll, pitch = -math.sin(math.radians(angle_deg)) * share, math.cos(math.radians(angle_deg)) * share
            roll_hi, roll_lo = max(roll_hi, roll), min(roll_lo, roll)
            pitch_hi, pitch_lo = max(pitch_hi, pitch), min(pitch_lo, pitch)
        push = ((roll_hi + roll_lo) * math.pi / 4.0, (pitch_hi + pitch_lo) * math.pi / 4.0)
        if push == (0.0, 0.0):
            return lean
        limit = max(0.0, min(avoid_max, angle_max_rad * LEAN_SHARE_MAX))
        size = math.hypot(*push)
        if size > limit:
            push = (push[0] * limit / size, push[1] * limit / size)
        out = (push[0] + lean[0], push[1] + lean[1])
        size = math.hypot(*out)
        if size > angle_max_rad:
            out = (out[0] * angle_max_rad / size, out[1] * angle_max_rad / size)
        return out

    def _proximity(self, g: FenceGeometry, vel: tuple[float, float, float], kp: float, accel: float,
                   dt: float) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
        """Keep AVOID_MARGIN from each obstacle the sensor reports (adjust_velocity_proximity): the
        velocity turned into the body frame, its part toward each obstacle cut to what stops at the
        margin (AVOID_BEHAVE's stop is flown as the slide here), and a push back from one closer
        than the margin by more than AVOID_BACKUP_DZ. Obstacles are level (the middle layer), so
        the climb is left alone."""
        p = self.params
        c, s = math.cos(g.yaw_rad), math.sin(g.yaw_rad)
        vn, ve, vu = vel
        safe = (vn * c + ve * s, -vn * s + ve * c)
        moving = vn != 0.0 or ve != 0.0 or vu != 0.0
        margin = max(p["AVOID_MARGIN"], 0.0)
        deadzone = max(0.0, p["AVOID_BACKUP_DZ"])
        speed3 = math.sqrt(vn * vn + ve * ve + vu * vu)
        margin_xy = margin * math.hypot(*safe) / speed3 if moving else 0.0
        quads = Quadrants()
        for ob in g.obstacles:
            distance = math.hypot(*ob)
            if distance == 0.0:
                continue
            if distance - margin < 0.0 and margin - distance > deadzone:
                _back_away(quads, kp, accel, margin - distance, ob, dt)
            if moving:
                safe = _limit_along(kp, accel, safe, (ob[0] / distance, ob[1] / distance),
                                    max(distance - margin_xy, 0.0), dt)
        bf, br = quads.total()
        back = (bf * c - br * s, bf * s + br * c, 0.0)
        return (safe[0] * c - safe[1] * s, safe[0] * s + safe[1] * c, vu), back

    # ----- the horizontal fences ------------------------------------------------------------------
    @staticmethod
    def _circle_fence(g: FenceGeometry, vel: Vec2, kp: float, accel: float, behave: int,
                      dt: float) -> tuple[Vec2, Vec2]:
        """FENCE_RADIUS about home (adjust_velocity_circle_fence)."""
        speed = math.hypot(*vel)
        if not g.enabled_fences & CIRCLE or speed == 0.0:
            return vel, (0.0, 0.0)
        pos = (g.position_ne[0] - g.home_ne[0], g.position_ne[1] - g.home_ne[1])
        return _inclusion_circle(pos, vel, speed, g.radius_m, g.margin_m, kp, accel, behave, dt, True)

    @staticmethod
    def _inclusion_circles(g: FenceGeometry, vel: Vec2, kp: float, accel: float, behave: int,
                           dt: float) -> tuple[Vec2, Vec2]:
        if not g.enabled_fences & POLYGON:
            return vel, (0.0, 0.0)
        quads = Quadrants()
        speed = math.hypot(*vel)
        for shape in g.shapes:
            if shape.kind != "circle" or not shape.inclusion:
                continue
            cn, ce, radius = shape.circle
            pos = (g.position_ne[0] - cn, g.position_ne[1] - ce)
            if pos[0] * pos[0] + pos[1] * pos[1] > radius * radius:
                continue  # outside this one: it does not limit
            if radius - g.margin_m < 0.0:
                return vel, (0.0, 0.0)  # as AC_Avoid: the pushes so far are dropped
            vel, back = _inclusion_circle(pos, vel, speed, radius, g.margin_m, kp, accel, behave, dt, False)
            quads.add(*back)
            if vel == (0.0, 0.0) and behave == STOP and speed:
                break  # stopped inside the margin: the rest are not looked at
        return vel, quads.total()

    @staticmethod
    def _exclusion_circles(g: FenceGeometry, vel: Vec2, kp: float, accel: float, behave: int,
                           dt: float) -> tuple[Vec2, Vec2]:
        if not g.enabled_fences & POLYGON:
            return vel, (0.0, 0.0)
        quads = Quadrants()
        margin = g.margin_m
        speed = math.hypot(*vel)
        ahead = (0.0, 0.0)
        if speed and behave == STOP:
            k = (LOOK_PAST_M + margin + stopping_distance(kp, accel, speed)) / speed
            ahead = (vel[0] * k, vel[1] * k)
        for shape in g.shapes:
            if shape.kind != "circle" or shape.inclusion:
                continue
            cn, ce, radius = shape.circle
            if radius < margin:
                return vel, (0.0, 0.0)  # as AC_Avoid: the pushes so far are dropped
            pos = (g.position_ne[0] - cn, g.position_ne[1] - ce)
            dist = math.hypot(*pos)
            if dist < radius:
                continue  # inside it already: it does not limit
            to_centre = (-pos[0], -pos[1])
            to_boundary = dist - radius
            if to_boundary - margin < 0.0:
                _back_away(quads, kp, accel, margin - to_boundary, to_centre, dt)
            if speed == 0.0:
                continue
            if behave == SLIDE:
                if dist == 0.0 or to_boundary <= 0.0:
                    continue
                unit = (to_centre[0] / dist, to_centre[1] / dist)
                vel = _limit_along(kp, accel, vel, unit, max(to_boundary - margin, 0.0), dt)
            elif dist < radius + margin:
                end = (pos[0] + ahead[0], pos[1] + ahead[1])
                if math.hypot(*end) <= dist:
                    return (0.0, 0.0), quads.total()
            else:
                vel = _slowed_before_circle(pos, (pos[0] + ahead[0], pos[1] + ahead[1]), radius + margin, vel, speed,
                                            kp, accel, dt)
        return vel, quads.total()

    @staticmethod
    def _polygons(g: FenceGeometry, vel: Vec2, kp: float, accel: float, behave: int,
                  dt: float) -> tuple[Vec2, Vec2]:
        """Inclusion polygons, then exclusion ones (adjust_velocity_inclusion_and_exclusion_polygons)."""
        if not g.enabled_fences & POLYGON:
            return vel, (0.0, 0.0)
        quads = Quadrants()
        for inclusion in (True, False):
            for shape in g.shapes:
                if shape.kind == "poly" and shape.inclusion == inclusion:
                    vel, back = _polygon(g.position_ne, vel, shape.vertices, g.margin_m, kp, accel, behave, dt,
                                         inclusion)
                    quads.add(*back)
        return vel, quads.total()


def _inclusion_circle(pos: Vec2, vel: Vec2, speed: float, radius: float, margin: float, kp: float, accel: float,
                      behave: int, dt: float, is_fence_radius: bool) -> tuple[Vec2, Vec2]:
    """Stay `margin` inside a circle about the origin, `pos` from its centre: the velocity and the
    push back (the circle fence and inclusion circles share this)."""
    if is_fence_radius and margin > radius:
        return vel, (0.0, 0.0)
    dist = math.hypot(*pos)
    if is_fence_radius and dist > radius:
        return vel, (0.0, 0.0)  # outside the fence: nothing to adjust
    quads = Quadrants()
    safe_radius = radius - margin
    if dist - safe_radius > 0.0:
        _back_away(quads, kp, accel, dist - safe_radius, pos, dt)
    back = quads.total()
    if speed == 0.0:
        return vel, back
    stop = stopping_distance(kp, accel, speed)
    if behave == SLIDE:
        k = stop / speed
        point = (pos[0] + vel[0] * k, pos[1] + vel[1] * k)
        point_dist = math.hypot(*point)
        if point_dist == 0.0 or point_dist <= safe_radius:
            return vel, back
        scale = safe_radius / point_dist
        toward = (point[0] * scale - pos[0], point[1] * scale - pos[1])
        distance = math.hypot(*toward)
        if distance > 0.0:
            top = min(speed, max_speed(kp, accel, distance, dt))
            vel = (toward[0] * top / distance, toward[1] * top / distance)
        return vel, back
    k = (LOOK_PAST_M + margin + stop) / speed
    end = (pos[0] + vel[0] * k, pos[1] + vel[1] * k)
    if dist >= safe_radius:
        if math.hypot(*end) >= dist:
            return (0.0, 0.0), back  # further out: stop; a move back in is left alone
        return vel, back
    return _slowed_before_circle(pos, end, safe_radius, vel, speed, kp, accel, dt), back


def _slowed_before_circle(pos: Vec2, end: Vec2, radius: float, vel: Vec2, speed: float, kp: float, accel: float,
                          dt: float) -> Vec2:
    """The velocity, its direction kept, slow enough to stop where pos-end crosses the circle."""
    hit = _circle_segment_intersection(pos, end, radius)
    if hit is not None:
        top = max_speed(kp, accel, math.hypot(hit[0] - pos[0], hit[1] - pos[1]), dt)
        if top < speed:
            k = max(top, 0.0) / speed
            return vel[0] * k, vel[1] * k
    return vel


def _polygon(pos: Vec2, vel: Vec2, vertices: Sequence[Vec2], margin: float, kp: float, accel: float, behave: int,
             dt: float, stay_inside: bool) -> tuple[Vec2, Vec2]:
    """Stay `margin` from each edge of a polygon, inside or out (adjust_velocity_polygon)."""
    if not vertices or point_in_polygon(pos, vertices) != stay_inside:
        return vel, (0.0, 0.0)  # on the wrong side already: a breach, not avoidance's
    margin = max(margin, 0.0)
    safe = vel
    speed = math.hypot(*vel)
    end = pos
    if speed:
        k = (LOOK_PAST_M + margin + stopping_distance(kp, accel, speed)) / speed
        end = (pos[0] + vel[0] * k, pos[1] + vel[1] * k)
    quads = Quadrants()
    count = len(vertices)
    for i in range(count):
        start, finish = vertices[(i + 1) % count], vertices[i]
        near = closest_point(pos, start, finish)
        to_edge = (near[0] - pos[0], near[1] - pos[1])
        distance = math.hypot(*to_edge)
        if distance - margin < 0.0:
            _back_away(quads, kp, accel, margin - distance, to_edge, dt)
        if not speed:
            continue
        if behave == SLIDE:
            if distance == 0.0:
                return vel, (0.0, 0.0)  # exactly on the edge: a breach
            safe = _limit_along(kp, accel, safe, (to_edge[0] / distance, to_edge[1] / distance),
                                max(distance - margin, 0.0), dt)
        else:
            hit = segment_intersection(pos, end, start, finish)
            if hit is None:
                continue
            toward = (hit[0] - pos[0], hit[1] - pos[1])
            reach = math.hypot(*toward)
            if reach == 0.0:
                return vel, (0.0, 0.0)
            if reach <= margin:
                safe = (0.0, 0.0)
            else:
                safe = _limit_along(kp, accel, safe, (toward[0] / reach, toward[1] / reach), reach - margin, dt)
    return safe, quads.total()

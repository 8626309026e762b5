"""ArduCopter's BendyRuler path planner (OA_TYPE 1, AP_OABendyRuler): once a plan, it looks for a
bearing (OA_BR_TYPE 1, horizontal) or a climb (2, vertical) to fly that keeps clear of the fence,
and answers the point to fly to, or that no avoidance is needed (the way straight to the
destination is clear).

Margins: a segment's margin is how much further from every obstacle it stays (negative: closer,
or across it), the least over
- each obstacle of the database (obstacle_database.py): its distance from the segment (in 3D, the
  horizontal search's at the vehicle's height) less its radius; with OA_TYPE 3 these alone;
and, further than FENCE_MARGIN:
- the circle round home (FENCE_TYPE bit 2): FENCE_RADIUS - FENCE_MARGIN less the further end's
  distance from home;
- with the polygon fence on (FENCE_TYPE bit 4): each polygon's closest distance to the segment
  (outside an inclusion polygon or inside an exclusion one, negative); a segment that crosses a
  polygon's edge gets minus the distance from its end to the crossing nearest its start. The
  closest distance skips each polygon's closing edge (last vertex to first), as ArduPilot's
  Polygon_closest_distance_line does for the unclosed polygons the fence holds;
- each exclusion circle: the segment's distance to its centre less (radius + FENCE_MARGIN); each
  inclusion circle (radius + FENCE_MARGIN) less the further end's distance from its centre.
The vertical search also keeps below FENCE_ALT_MAX (FENCE_TYPE bit 1): FENCE_ALT_MAX -
FENCE_MARGIN less the higher end's height above home. A segment is clear when its margin is more
than OA_MARGIN_MAX. No obstacle at all: an infinite margin.

The search (search_xy_path): bearings from the one to the destination (rounded to 0.01 degree)
out to 170 degrees either side in 5 degree steps, the left one (-) of each pair first. A bearing
whose step 1 (from here, the look-ahead long: the present look-ahead, at most 2 m past the
destination) is clear is a candidate; the first candidate whose step 2 (from step 1's end towards
the destination, and 45 degrees either side of that, the look-ahead long but at least 2 m and at
most the distance left) is clear too is taken, unless it turns more than OA_BR_CONT_ANGLE from
the bearing taken before and is less than OA_BR_CONT_RATIO times better than that one still is
(the previous bearing is kept then). Taken straight towards the destination with step 2 straight
too: no avoidance needed. Failing that, the candidate nearest the ground course (the heading
below 0.2 m/s), or failing any, the bearing of the best margin, flown at the look-ahead shortened
by a negative margin. The look-ahead (OA_BR_LOOKAHEAD) starts at half and grows by 10 % a clear
plan (5 % a candidate's), shrinking by 10 % when none, within half and all of it.

The vertical search (search_vertical_path) tries pitches 0 (towards the destination), up, down
and 180 (away) in that order, each the look-ahead long; the first clear one whose step 2 (from its
end: level towards the destination, up, down or away) is clear too is taken; failing that the
first clear one, or failing any the best. Whatever is taken is flown as far as the destination is
(horizontally) away: straight up by that much, or to the destination itself; only pitch 0 with a
level step 2 clear needs no avoidance.

Everything is in metres and degrees (bearings from north, clockwise) in the local (north, east)
frame, heights up.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from ..safety.fence_shapes import Shape, closest_point, point_in_polygon, segment_intersection
from .obstacle_database import Obstacle

Vec2 = tuple[float, float]
Vec3 = tuple[float, float, float]  # north, east, up

BEARING_STEP_DEG = 5  # OA_BENDYRULER_BEARING_INC_XY
BEARING_SPAN_DEG = 170  # searched either side of the bearing to the destination
STEP2_BEARINGS_DEG = (0.0, 45.0, -45.0)
STEP2_MIN_M = 2.0  # OA_BENDYRULER_LOOKAHEAD_STEP2_MIN
PAST_DESTINATION_M = 2.0  # OA_BENDYRULER_LOOKAHEAD_PAST_DEST
LOW_SPEED_M_S = 0.2  # below it the heading stands for the ground course
ALT_MAX_FENCE, CIRCLE_FENCE, POLYGON_FENCE = 1, 2, 4  # FENCE_TYPE bits
VERTICAL_PITCHES_DEG = (0.0, 90.0, -90.0, 180.0)  # step 1's in the order searched, and step 2's
NO_BEARING = math.inf  # no bearing taken before


def wrap_180(angle: float) -> float:
    angle = math.fmod(angle, 360.0)
    if angle > 180.0:
        angle -= 360.0
    elif angle <= -180.0:
        angle += 360.0
    return angle


def bearing_deg(a: Vec2, b: Vec2) -> float:
    """From a to b, 0-360 degrees, rounded to 0.01 degree as Location::get_bearing_to's centidegrees."""
    bearing = math.degrees(math.atan2(b[1] - a[1], b[0] - a[0])) % 360.0
    return int(bearing * 100.0 + 0.5) * 0.01


def offset(p: Vec2, bearing: float, distance: float) -> Vec2:
    rad = math.radians(bearing)
    return p[0] + math.cos(rad) * distance, p[1] + math.sin(rad) * distance


def offset_pitched(p: Vec3, bearing: float, pitch: float, distance: float) -> Vec3:
    """Location::offset_bearing_and_pitch: `distance` along a bearing, pitched up (+) or down."""
    level = math.cos(math.radians(pitch)) * distance
    n, e = offset((p[0], p[1]), bearing, level)
    return n, e, p[2] + math.sin(math.radians(pitch)) * distance


def _segment_point(a: Vec2, b: Vec2, p: Vec2) -> float:
    near = closest_point(p, a, b)
    return math.hypot(near[0] - p[0], near[1] - p[1])


def _segments(a1: Vec2, a2: Vec2, b1: Vec2, b2: Vec2) -> float:
    """Vector2::closest_distance_between_lines: the nearest of the four ends to the other segment."""
    return min(_segment_point(b1, b2, a1), _segment_point(b1, b2, a2),
               _segment_point(a1, a2, b1), _segment_point(a1, a2, b2))


def _segment_point_3d(a: Vec3, b: Vec3, p: Vec3) -> float:
    d = (b[0] - a[0], b[1] - a[1], b[2] - a[2])
    span = d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
    t = 0.0 if span == 0.0 else ((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1] + (p[2] - a[2]) * d[2]) / span
    t = min(max(t, 0.0), 1.0)
    return math.dist(p, (a[0] + d[0] * t, a[1] + d[1] * t, a[2] + d[2] * t))


def polygon_line_distance(vertices: Sequence[Vec2], start: Vec2, end: Vec2) -> float:
    """Polygon_closest_distance_line: minus the distance from `end` to the crossing nearest
    `start` when the segment crosses an edge, else the closest distance to the edges but the
    closing one."""
    crossing, nearest = None, math.inf
    count = len(vertices)
    for i in range(count):
        point = segment_intersection(vertices[i], vertices[(i + 1) % count], start, end)
        if point is not None:
            d = math.hypot(point[0] - start[0], point[1] - start[1])
            if d < nearest:
                crossing, nearest = point, d
    if crossing is not None:
        return -math.hypot(crossing[0] - end[0], crossing[1] - end[1])
    return min((_segments(vertices[i], vertices[i + 1], start, end) for i in range(count - 1)), default=math.inf)


@dataclass(frozen=True)
class FenceView:
    """What BendyRuler sees of the fence: the shapes, the fences on, the circle round home."""
    shapes: Sequence[Shape]
    enabled_fences: int
    radius: float  # FENCE_RADIUS
    fence_margin: float  # FENCE_MARGIN
    home: Vec2 = (0.0, 0.0)
    alt_max: float = 100.0  # FENCE_ALT_MAX, above home
    home_up: float = 0.0
    obstacles: Sequence[Obstacle] | None = None  # the obstacle database's (None: no database)
    up: float = 0.0  # the height of the horizontal search's segments (the vehicle's)
    proximity_only: bool = False  # the database alone (OA_TYPE 3's BendyRuler while Dijkstra flies)

    def margin_3d(self, start: Vec3, end: Vec3) -> float:
        """The vertical search's margin: margin()'s, and below FENCE_ALT_MAX less FENCE_MARGIN."""
        return self._margin(start, end, True)

    def margin(self, start: Vec2, end: Vec2) -> float:
        """calc_avoidance_margin: the least margin of the segment from every obstacle (inf: none)."""
        return self._margin((start[0], start[1], self.up), (end[0], end[1], self.up), False)

    def _database_margin(self, start: Vec3, end: Vec3) -> float:
        """The segment's distance from each database obstacle less its radius, the least."""
        if not self.obstacles or start == end:
            return math.inf
        return min(_segment_point_3d(start, end, o.pos) - o.radius for o in self.obstacles)

    def _margin(self, start3: Vec3, end3: Vec3, vertical: bool) -> float:
        least = self._database_margin(start3, end3)
        if self.proximity_only:
            return least
        start, end = (start3[0], start3[1]), (end3[0], end3[1])
        if self.enabled_fences & CIRCLE_FENCE:
            far = max(math.dist(self.home, start), math.dist(self.home, end))
            least = min(least, self.radius - self.fence_margin - far)
        if vertical and self.enabled_fences & ALT_MAX_FENCE:
            highest = max(start3[2], end3[2]) - self.home_up
            least = min(least, self.alt_max - self.fence_margin - highest)
        if not self.enabled_fences & POLYGON_FENCE:
            return least
        for shape in self.shapes:
            if shape.kind == "poly":
                outside = not point_in_polygon(start, shape.vertices)
                sign = (-1.0 if outside else 1.0) if shape.inclusion else (1.0 if outside else -1.0)
                least = min(least, sign * polygon_line_distance(shape.vertices, start, end) - self.fence_margin)
            else:
                n, e, radius = shape.circle
                if shape.inclusion:
                    far = max(math.dist((n, e), start), math.dist((n, e), end))
                    least = min(least, radius + self.fence_margin - far)
                else:
                    least = min(least, _segment_point(start, end, (n, e)) - (radius + self.fence_margin))
        return least


@dataclass(frozen=True)
class Settings:
    lookahead: float  # OA_BR_LOOKAHEAD
    ratio: float  # OA_BR_CONT_RATIO
    angle: float  # OA_BR_CONT_ANGLE
    margin_max: float  # OA_MARGIN_MAX


class BendyRuler:
    """AP_OABendyRuler's state between plans: the look-ahead, the bearing taken and for where."""

    def __init__(self) -> None:
        self.current_lookahead = 0.0
        self.bearing_prev = NO_BEARING
        self.destination_prev: Vec2 | None = None

    def update(self, here: Vec2, destination: Vec2, ground_velocity: Vec2, heading_deg: float, fence: FenceView,
               settings: Settings) -> tuple[bool, Vec2]:
        """(avoiding, the point to fly to now); not avoiding: the way to the destination is clear."""
        lookahead = max(settings.lookahead, 1.0) if math.isfinite(settings.lookahead) else 1.0
        self.current_lookahead = min(max(self.current_lookahead, lookahead * 0.5), lookahead)
        to_dest = bearing_deg(here, destination)
        distance = math.dist(here, destination)
        step1 = min(self.current_lookahead, distance + PAST_DESTINATION_M)
        step2 = self.current_lookahead
        if math.hypot(*ground_velocity) < LOW_SPEED_M_S:
            course = heading_deg
        else:
            course = math.degrees(math.atan2(ground_velocity[1], ground_velocity[0]))
        margin_max = settings.margin_max
        best_bearing, best_bearing_margin, have_best = to_dest, -math.inf, False
        best_margin, best_margin_bearing = -math.inf, to_dest
        for i in range(BEARING_SPAN_DEG // BEARING_STEP_DEG + 1):
            for sign in ((-1.0,) if i == 0 else (-1.0, 1.0)):
                test_bearing = wrap_180(to_dest + sign * i * BEARING_STEP_DEG)
                test = offset(here, test_bearing, step1)
                margin = fence.margin(here, test)
                if margin > best_margin:
                    best_margin_bearing, best_margin = test_bearing, margin
                if margin <= margin_max:
                    continue
                if not have_best or abs(wrap_180(course - test_bearing)) < abs(wrap_180(course - best_bearing)):
                    best_bearing, best_bearing_margin, have_best = test_bearing, margin, True
                to_dest2 = bearing_deg(test, destination)
                distance2 = min(max(step2, STEP2_MIN_M), math.dist(test, destination))
                for j, turn in enumerate(STEP2_BEARINGS_DEG):
                    test2 = offset(test, wrap_180(to_dest2 + turn), distance2)
                    if fence.margin(test, test2) > margin_max:
                        active = i != 0 or j != 0
                        final = self._resist(destination, here, active, test_bearing, step1, margin, fence,
                                             settings)
                        point = offset(here, final, min(distance, step1))
                        self.current_lookahead = min(lookahead, self.current_lookahead * 1.1)
                        return active, point
        if have_best:  # none clear two steps ahead: the one clear one step ahead nearest the course
            chosen, reach = best_bearing, max(step1 + min(best_bearing_margin, 0.0), 0.0)
            self.current_lookahead = min(lookahead, self.current_lookahead * 1.05)
        else:  # none clear at all: the best of them
            chosen, reach = best_margin_bearing, max(step1 + min(best_margin, 0.0), 0.0)
            self.current_lookahead = max(lookahead * 0.5, self.current_lookahead * 0.9)
        return True, offset(here, chosen, reach)

    def update_vertical(self, here: Vec3, destination: Vec2, fence: FenceView,
                        settings: Settings) -> tuple[bool, Vec3]:
        """search_vertical_path: (avoiding, the point to fly to now, with its height)."""
        lookahead = max(settings.lookahead, 1.0) if math.isfinite(settings.lookahead) else 1.0
        self.current_lookahead = min(max(self.current_lookahead, lookahead * 0.5), lookahead)
        flat = (here[0], here[1])
        to_dest = bearing_deg(flat, destination)
        distance = math.dist(flat, destination)
        step1 = min(self.current_lookahead, distance + PAST_DESTINATION_M)
        step2 = self.current_lookahead
        margin_max = settings.margin_max
        best_pitch, have_best = 0.0, False
        best_margin, best_margin_pitch = -math.inf, 0.0
        for pitch in VERTICAL_PITCHES_DEG:
            test = offset_pitched(here, to_dest, pitch, step1)
            margin = fence.margin_3d(here, test)
            if margin > best_margin:
                best_margin_pitch, best_margin = pitch, margin
            if margin <= margin_max:
                continue
            if not have_best:
                best_pitch, have_best = pitch, True
            to_dest2 = to_dest if abs(pitch) == 90.0 else bearing_deg((test[0], test[1]), destination)
            distance2 = min(max(step2, STEP2_MIN_M), math.dist((test[0], test[1]), destination))
            for j, pitch2 in enumerate(VERTICAL_PITCHES_DEG):
                if fence.margin_3d(test, offset_pitched(test, to_dest2, pitch2, distance2)) > margin_max:
                    # (ArduCopter would stay active for proximity obstacles beside the way on: none here)
                    self.current_lookahead = min(lookahead, self.current_lookahead * 1.1)
                    return pitch != 0.0 or j != 0, offset_pitched(here, to_dest, pitch, distance)
        if have_best:
            chosen = best_pitch
            self.current_lookahead = min(lookahead, self.current_lookahead * 1.05)
        else:
            chosen = best_margin_pitch
            self.current_lookahead = max(lookahead * 0.5, self.current_lookahead * 0.9)
        return True, offset_pitched(here, to_dest, chosen, distance)

    def _resist(self, destination: Vec2, here: Vec2, active: bool, bearing: float, step1: float, margin: float,
                fence: FenceView, settings: Settings) -> float:
        """resist_bearing_change: the bearing to fly, the previous one kept when the new turns
        more than OA_BR_CONT_ANGLE from it without OA_BR_CONT_RATIO times the margin."""
        changed_destination = self.destination_prev is None or math.dist(destination, self.destination_prev) > 0.01
        if changed_destination:
            self.destination_prev = destination
        if active and not changed_destination and settings.ratio > 0.0:
            previous = self.bearing_prev
            if previous != NO_BEARING and abs(wrap_180(previous - bearing)) > settings.angle:
                previous_margin = fence.margin(here, offset(here, wrap_180(previous), step1))
                if margin < settings.ratio * previous_margin:
                    return previous  # kept: bearing_prev stays
        else:
            self.bearing_prev = NO_BEARING
        self.bearing_prev = bearing
        return bearing

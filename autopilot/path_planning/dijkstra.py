"""The geometry of ArduCopter's Dijkstra path planner (OA_TYPE 2): the shortest way round the
fence, as a list of corners, or the reason there is none.

The corners a path may turn at are the fence's own, pushed out by the margin (OA_MARGIN_MAX):
- a polygon's corner moves the margin along the bisector of its two edges, away from the inside of
  an exclusion polygon and into an inclusion polygon; a corner pointing the other way (a notch)
  gets none, as a path never turns there. The margin is measured along the bisector, so past a
  square's corner the path keeps only margin/sqrt(2) from each edge (measured: 3.5 m beside a
  square with OA_MARGIN_MAX 5);
- an exclusion circle becomes a hexagon of corners at bearings 30, 90, ... 330 degrees, far enough
  out that its sides keep (radius + margin) from the centre;
- an inclusion circle gets no corners; it only forbids leaving it.
Two points see each other when the segment between them crosses no edge of the fence's polygons
(a touch counts), keeps more than the radius from each exclusion circle's centre and stays inside
every inclusion circle: the fence itself, not the margin, is what a leg must not cross.

The search is A* (Dijkstra's with the straight-line distance still to go added), over the source,
the destination and the corners in that order, inclusion polygons' corners first, then exclusion
polygons', then circles': of equally good nodes the first in that order is taken, as ArduCopter's
is, so a fence that offers two equal ways goes the way its first corners lie.

Everything is in metres in the local (north, east) frame; no input makes it raise.
"""
from __future__ import annotations

import math
from collections.abc import Sequence

from ..safety.fence_shapes import Shape, closest_point, point_in_polygon, segment_intersection

Vec2 = tuple[float, float]

OVERLAPPING_POINTS = "overlapping polygon points"  # a corner on top of its neighbour
OVERLAPPING_LINES = "overlapping polygon lines"  # no side of a corner is outside (inside) the polygon
TOO_MANY_POINTS = "too many fence points"
NO_PATH = "could not find path"
POINTS_MAX = 254  # corners ArduCopter's planner handles (its node indexes are bytes, 255 = none)
CIRCLE_BEARINGS_DEG = (30.0, 90.0, 150.0, 210.0, 270.0, 330.0)
# The hexagon's corners lie this much further out than its sides (1 / cos 30 degrees).
CIRCLE_SIDE_SCALE = 1.0 / math.cos(math.radians(180.0 / len(CIRCLE_BEARINGS_DEG)))


class PlanError(ValueError):
    """The fence gives no corners to plan with, or no path: the words ArduCopter puts after
    "Dijkstra: "."""


def _unit(dn: float, de: float) -> Vec2 | None:
    length = math.hypot(dn, de)
    return (dn / length, de / length) if length > 0.0 and math.isfinite(length) else None


def _wrap_pi(angle: float) -> float:
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


def _polygon_corners(vertices: Sequence[Vec2], margin: float, inclusion: bool) -> list[Vec2]:
    """One polygon's corners pushed `margin` out of it (an exclusion polygon) or into it (an
    inclusion polygon); PlanError for corners on top of each other or a polygon whose edges cross."""
    count, corners = len(vertices), []
    for j in range(count):
        here, before, after = vertices[j], vertices[j - 1], vertices[(j + 1) % count]
        to_before = (before[0] - here[0], before[1] - here[1])
        to_after = (after[0] - here[0], after[1] - here[1])
        if to_before == (0.0, 0.0) or to_after == (0.0, 0.0) or to_before == to_after:
            raise PlanError(OVERLAPPING_POINTS)
        u_before, u_after = _unit(*to_before), _unit(*to_after)
        if u_before is None or u_after is None:
            continue  # a corner too far out to have a direction: no node
        bisector = _unit(u_before[0] + u_after[0], u_before[1] + u_after[1])
        if bisector is None:
            continue  # a straight run through the vertex: nothing to turn round
        push = (bisector[0] * margin, bisector[1] * margin)
        point = (here[0] + push[0], here[1] + push[1])
        if point_in_polygon(point, vertices) != inclusion:  # on the wrong side: the other way
            push = (-push[0], -push[1])
            point = (here[0] + push[0], here[1] + push[1])
            if point_in_polygon(point, vertices) != inclusion:
                raise PlanError(OVERLAPPING_LINES)
        angle = math.atan2(push[1], push[0]) - math.atan2(u_before[1], u_before[0])
        if abs(_wrap_pi(angle)) < math.pi / 2.0:
            continue  # a notch: a path never turns there
        corners.append(point)
    return corners


def _circle_corners(circle: tuple[float, float, float], margin: float) -> list[Vec2]:
    n, e, radius = circle
    reach = (radius + margin) * CIRCLE_SIDE_SCALE
    return [(n + math.cos(math.radians(b)) * reach, e + math.sin(math.radians(b)) * reach)
            for b in CIRCLE_BEARINGS_DEG]


def fence_corners(shapes: Sequence[Shape], margin: float) -> list[Vec2]:
    """The corners a path may turn at, in ArduCopter's order (see the module's doc); a negative
    margin counts as none. PlanError when a polygon gives none, or too many."""
    margin = max(margin, 0.0) if math.isfinite(margin) else 0.0
    corners: list[Vec2] = []
    for inclusion in (True, False):
        for shape in shapes:
            if shape.kind == "poly" and shape.inclusion == inclusion:
                corners.extend(_polygon_corners(shape.vertices, margin, inclusion))
    for shape in shapes:
        if shape.kind == "circle" and not shape.inclusion:
            corners.extend(_circle_corners(shape.circle, margin))
    if len(corners) > POINTS_MAX:
        raise PlanError(TOO_MANY_POINTS)
    return corners


def crosses_fence(shapes: Sequence[Shape], a: Vec2, b: Vec2) -> bool:
    """Whether the segment a-b crosses the fence (AP_OADijkstra::intersects_fence)."""
    for shape in shapes:
        if shape.kind == "poly":
            vertices = shape.vertices
            for i in range(len(vertices)):
                if segment_intersection(vertices[i], vertices[(i + 1) % len(vertices)], a, b) is not None:
                    return True
            continue
        n, e, radius = shape.circle
        if shape.inclusion:
            if math.hypot(a[0] - n, a[1] - e) > radius or math.hypot(b[0] - n, b[1] - e) > radius:
                return True
        else:
            near = closest_point((n, e), a, b)
            if math.hypot(near[0] - n, near[1] - e) <= radius:
                return True
    return False


class FenceGraph:
    """The corners of a fence and which of them see each other, built once per fence."""

    def __init__(self, shapes: Sequence[Shape], margin: float):
        """PlanError (fence_corners') when the fence gives no corners to plan with."""
        self.shapes = tuple(shapes)
        self.corners = fence_corners(self.shapes, margin)
        count = len(self.corners)
        # corner index -> [(other corner index, distance)], in index order
        self.seen: list[list[tuple[int, float]]] = [[] for _ in range(count)]
        for i in range(count - 1):
            for j in range(i + 1, count):
                a, b = self.corners[i], self.corners[j]
                if not crosses_fence(self.shapes, a, b):
                    d = math.dist(a, b)
                    self.seen[i].append((j, d))
                    self.seen[j].append((i, d))

    def crosses(self, a: Vec2, b: Vec2) -> bool:
        return crosses_fence(self.shapes, a, b)

    def shortest_path(self, source: Vec2, destination: Vec2) -> list[Vec2]:
        """The points from source to destination (both included) of the shortest way round the
        fence; PlanError(NO_PATH) when there is none."""
        corners, shapes = self.corners, self.shapes
        points = [source, destination, *corners]  # node 0 the source, 1 the destination, then the corners
        count = len(points)
        dist = [math.inf] * count
        came_from = [-1] * count
        visited = [False] * count
        dist[0], visited[0] = 0.0, True
        # the corners and the destination seen from the source, and the corners that see the destination
        for k in range(2, count):
            if not crosses_fence(shapes, source, points[k]):
                dist[k], came_from[k] = math.dist(source, points[k]), 0
        if not crosses_fence(shapes, source, destination):
            dist[1], came_from[1] = math.dist(source, destination), 0
        sees_destination = {k for k in range(2, count) if not crosses_fence(shapes, destination, points[k])}
        to_go = [math.dist(p, destination) for p in points]
        while True:
            current, best = -1, math.inf
            for k in range(count):
                if not visited[k] and dist[k] < math.inf and dist[k] + to_go[k] < best:
                    current, best = k, dist[k] + to_go[k]
            if current < 0 or current == 1:
                break
            visited[current] = True
            if current >= 2:
                neighbours = [(j + 2, d) for j, d in self.seen[current - 2]]
                if current in sees_destination:
                    neighbours.append((1, math.dist(points[current], destination)))
            else:
                neighbours = []
            for k, d in neighbours:
                if dist[current] + d < dist[k]:
                    dist[k], came_from[k] = dist[current] + d, current
        if came_from[1] < 0:
            raise PlanError(NO_PATH)
        path, k = [destination], came_from[1]
        while k > 0 and len(path) <= count:  # (a chain longer than the nodes would be a loop)
            path.append(points[k])
            k = came_from[k]
        if k != 0:
            raise PlanError(NO_PATH)
        path.append(source)
        return path[::-1]

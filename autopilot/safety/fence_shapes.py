"""The stored fence as shapes in the local frame: polygons and circles, each kept in or out.
Both the breach check (failsafe.py) and simple avoidance (simple_avoid.py) read them; they are
rebuilt only when a new fence is uploaded."""
from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from typing import Any, NamedTuple

CMD_POLY_INCLUSION, CMD_POLY_EXCLUSION, CMD_CIRCLE_INCLUSION, CMD_CIRCLE_EXCLUSION = 5001, 5002, 5003, 5004
Vec2 = tuple[float, float]


class Shape(NamedTuple):
    kind: str  # "poly" or "circle"
    inclusion: bool  # the vehicle must stay inside it (else outside)
    vertices: Sequence[tuple[float, float]]  # a polygon's (north, east) corners
    circle: tuple[float, float, float]  # a circle's (north, east, radius)

    def contains(self, p: tuple[float, float]) -> bool:
        if self.kind == "poly":
            return point_in_polygon(p, self.vertices)
        n, e, radius = self.circle
        return math.hypot(p[0] - n, p[1] - e) <= radius


def point_in_polygon(p: tuple[float, float], poly: Sequence[tuple[float, float]]) -> bool:
    """Even-odd rule on a local (north, east) polygon."""
    inside = False
    x, y = p
    count = len(poly)
    for i in range(count):
        (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % count]
        if (y1 > y) != (y2 > y) and x < (x2 - x1) * (y - y1) / (y2 - y1) + x1:
            inside = not inside
    return inside


def breached_shapes(shapes: Sequence[Shape], p: Vec2) -> list[Shape]:
    """The shapes the point is on the wrong side of: outside an inclusion or inside an exclusion."""
    return [s for s in shapes if s.contains(p) != s.inclusion]


def closest_point(p: Vec2, v: Vec2, w: Vec2) -> Vec2:
    """The point of segment v-w nearest p (Vector2::closest_point)."""
    dx, dy = w[0] - v[0], w[1] - v[1]
    l2 = dx * dx + dy * dy
    if l2 < 1.1920929e-07:
        return v
    t = ((p[0] - v[0]) * dx + (p[1] - v[1]) * dy) / l2
    if t <= 0.0:
        return v
    if t >= 1.0:
        return w
    return v[0] + dx * t, v[1] + dy * t


def segment_intersection(a0: Vec2, a1: Vec2, b0: Vec2, b1: Vec2) -> Vec2 | None:
    """Where segments a0-a1 and b0-b1 cross, ends included (Vector2::segment_intersection);
    None for parallel or collinear ones."""
    r1 = (a1[0] - a0[0], a1[1] - a0[1])
    r2 = (b1[0] - b0[0], b1[1] - b0[1])
    q = (b0[0] - a0[0], b0[1] - a0[1])
    cross = r1[0] * r2[1] - r1[1] * r2[0]
    if cross == 0.0:
        return None
    t = (q[0] * r2[1] - q[1] * r2[0]) / cross
    u = (q[0] * r1[1] - q[1] * r1[0]) / cross
    if 0.0 <= u <= 1.0 and 0.0 <= t <= 1.0:
        return a0[0] + r1[0] * t, a0[1] + r1[1] * t
    return None


def vertex_count(p1: float) -> int:
    """A polygon vertex's count of vertices (param 1), as a byte holds it: anything else is 0."""
    return int(p1) if math.isfinite(p1) and 0 <= p1 <= 255 else 0


class FenceShapes:
    __slots__ = ("_version", "_shapes")

    def __init__(self) -> None:
        self._version: int | None = None
        self._shapes: tuple[Shape, ...] = ()

    def shapes(self, version: int, items: Callable[[], Iterable[Any]],
               ned_of: Callable[[float, float, float], tuple[float, float, float]]) -> tuple[Shape, ...]:
        """The shapes of the fence items (their store's `version`), in the local frame."""
        if self._version == version:
            return self._shapes
        shapes: list[Shape] = []
        vertices: list[tuple[float, float]] = []
        for item in items():
            n, e, _ = ned_of(item.x * 1e-7, item.y * 1e-7, 0.0)
            if item.command in (CMD_POLY_INCLUSION, CMD_POLY_EXCLUSION):
                vertices.append((n, e))
                if len(vertices) >= max(vertex_count(item.p1), 3):
                    shapes.append(Shape("poly", item.command == CMD_POLY_INCLUSION, tuple(vertices), (0.0, 0.0, 0.0)))
                    vertices = []
            elif item.command in (CMD_CIRCLE_INCLUSION, CMD_CIRCLE_EXCLUSION):
                shapes.append(Shape("circle", item.command == CMD_CIRCLE_INCLUSION, (), (n, e, item.p1)))
        self._shapes, self._version = tuple(shapes), version
        return self._shapes

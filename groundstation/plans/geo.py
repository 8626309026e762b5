"""Flat-earth geometry in metres north and east of an origin, as QGroundControl's planners work
(a local tangent plane at the shape's first vertex): converting, offsetting lines and polygons,
clipping a line to a polygon. Points are (north, east)."""
from __future__ import annotations

import math
from dataclasses import dataclass

EARTH_RADIUS_M = 6378137.0


@dataclass(frozen=True)
class LocalFrame:
    lat0: float
    lon0: float

    def to_ne(self, lat: float, lon: float) -> tuple[float, float]:
        north = math.radians(lat - self.lat0) * EARTH_RADIUS_M
        east = math.radians(lon - self.lon0) * EARTH_RADIUS_M * math.cos(math.radians(self.lat0))
        return north, east

    def to_latlon(self, north: float, east: float) -> tuple[float, float]:
        lat = self.lat0 + math.degrees(north / EARTH_RADIUS_M)
        lon = self.lon0 + math.degrees(east / (EARTH_RADIUS_M * math.cos(math.radians(self.lat0))))
        return lat, lon


def _cross(a, b) -> float:
    return a[0] * b[1] - a[1] * b[0]


def _line_meet(p, d, q, e):
    """Where the line p + t*d meets q + s*e; None when they are parallel."""
    den = _cross(d, e)
    if abs(den) < 1e-12:
        return None
    t = _cross((q[0] - p[0], q[1] - p[1]), e) / den
    return p[0] + t * d[0], p[1] + t * d[1]


def _left_normal(a, b) -> tuple[float, float]:
    """Unit normal to the left of travel from a to b (north-east axes: left of north is west)."""
    dn, de = b[0] - a[0], b[1] - a[1]
    length = math.hypot(dn, de)
    return de / length, -dn / length


def _offset_edges(points: list, distance: float, closed: bool) -> list:
    pairs = list(zip(points, points[1:] + (points[:1] if closed else [])))
    edges = []
    for a, b in pairs:
        nn, ne = _left_normal(a, b)
        edges.append(((a[0] + nn * distance, a[1] + ne * distance), (b[0] + nn * distance, b[1] + ne * distance)))
    return edges


def _corner(e1, e2):
    """The vertex where two consecutive offset edges meet (their shared end when parallel)."""
    d1 = (e1[1][0] - e1[0][0], e1[1][1] - e1[0][1])
    d2 = (e2[1][0] - e2[0][0], e2[1][1] - e2[0][1])
    return _line_meet(e1[0], d1, e2[0], d2) or e1[1]


def offset_polyline(points: list, distance: float) -> list:
    """The polyline moved `distance` to the left of its direction of travel (negative: right),
    its inner vertices where the moved edges meet, as QGC's corridor transects are made."""
    edges = _offset_edges(points, distance, closed=False)
    return [edges[0][0]] + [_corner(a, b) for a, b in zip(edges, edges[1:])] + [edges[-1][1]]


def signed_area(polygon: list) -> float:
    """Positive when the vertices run clockwise seen from above (north-east axes)."""
    return 0.5 * sum(_cross(a, b) for a, b in zip(polygon, polygon[1:] + polygon[:1]))


def offset_polygon(polygon: list, distance: float) -> list:
    """The polygon grown outwards by `distance` (each edge moved out, vertices where they meet)."""
    outward = distance if signed_area(polygon) > 0 else -distance  # left of travel is outside when clockwise
    edges = _offset_edges(polygon, outward, closed=True)
    return [_corner(edges[i - 1], edges[i]) for i in range(len(edges))]


def clip_line(a, b, polygon: list) -> tuple | None:
    """The part of segment a-b inside the polygon from its first crossing to its last, in the
    direction a to b (QGC joins the pieces of a concave crossing into one transect)."""
    d = (b[0] - a[0], b[1] - a[1])
    hits = []
    for p, q in zip(polygon, polygon[1:] + polygon[:1]):
        e = (q[0] - p[0], q[1] - p[1])
        den = _cross(d, e)
        if abs(den) < 1e-12:
            continue
        w = (p[0] - a[0], p[1] - a[1])
        t, s = _cross(w, e) / den, _cross(w, d) / den
        if 0.0 <= t <= 1.0 and 0.0 <= s <= 1.0:
            hits.append(t)
    if len(hits) < 2 or max(hits) - min(hits) < 1e-9:
        return None
    t0, t1 = min(hits), max(hits)
    return (a[0] + t0 * d[0], a[1] + t0 * d[1]), (a[0] + t1 * d[0], a[1] + t1 * d[1])


def along(a, b, distance: float) -> tuple[float, float]:
    """The point `distance` from a towards b (negative: behind a)."""
    length = math.dist(a, b)
    return a[0] + (b[0] - a[0]) * distance / length, a[1] + (b[1] - a[1]) * distance / length

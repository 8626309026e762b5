"""The way back SMART_RTL flies: ArduCopter's AP_SmartRTL breadcrumbs.

While armed and flying in any other mode, the vehicle's position is offered a few times a second
(`update`); a point is kept when it lies SRTL_ACCURACY metres or more from the last one. Home
(where the vehicle armed) is the first point. The path is kept short as AP_SmartRTL keeps it:

* simplification (Ramer-Douglas-Peucker, tolerance SRTL_ACCURACY / 2) of the points not yet
  simplified, once 50 new points have come (or 10, when the path is nearly full);
* pruning: where two non-adjacent segments pass within 0.99 SRTL_ACCURACY of each other, the loop
  between them is cut out and a point halfway between the two segments replaces it (done when
  the path is nearly full, at least 10 points at a time, and all at once when SMART_RTL starts).

SMART_RTL takes the points back from the end (`pop`, `peek`). With no position for 15 s, or no
room for a new point for 15 s, the path is given up for the flight ("SmartRTL deactivated: ...").
SRTL_POINTS (at most 500; 0 turns SmartRTL off) is read at boot, as ArduCopter reads it.
ArduCopter does this work in a background thread a little at a time; here it is done at once.
"""
from __future__ import annotations

import math
from collections.abc import Callable

from ..params import ParamStore
from ..results import Severity
from ..views import Vector3

POINTS_MAX = 500  # SMARTRTL_POINTS_MAX
TIMEOUT_S = 15.0  # SMARTRTL_TIMEOUT
SIMPLIFY_AFTER = 50  # SMARTRTL_CLEANUP_POINT_TRIGGER: new points that start a simplification
LOW_SPACE_MARGIN = 10  # SMARTRTL_CLEANUP_START_MARGIN: free slots below which cleanup starts
CLEANUP_POINTS_MIN = 10  # SMARTRTL_CLEANUP_POINT_MIN
LOW_SPACE_TEXT_EVERY_S = 10.0
LOOPS_SHARE = 0.25  # SMARTRTL_PRUNING_LOOP_BUFFER_LEN_MULT: loops remembered, of the points
PARALLEL = 1.1920929e-07  # FLT_EPSILON: segments this parallel are not compared (AP_SmartRTL)


class ReturnPath:
    def __init__(self, params: ParamStore, notify: Callable[[str, Severity], None]):
        self._params = params
        self._notify = notify
        self.capacity = min(max(int(params["SRTL_POINTS"]), 0), POINTS_MAX)
        self.enabled = self.capacity > 0 and params["SRTL_ACCURACY"] > 0
        self.points: list[Vector3] = []
        self.active = False  # a path is kept and usable (from the first good position on)
        self._home_saved = False
        self._last_good_s = 0.0
        self._last_saved_s = 0.0
        self._simplified = 0  # points at the start of the path already simplified
        self._low_space_said_s = -math.inf

    @property
    def accuracy(self) -> float:
        return self._params["SRTL_ACCURACY"]

    # ----- recording ---------------------------------------------------------------------------
    def set_home(self, position_ok: bool, here: Vector3, now_s: float) -> None:
        """A new path starting here (on arming, and at the first good position after boot)."""
        if not self.enabled:
            return
        self.points.clear()
        self._simplified = 0
        if not position_ok:
            return
        self._add(here)
        self._last_good_s = self._last_saved_s = now_s
        self.active = self._home_saved = True

    def update(self, position_ok: bool, save: bool, here: Vector3, now_s: float) -> None:
        """Offered at about 3 Hz in every mode; `save`: armed and not flying SMART_RTL."""
        if position_ok and not self._home_saved:
            self.set_home(True, here, now_s)
        if not (self.active and save):
            return
        if not position_ok:
            if now_s - self._last_good_s > TIMEOUT_S:
                self._deactivate("bad position")
            return
        self._last_good_s = now_s
        if self._add(here):
            self._last_saved_s = now_s
            self._routine_cleanup(now_s)
        elif now_s - self._last_saved_s > TIMEOUT_S:
            self._deactivate("buffer full")

    def _add(self, point: Vector3) -> bool:
        """Keep `point` if far enough from the last; False when there is no room for it."""
        points = self.points
        if points and _dist2(points[-1], point) < self.accuracy ** 2:
            return True
        if len(points) >= self.capacity:
            return False
        points.append(point)
        return True

    def _deactivate(self, reason: str) -> None:
        self.active = False
        self._notify(f"SmartRTL deactivated: {reason}", Severity.WARNING)

    # ----- taking the way back -----------------------------------------------------------------
    def pop(self) -> Vector3 | None:
        """The last point, taken off the path (None when there is none)."""
        if not self.active or not self.points:
            return None
        point = self.points.pop()
        self._simplified = min(self._simplified, len(self.points))
        return point

    def peek(self) -> Vector3 | None:
        return self.points[-1] if self.active and self.points else None

    def add_back(self, point: Vector3) -> bool:
        """A point SMART_RTL took and did not reach, put back when it ends (exit)."""
        return self._add(point)

    # ----- cleanup -----------------------------------------------------------------------------
    def _routine_cleanup(self, now_s: float) -> None:
        count = len(self.points)
        new = count - self._simplified
        low_on_space = self.capacity - count <= LOW_SPACE_MARGIN
        if new >= SIMPLIFY_AFTER or (low_on_space and new >= CLEANUP_POINTS_MIN):
            self.simplify()
        elif low_on_space:
            self.prune(CLEANUP_POINTS_MIN)
        count = len(self.points)
        if count >= self.capacity - 9 and now_s - self._low_space_said_s > LOW_SPACE_TEXT_EVERY_S:
            self._notify("SmartRTL Low on space!", Severity.INFO)
            self._low_space_said_s = now_s

    def thorough_cleanup(self) -> None:
        """Everything simplified and every loop cut out: done as SMART_RTL starts."""
        self.simplify()
        self.prune(POINTS_MAX)

    def simplify(self) -> None:
        """Ramer-Douglas-Peucker over the points not yet simplified (from the last one that was)."""
        points = self.points
        count = len(points)
        if count < 3:
            self._simplified = count
            return
        epsilon = self.accuracy * 0.5
        keep = [True] * count
        stack = [(max(self._simplified - 1, 0), count - 1)]
        while stack:
            start, end = stack.pop()
            farthest, farthest_m = start, 0.0
            for i in range(start + 1, end):
                distance = _to_segment(points[i], points[start], points[end])
                if distance > farthest_m:
                    farthest, farthest_m = i, distance
            if farthest_m > epsilon:
                stack.append((start, farthest))
                stack.append((farthest, end))
            else:
                for i in range(start + 1, end):
                    keep[i] = False
        self.points = [p for p, kept in zip(points, keep) if kept]
        self._simplified = len(self.points)

    def prune(self, at_least: int) -> None:
        """Cut out the loops found (the last found first) until `at_least` points are gone."""
        loops = self._find_loops()
        points = self.points
        removed = 0
        while loops and removed < at_least:
            start, end, midpoint, _ = loops.pop()
            gone = end - start
            points[start] = midpoint
            del points[start + 1:end + 1]
            removed += gone
            loops = [(s - gone if s >= end else s, e - gone if e >= end else e, m, length)
                     for s, e, m, length in loops]
        self._simplified = min(self._simplified, len(points))

    def _find_loops(self) -> list[tuple[int, int, Vector3, float]]:
        """AP_SmartRTL's loop search: each segment from the newest back against the older ones
        (not its neighbour); the first close pass found for a segment makes a loop."""
        points = self.points
        loops: list[tuple[int, int, Vector3, float]] = []
        loops_max = int(self.capacity * LOOPS_SHARE)
        delta = self.accuracy * 0.99
        for i in range(len(points) - 1, 3, -1):
            for j in range(1, i - 1):
                distance, midpoint = _segment_segment(points[i], points[i - 1], points[j - 1], points[j])
                if distance < delta:
                    if not _add_loop(loops, loops_max, points, j, i - 1, midpoint):
                        return loops
                    break
        return loops


def _add_loop(loops: list, loops_max: int, points: list, start: int, end: int, midpoint: Vector3) -> bool:
    """Remember a loop; of loops that overlap, the longer (by its squared lengths) is kept.
    False when no more loops can be remembered."""
    if len(loops) >= loops_max:
        return False
    if end <= start:
        return False
    length = _dist2(midpoint, points[start]) + _dist2(midpoint, points[end])
    length += sum(_dist2(points[i], points[i + 1]) for i in range(start, end))
    overlapping = [loop for loop in loops if _overlap(loop, start, end)]
    if overlapping:
        if sum(loop[3] for loop in overlapping) > length:
            return True
        loops[:] = [loop for loop in loops if not _overlap(loop, start, end)]
    loops.append((start, end, midpoint, length))
    return True


def _overlap(loop: tuple, start: int, end: int) -> bool:
    """Whether a remembered loop and the loop start..end overlap (one inside the other, or one
    end of the remembered loop inside the new one)."""
    s, e = loop[0], loop[1]
    if (s >= start and e <= end) or (start >= s and end <= e):
        return True
    return (start <= s <= end) != (start <= e <= end)


def _dist2(a: Vector3, b: Vector3) -> float:
    return (a[0] - b[0]) ** 2 + (a[1] - b[1]) ** 2 + (a[2] - b[2]) ** 2


def _to_segment(p: Vector3, a: Vector3, b: Vector3) -> float:
    """Distance from p to the segment a-b."""
    ab = (b[0] - a[0], b[1] - a[1], b[2] - a[2])
    length2 = ab[0] ** 2 + ab[1] ** 2 + ab[2] ** 2
    if length2 == 0.0:
        return math.sqrt(_dist2(p, a))
    k = ((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1] + (p[2] - a[2]) * ab[2]) / length2
    k = min(max(k, 0.0), 1.0)
    return math.sqrt(_dist2(p, (a[0] + k * ab[0], a[1] + k * ab[1], a[2] + k * ab[2])))


def _segment_segment(p1: Vector3, p2: Vector3, p3: Vector3, p4: Vector3) -> tuple[float, Vector3]:
    """Closest distance between segments p1-p2 and p3-p4, and the point halfway between their
    closest points; (inf, origin) for (nearly) parallel segments, as AP_SmartRTL gives."""
    u = (p2[0] - p1[0], p2[1] - p1[1], p2[2] - p1[2])
    v = (p4[0] - p3[0], p4[1] - p3[1], p4[2] - p3[2])
    w = (p1[0] - p3[0], p1[1] - p3[1], p1[2] - p3[2])
    a = u[0] * u[0] + u[1] * u[1] + u[2] * u[2]
    b = u[0] * v[0] + u[1] * v[1] + u[2] * v[2]
    c = v[0] * v[0] + v[1] * v[1] + v[2] * v[2]
    d = u[0] * w[0] + u[1] * w[1] + u[2] * w[2]
    e = v[0] * w[0] + v[1] * w[1] + v[2] * w[2]
    det = a * c - b * b
    if abs(det) < PARALLEL:
        return math.inf, (0.0, 0.0, 0.0)
    t1 = min(max((b * e - c * d) / det, 0.0), 1.0)
    t2 = min(max((a * e - b * d) / det, 0.0), 1.0)
    q1 = (p1[0] + u[0] * t1, p1[1] + u[1] * t1, p1[2] + u[2] * t1)
    q2 = (p3[0] + v[0] * t2, p3[1] + v[1] * t2, p3[2] + v[2] * t2)
    return math.sqrt(_dist2(q1, q2)), ((q1[0] + q2[0]) / 2, (q1[1] + q2[1]) / 2, (q1[2] + q2[2]) / 2)

"""Where AUTO RTL joins the mission: the nearest landing sequence (DO_LAND_START) or the nearest
leg of a return path (after a DO_RETURN_PATH_START), as AP_Mission finds them.

`where(item)` gives an item's point (local NED), or None for an item without a location. Indexes
are into the stored items (seq = index + 1); the search starts at seq 1, as AP_Mission's does.
"""
from __future__ import annotations

import math
from collections.abc import Callable, Sequence

from .commands import CMD_LAND, is_nav
from .store import MissionItem

CMD_DO_RETURN_PATH_START, CMD_DO_LAND_START = 188, 189
LANDING_COMMANDS = {CMD_LAND, 85, 208}  # NAV_LAND, NAV_VTOL_LAND, DO_PARACHUTE (is_landing_type_cmd)

Point = tuple[float, float, float]
Where = Callable[[MissionItem], Point | None]


def landing_sequence_start(items: Sequence[MissionItem], here: Point, where: Where) -> int | None:
    """The index of the DO_LAND_START nearest `here` (by its own location, or the next navigation
    item's when it has none); None when the mission has none."""
    best, best_m = None, math.inf
    for index, item in enumerate(items):
        if item.command != CMD_DO_LAND_START:
            continue
        point = where(item)
        if point is None:
            following = next((i for i in items[index + 1:] if is_nav(i.command)), None)
            point = None if following is None else where(following)
            if point is None:
                continue
        distance = math.dist(point, here)
        if distance < best_m:
            best, best_m = index, distance
    return best


def closest_return_leg(items: Sequence[MissionItem], here: Point, where: Where) -> int | None:
    """The index of the item ending the return-path leg nearest `here`: of the items from each
    DO_RETURN_PATH_START up to a landing (a path that never reaches one does not count); None
    when there is no such path."""
    best, best_m = None, math.inf
    for start, item in enumerate(items):
        if item.command != CMD_DO_RETURN_PATH_START:
            continue
        found = _nearest_leg_end(items, start, here, where)
        if found is not None and found[1] <= best_m:
            best, best_m = found
    return best


def _nearest_leg_end(items: Sequence[MissionItem], start: int, here: Point, where: Where) -> tuple[int, float] | None:
    previous: Point | None = None
    nearest: tuple[int, float] | None = None
    for index in range(start, len(items)):
        item = items[index]
        point = where(item)
        if point is not None:
            distance = math.dist(point, here) if previous is None else _to_segment(here, previous, point)
            if distance is not None and (nearest is None or distance < nearest[1]):
                nearest = (index, distance)
            previous = point
        if item.command in LANDING_COMMANDS or item.command == CMD_DO_LAND_START:
            return nearest
    return None


def _to_segment(p: Point, a: Point, b: Point) -> float | None:
    """Distance from p to the segment a-b, axis by axis clamped as AP_Mission clamps it; None for
    a leg of no length."""
    leg = tuple(bi - ai for ai, bi in zip(a, b))
    length2 = sum(x * x for x in leg)
    if length2 == 0.0:
        return None
    rel = tuple(pi - ai for ai, pi in zip(a, p))
    k = sum(r * x for r, x in zip(rel, leg)) / length2
    proj = tuple(min(max(k * x, min(0.0, x)), max(0.0, x)) for x in leg)
    return math.dist(proj, rel)

"""DO_SET_RESUME_REPEAT_DIST: a mission interrupted and resumed flies again the last metres it had
flown before the interruption (a sprayer's missed strip), as AP_Mission's resume does:

- while the repeat distance is set, each navigation item with a location that is loaded joins a
  history of the last HISTORY such items (the last one is the item being flown);
- on a resume, the way back from where AUTO was left, through the waypoints passed in reverse, is
  measured out to the repeat distance; the point reached is flown to as the item that begins the
  leg it lies on (a copy of that waypoint, moved along its leg), or the oldest waypoint kept if the
  history is shorter; the mission goes on from there, and says "Mission: Returned to interrupted
  WP" when the item that was interrupted is loaded again;
- anything that sets the current item (a start, MISSION_SET_CURRENT, a resume without a rewind)
  forgets the history and the distance.

Distances are AP's Location arithmetic: latitude and longitude in 1e-7 degrees on a flat earth
scaled by the cosine of the latitude.
"""
from __future__ import annotations

import math
from dataclasses import replace

from ..location import M_PER_E7, longitude_scale
from .store import MissionItem

HISTORY = 7  # AP_MISSION_MAX_WP_HISTORY
LAST_PASSED = HISTORY - 2  # the waypoint before the one being flown
RETURNED = "Mission: Returned to interrupted WP"


def _offset_m(a: tuple[float, float], b: tuple[float, float]) -> tuple[float, float]:
    """(north, east) metres from a to b, each (lat, lon) in 1e-7 degrees."""
    return (b[0] - a[0]) * M_PER_E7, (b[1] - a[1]) * M_PER_E7 * longitude_scale(b[0])


def _distance_m(a: tuple[float, float], b: tuple[float, float]) -> float:
    return math.hypot(*_offset_m(a, b))


class WaypointHistory:
    def __init__(self) -> None:
        self.clear()

    def clear(self) -> None:
        self.indexes: list[int | None] = [None] * HISTORY
        self.rewound: tuple[int, MissionItem] | None = None  # the point a resume flies back to
        self.resuming = False  # flying back: the history is left as it is

    def loaded(self, index: int, item: MissionItem, repeat_m: int) -> bool:
        """A navigation item was loaded; True when it is the interrupted one, flown back to."""
        if repeat_m > 0 and not self.resuming and not (item.x == 0 and item.y == 0):
            self.indexes = self.indexes[1:] + [index]
        if self.resuming and index == self.indexes[-1]:
            self.resuming = False
            return True
        return False

    def rewind(self, items: list, exit_e7: tuple[float, float] | None, repeat_m: int) -> tuple[int, MissionItem] | None:
        """The (index, item) a resume flies to, or None: no rewind (nothing passed yet, or no
        exit position)."""
        if repeat_m <= 0 or self.indexes[LAST_PASSED] is None:
            return None
        if not self.resuming and exit_e7 is not None:
            self.rewound = _rewind_point(items, self.indexes, exit_e7, repeat_m) or self.rewound
        return self.rewound


def _location(item: MissionItem) -> tuple[float, float]:
    return float(item.x), float(item.y)


def _rewind_point(items: list, history: list, exit_e7: tuple[float, float], repeat_m: int):
    left = float(repeat_m)
    previous = exit_e7
    index = None
    for i in range(LAST_PASSED, -1, -1):
        k = history[i]
        if k is None:
            break
        if k >= len(items):
            return None  # a list changed under the history: no rewind
        index = i
        left -= _distance_m(previous, _location(items[k]))
        if left <= 0.0:
            break
        previous = _location(items[k])
    if index is None:
        return None
    passed = items[history[index]]
    if left > 0.0:  # the history ran out first: back to the oldest waypoint kept
        return history[index], passed
    following = history[index + 1]
    if following is None or following >= len(items):
        return None
    ahead = items[following]
    dn, de = _offset_m(_location(passed), _location(ahead))
    length = math.hypot(dn, de)
    share = abs(left) / length if length > 0 else 0.0
    lat = passed.x + dn * share / M_PER_E7
    lon = passed.y + de * share / M_PER_E7 / longitude_scale(lat)
    z = passed.z + (ahead.z - passed.z) * share
    return history[index], replace(passed, x=int(round(lat)), y=int(round(lon)), z=z)

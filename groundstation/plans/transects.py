"""QGroundControl's transect-style items (survey and corridor scan share them): from transects of
typed points to the waypoints and camera commands it uploads, as it does for ArduPilot (no
CONDITION_GATE; hover-and-capture off; images taken in the turnarounds, its default)."""
from __future__ import annotations

from dataclasses import dataclass

from .geo import LocalFrame, along
from .items import trigger_distance, waypoint

ENTRY, EXIT, TURNAROUND, INTERIOR = "entry", "exit", "turnaround", "interior"


@dataclass(frozen=True)
class TransectPoint:
    ne: tuple  # (north, east) metres in the shape's frame
    kind: str


def with_turnarounds(points: list, distance: float) -> list:
    """A transect (entry, ..., exit) extended by `distance` beyond each end, along its end legs."""
    if distance <= 0:
        return points
    first, second, last, before = points[0].ne, points[1].ne, points[-1].ne, points[-2].ne
    start, end = along(first, second, -distance), along(last, before, -distance)
    return [TransectPoint(start, TURNAROUND)] + points + [TransectPoint(end, TURNAROUND)]


def flight_items(frame: LocalFrame, transects: list, altitude: float, trigger_m: float,
                 turnaround_m: float) -> list:
    """The items for the transects flown in order: a waypoint per point; the camera started by
    distance at the first point and at every transect's entry, stopped at the last point."""
    path = [p for transect in transects for p in transect]
    items = []
    triggering = trigger_m > 0
    for k, point in enumerate(path):
        lat, lon = frame.to_latlon(*point.ne)
        items.append(waypoint(lat, lon, altitude))
        if not triggering:
            continue
        first, last = k == 0, k == len(path) - 1
        if point.kind == TURNAROUND and (first or last):
            items.append(trigger_distance(trigger_m if first else 0.0, True))
        elif point.kind == ENTRY:
            # QGC starts the camera again at every entry, so a resumed mission reflies a transect
            items.append(trigger_distance(trigger_m, True))
        elif point.kind == EXIT and last and turnaround_m <= 0:
            items.append(trigger_distance(0.0, True))
    return items


def visual_points(frame: LocalFrame, transects: list) -> list:
    """The transects' points (turnarounds left out) as [lat, lon], QGC's VisualTransectPoints."""
    return [list(frame.to_latlon(*p.ne)) for transect in transects for p in transect if p.kind != TURNAROUND]


def transect_style_json(frame: LocalFrame, transects: list, items: list, first_jump_id: int, *,
                        altitude: float, side_m: float, trigger_m: float, turnaround_m: float) -> dict:
    """QGC's TransectStyleComplexItem object (version 2) with a manual camera (CameraCalc v2)."""
    shots = 0
    if trigger_m > 0:
        pts = [p.ne for transect in transects for p in transect if p.kind != TURNAROUND]
        length = sum(((a[0] - b[0]) ** 2 + (a[1] - b[1]) ** 2) ** 0.5 for a, b in zip(pts, pts[1:]))
        shots = int(-(-length // trigger_m))
    return {
        "CameraCalc": {"AdjustedFootprintFrontal": trigger_m, "AdjustedFootprintSide": side_m,
                       "CameraName": "Manual (no camera specs)", "DistanceMode": 1,
                       "DistanceToSurface": altitude, "version": 2},
        "CameraShots": shots,
        "CameraTriggerInTurnAround": True,
        "HoverAndCapture": False,
        "Items": [it.qgc_json(first_jump_id + k) for k, it in enumerate(items)],
        "Refly90Degrees": False,
        "TurnAroundDistance": turnaround_m,
        "VisualTransectPoints": visual_points(frame, transects),
        "version": 2,
    }

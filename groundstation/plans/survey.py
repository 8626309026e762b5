"""QGroundControl's survey (complexItemType "survey", version 5) over a polygon: parallel
transects `side_m` apart at `angle` degrees, swept across the polygon's bounding box from its
centre out, clipped to the polygon, flown as a lawnmower from the entry corner, each extended by
the turnaround distance; the camera triggered every `trigger_m` metres."""
from __future__ import annotations

import math
from dataclasses import dataclass

from .geo import LocalFrame, clip_line
from .transects import ENTRY, EXIT, TransectPoint, flight_items, transect_style_json, with_turnarounds

TOP_LEFT, TOP_RIGHT, BOTTOM_LEFT, BOTTOM_RIGHT = range(4)  # QGC's entryLocation


@dataclass(frozen=True)
class Survey:
    polygon: tuple  # ((lat, lon), ...)
    altitude: float
    side_m: float          # distance between transects (CameraCalc's AdjustedFootprintSide)
    trigger_m: float       # distance between photos (AdjustedFootprintFrontal)
    angle: float = 0.0     # degrees clockwise from north
    entry: int = TOP_LEFT
    turnaround_m: float = 10.0  # QGC's multirotor default

    @property
    def frame(self) -> LocalFrame:
        return LocalFrame(*self.polygon[0])

    def transects(self) -> list:
        frame = self.frame
        # QGC's plane: x east, y north
        pts = [(e, n) for n, e in (frame.to_ne(*v) for v in self.polygon)]
        xs, ys = [p[0] for p in pts], [p[1] for p in pts]
        cx, cy = (min(xs) + max(xs)) / 2, (min(ys) + max(ys)) / 2
        half = 1.5 * math.hypot(max(xs) - min(xs), max(ys) - min(ys)) / 2
        angle = self.angle - 180.0 if self.angle > 90.0 else self.angle + 180.0 if self.angle < -90.0 else self.angle
        r = math.radians(-angle)

        def turned(x, y):
            return ((x - cx) * math.cos(r) - (y - cy) * math.sin(r) + cx,
                    (x - cx) * math.sin(r) + (y - cy) * math.cos(r) + cy)
        polygon_ne = [(y, x) for x, y in pts]
        lines = []
        x = cx - half
        while x < cx + half:
            (ax, ay), (bx, by) = turned(x, cy - half), turned(x, cy + half)
            inside = clip_line((ay, ax), (by, bx), polygon_ne)
            if inside is not None:
                lines.append(list(inside))
            x += self.side_m
        if self.entry in (BOTTOM_LEFT, BOTTOM_RIGHT):
            lines = [line[::-1] for line in lines]
        if self.entry in (TOP_RIGHT, BOTTOM_RIGHT):
            lines.reverse()
        lines = [line[::-1] if k % 2 else line for k, line in enumerate(lines)]
        return [with_turnarounds([TransectPoint(a, ENTRY), TransectPoint(b, EXIT)], self.turnaround_m)
                for a, b in lines]

    def items(self) -> list:
        return flight_items(self.frame, self.transects(), self.altitude, self.trigger_m, self.turnaround_m)

    def qgc_json(self, first_jump_id: int) -> dict:
        return {
            "TransectStyleComplexItem": transect_style_json(
                self.frame, self.transects(), self.items(), first_jump_id, altitude=self.altitude,
                side_m=self.side_m, trigger_m=self.trigger_m, turnaround_m=self.turnaround_m),
            "angle": self.angle, "complexItemType": "survey", "entryLocation": self.entry,
            "flyAlternateTransects": False, "polygon": [list(v) for v in self.polygon],
            "splitConcavePolygons": False, "type": "ComplexItem", "version": 5,
        }

"""QGroundControl's corridor scan (complexItemType "CorridorScan", version 2) along a polyline:
ceil(width / side) transects, each the polyline moved sideways (the first half a spacing inside
the corridor's left edge), flown back and forth, each extended by the turnaround distance."""
from __future__ import annotations

import math
from dataclasses import dataclass

from .geo import LocalFrame, offset_polyline
from .transects import ENTRY, EXIT, INTERIOR, TransectPoint, flight_items, transect_style_json, with_turnarounds

SWAPPED = {ENTRY: EXIT, EXIT: ENTRY}


@dataclass(frozen=True)
class Corridor:
    polyline: tuple  # ((lat, lon), ...)
    width_m: float
    altitude: float
    side_m: float
    trigger_m: float
    entry: int = 0
    turnaround_m: float = 10.0

    @property
    def frame(self) -> LocalFrame:
        return LocalFrame(*self.polyline[0])

    def transects(self) -> list:
        frame = self.frame
        line = [frame.to_ne(*v) for v in self.polyline]
        spacing = self.side_m if self.side_m >= 0.5 else 100000.0  # QGC's guard: one transect
        count = math.ceil(self.width_m / spacing) if self.width_m > 0 else 1
        transects = []
        for k in range(count):
            offset = 0.0 if count == 1 else self.width_m / 2 - spacing / 2 - k * spacing
            pts = offset_polyline(line, offset)
            kinds = [ENTRY] + [INTERIOR] * (len(pts) - 2) + [EXIT]
            points = [TransectPoint(p, kind) for p, kind in zip(pts, kinds)]
            transects.append(with_turnarounds(points, self.turnaround_m))
        if self.entry in (1, 3):
            transects.reverse()
        if self.entry in (2, 3):
            transects = [t[::-1] for t in transects]
        return [[TransectPoint(p.ne, SWAPPED.get(p.kind, p.kind)) for p in reversed(t)] if k % 2 else t
                for k, t in enumerate(transects)]

    def items(self) -> list:
        return flight_items(self.frame, self.transects(), self.altitude, self.trigger_m, self.turnaround_m)

    def qgc_json(self, first_jump_id: int) -> dict:
        return {
            "CorridorWidth": self.width_m, "EntryPoint": self.entry,
            "TransectStyleComplexItem": transect_style_json(
                self.frame, self.transects(), self.items(), first_jump_id, altitude=self.altitude,
                side_m=self.side_m, trigger_m=self.trigger_m, turnaround_m=self.turnaround_m),
            "complexItemType": "CorridorScan", "polyline": [list(v) for v in self.polyline],
            "type": "ComplexItem", "version": 2,
        }

"""QGroundControl's structure scan (complexItemType "StructureScan", version 3): the structure's
footprint grown by the scan distance is flown once per layer, round from the entry vertex back to
it, with the camera triggered by distance round each layer and pointed at the structure
(DO_SET_ROI_WPNEXT_OFFSET, 90 degrees off the next waypoint) for the whole scan. QGC saves only
these settings, not the items: it makes them again when it loads the plan, and so does
`from_qgc_json` here.

ArduCopter 4.7 refuses DO_SET_ROI_WPNEXT_OFFSET at upload (MAV_MISSION_UNSUPPORTED: QGC issue
6824, ArduPilot issue 30710; it comes in 4.8), so a QGC structure scan stops there on it.
`items_pointing_at_centre` is the scan as ArduPilot's developers advise flying it meanwhile: the
same items with the structure's centre as a fixed ROI (DO_SET_ROI_LOCATION) instead."""
from __future__ import annotations

from dataclasses import dataclass

from .geo import LocalFrame, offset_polygon
from .items import (DO_SET_ROI_LOCATION, DO_SET_ROI_NONE, DO_SET_ROI_WPNEXT_OFFSET, FRAME_MISSION, FRAME_RELATIVE,
                    PlannedItem, trigger_distance, waypoint)

MANUAL_CAMERA = "Manual (no camera specs)"


@dataclass(frozen=True)
class StructureScan:
    footprint: tuple        # ((lat, lon), ...) of the structure
    scan_distance_m: float  # from the structure's walls (CameraCalc's DistanceToSurface)
    layer_height_m: float   # AdjustedFootprintFrontal
    trigger_m: float        # AdjustedFootprintSide
    structure_height_m: float
    layers: int
    entrance_alt_m: float
    bottom_alt_m: float = 0.0
    gimbal_pitch_deg: float = 0.0
    start_from_top: bool = False

    @property
    def frame(self) -> LocalFrame:
        return LocalFrame(*self.footprint[0])

    def flight_polygon(self) -> list:
        frame = self.frame
        return [frame.to_latlon(*p) for p in offset_polygon([frame.to_ne(*v) for v in self.footprint],
                                                              self.scan_distance_m)]

    def items(self) -> list:
        ring = self.flight_polygon()
        entrance = ring[0]
        half = self.layer_height_m / 2
        alt = self.structure_height_m - half if self.start_from_top else self.bottom_alt_m + half
        step = -self.layer_height_m if self.start_from_top else self.layer_height_m
        items = [waypoint(*entrance, self.entrance_alt_m),
                 PlannedItem(DO_SET_ROI_WPNEXT_OFFSET, FRAME_MISSION, (0.0, 0.0, 0.0, 0.0),
                             self.gimbal_pitch_deg, 0.0, 90.0)]
        for _ in range(self.layers):
            for k, vertex in enumerate(ring + ring[:1]):
                items.append(waypoint(*vertex, alt))
                if k == 0:
                    items.append(trigger_distance(self.trigger_m, True))
            items.append(trigger_distance(0.0, False))
            alt += step
        items.append(PlannedItem(DO_SET_ROI_NONE, FRAME_MISSION, (0.0, 0.0, 0.0, 0.0), 0.0, 0.0, 0.0))
        items.append(waypoint(*entrance, self.entrance_alt_m))
        return items

    def items_pointing_at_centre(self) -> list:
        """items() with the ROI a fixed point: the footprint's centre, half way up the structure."""
        frame = self.frame
        ring = [frame.to_ne(*v) for v in self.footprint]
        centre = frame.to_latlon(sum(p[0] for p in ring) / len(ring), sum(p[1] for p in ring) / len(ring))
        roi = PlannedItem(DO_SET_ROI_LOCATION, FRAME_RELATIVE, (0.0, 0.0, 0.0, 0.0), *centre,
                          (self.bottom_alt_m + self.structure_height_m) / 2)
        return [roi if it.command == DO_SET_ROI_WPNEXT_OFFSET else it for it in self.items()]

    def qgc_json(self, first_jump_id: int = 0) -> dict:
        return {
            "CameraCalc": {"AdjustedFootprintFrontal": self.layer_height_m, "AdjustedFootprintSide": self.trigger_m,
                           "CameraName": MANUAL_CAMERA, "DistanceMode": 1,
                           "DistanceToSurface": self.scan_distance_m, "version": 2},
            "EntranceAltitude": self.entrance_alt_m, "GimbalPitch": self.gimbal_pitch_deg, "Layers": self.layers,
            "ScanBottomAlt": self.bottom_alt_m, "StartFromTop": self.start_from_top,
            "StructureHeight": self.structure_height_m, "complexItemType": "StructureScan",
            "polygon": [list(v) for v in self.footprint], "type": "ComplexItem", "version": 3,
        }


def from_qgc_json(obj: dict, where: str, number) -> StructureScan:
    """The scan a saved StructureScan describes; `number(field)` reads a number or raises an
    error naming where."""
    polygon = obj.get("polygon")
    if not isinstance(polygon, list) or len(polygon) < 3:
        raise ValueError(f"{where}.polygon: expected at least 3 [lat, lon] vertices")
    footprint = tuple((number(f"polygon[{k}][0]", v[0] if isinstance(v, list) and len(v) == 2 else None),
                       number(f"polygon[{k}][1]", v[1] if isinstance(v, list) and len(v) == 2 else None))
                      for k, v in enumerate(polygon))
    calc = obj.get("CameraCalc")
    if not isinstance(calc, dict):
        raise ValueError(f"{where}.CameraCalc: missing")
    layers = number("Layers", obj.get("Layers"))
    if layers != int(layers) or not 1 <= layers <= 1000:
        raise ValueError(f"{where}.Layers: expected a whole number 1..1000, got {layers}")
    return StructureScan(
        footprint, number("CameraCalc.DistanceToSurface", calc.get("DistanceToSurface")),
        number("CameraCalc.AdjustedFootprintFrontal", calc.get("AdjustedFootprintFrontal")),
        number("CameraCalc.AdjustedFootprintSide", calc.get("AdjustedFootprintSide")),
        number("StructureHeight", obj.get("StructureHeight")), int(layers),
        number("EntranceAltitude", obj.get("EntranceAltitude")), number("ScanBottomAlt", obj.get("ScanBottomAlt")),
        number("GimbalPitch", obj.get("GimbalPitch")), bool(obj.get("StartFromTop", False)))

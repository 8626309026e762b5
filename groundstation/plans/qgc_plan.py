"""A QGroundControl `.plan` (fileType "Plan", mission version 2) as QGC saves one for an
ArduCopter (firmwareType 3, vehicleType 2): simple items and complex items in order, each
complex item's own items numbered (doJumpId) in the mission's sequence."""
from __future__ import annotations

import json
from pathlib import Path

ARDUPILOT, MULTIROTOR = 3, 2


def plan_json(home: tuple, entries: list, cruise_speed: float = 15.0, hover_speed: float = 5.0) -> dict:
    """`entries`: PlannedItem or a complex item (an object with items() and qgc_json(first_jump_id))."""
    saved, jump_id = [], 1
    for entry in entries:
        if hasattr(entry, "qgc_json") and hasattr(entry, "items"):
            saved.append(entry.qgc_json(jump_id))
            jump_id += len(entry.items())
        else:
            saved.append(entry.qgc_json(jump_id))
            jump_id += 1
    return {
        "fileType": "Plan", "geoFence": {"circles": [], "polygons": [], "version": 2},
        "groundStation": "QGroundControl",
        "mission": {"cruiseSpeed": cruise_speed, "firmwareType": ARDUPILOT, "globalPlanAltitudeMode": 1,
                    "hoverSpeed": hover_speed, "items": saved, "plannedHomePosition": list(home),
                    "vehicleType": MULTIROTOR, "version": 2},
        "rallyPoints": {"points": [], "version": 2}, "version": 1,
    }


def write_plan(path: Path, home: tuple, entries: list) -> None:
    Path(path).write_text(json.dumps(plan_json(home, entries), indent=4) + "\n")

"""Mission files ground stations write: QGroundControl `.plan` (JSON) and "QGC WPL 110"
`.waypoints` (Mission Planner, MAVProxy). Both become the same list of plain items; every
mistake is a MissionFileError naming the file and the line or field. A `.plan`'s complex items
give the items QGC would upload: a survey's or corridor scan's are saved in it
(TransectStyleComplexItem.Items); a structure scan's are made again from its settings, as QGC
makes them when it loads the plan."""
from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

from ..plans.items import PlannedItem
from ..plans.structure import from_qgc_json as structure_scan

__all__ = ["MissionFileError", "MissionPlan", "PlannedItem", "load_mission"]
TRANSECT_STYLE = ("survey", "CorridorScan")


class MissionFileError(ValueError):
    pass


@dataclass
class MissionPlan:
    home: tuple | None  # (lat, lon, alt AMSL) if the file gives one
    items: list  # PlannedItem, not counting home


def _finite(where: str, value) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise MissionFileError(f"{where}: expected a number, got {value!r}")
    if not math.isfinite(value):
        raise MissionFileError(f"{where}: must be finite")
    return float(value)


def _checked_position(where: str, lat: float, lon: float) -> None:
    if not -90 <= lat <= 90:
        raise MissionFileError(f"{where}: latitude {lat} outside -90..90")
    if not -180 <= lon <= 180:
        raise MissionFileError(f"{where}: longitude {lon} outside -180..180")


def load_waypoints(path: Path, text: str) -> MissionPlan:
    lines = text.splitlines()
    if not lines or not lines[0].strip().startswith("QGC WPL 110"):
        raise MissionFileError(f"{path}:1: expected the header 'QGC WPL 110'")
    home, items = None, []
    for number, line in enumerate(lines[1:], start=2):
        if not line.strip():
            continue
        fields = line.split("\t") if "\t" in line else line.split()
        where = f"{path}:{number}"
        if len(fields) != 12:
            raise MissionFileError(f"{where}: expected 12 fields, found {len(fields)}")
        try:
            index, current, frame, command = (int(f) for f in fields[:4])
            p1, p2, p3, p4, lat, lon, alt = (float(f) for f in fields[4:11])
            autocontinue = int(float(fields[11]))
        except ValueError:
            raise MissionFileError(f"{where}: a field is not a number") from None
        if not all(math.isfinite(v) for v in (lat, lon, alt)):
            raise MissionFileError(f"{where}: latitude, longitude and altitude must be finite")
        _checked_position(where, lat, lon)
        if index == 0 and not items and home is None:
            home = (lat, lon, alt)
            continue
        items.append(PlannedItem(command, frame, (p1, p2, p3, p4), lat, lon, alt, bool(autocontinue)))
    return MissionPlan(home, items)


def load_plan(path: Path, text: str) -> MissionPlan:
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise MissionFileError(f"{path}:{exc.lineno}: not valid JSON ({exc.msg})") from None
    if not isinstance(data, dict) or data.get("fileType") != "Plan":
        raise MissionFileError(f"{path}: fileType must be \"Plan\"")
    mission = data.get("mission")
    if not isinstance(mission, dict) or not isinstance(mission.get("items"), list):
        raise MissionFileError(f"{path}: mission.items missing")
    home = None
    planned_home = mission.get("plannedHomePosition")
    if planned_home is not None:
        if not isinstance(planned_home, list) or len(planned_home) != 3:
            raise MissionFileError(f"{path}: mission.plannedHomePosition must be [lat, lon, alt]")
        home = tuple(_finite(f"{path}: mission.plannedHomePosition", v) for v in planned_home)
    items = []
    for k, raw in enumerate(mission["items"]):
        where = f"{path}: mission.items[{k}]"
        if not isinstance(raw, dict):
            raise MissionFileError(f"{where}: expected an object")
        if raw.get("type") == "SimpleItem":
            items.append(_simple_item(where, raw))
        elif raw.get("type") == "ComplexItem":
            items.extend(_complex_items(where, raw))
        else:
            raise MissionFileError(f"{where}.type: {raw.get('type')!r} is neither SimpleItem nor ComplexItem")
    return MissionPlan(home, items)


def _simple_item(where: str, raw) -> PlannedItem:
    if not isinstance(raw, dict):
        raise MissionFileError(f"{where}: expected an object")
    for key in ("command", "frame", "params"):
        if key not in raw:
            raise MissionFileError(f"{where}: missing '{key}'")
    params = raw["params"]
    if not isinstance(params, list) or len(params) != 7:
        raise MissionFileError(f"{where}.params: expected 7 values")
    # QGC writes null for "not set" (NaN); positions must be real numbers.
    p = [math.nan if v is None else _finite(f"{where}.params", v) for v in params[:4]]
    lat, lon, alt = (_finite(f"{where}.params[{i}]", params[i] if params[i] is not None else 0.0) for i in (4, 5, 6))
    command, frame = raw["command"], raw["frame"]
    if not isinstance(command, int) or not isinstance(frame, int) or isinstance(command, bool):
        raise MissionFileError(f"{where}: command and frame must be integers")
    if frame != 2:
        _checked_position(where, lat, lon)
    return PlannedItem(command, frame, tuple(p), lat, lon, alt, bool(raw.get("autoContinue", True)))


def _complex_items(where: str, raw: dict) -> list:
    kind = raw.get("complexItemType")
    if kind in TRANSECT_STYLE:
        inner = raw.get("TransectStyleComplexItem")
        if not isinstance(inner, dict):
            raise MissionFileError(f"{where}.TransectStyleComplexItem: missing")
        saved = inner.get("Items")
        if not isinstance(saved, list) or not saved:
            raise MissionFileError(f"{where}.TransectStyleComplexItem.Items: expected the {kind}'s items")
        return [_simple_item(f"{where}.TransectStyleComplexItem.Items[{k}]", item) for k, item in enumerate(saved)]
    if kind == "StructureScan":
        def number(field: str, value) -> float:
            return _finite(f"{where}.{field}", value)
        try:
            scan = structure_scan(raw, where, number)
        except ValueError as exc:  # a MissionFileError from number() too
            raise MissionFileError(str(exc)) from None
        if scan.layer_height_m <= 0 or scan.scan_distance_m < 0:
            raise MissionFileError(f"{where}.CameraCalc: layer height must be positive and the scan distance not negative")
        return scan.items()
    raise MissionFileError(f"{where}.complexItemType: {kind!r} not supported (survey, CorridorScan, StructureScan)")


def load_mission(path: Path) -> MissionPlan:
    try:
        text = Path(path).read_text()
    except FileNotFoundError:
        raise MissionFileError(f"{path}: no such file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise MissionFileError(f"{path}: cannot read ({exc})") from None
    if text.lstrip().startswith("QGC WPL"):
        plan = load_waypoints(path, text)
    elif text.lstrip().startswith("{"):
        plan = load_plan(path, text)
    else:
        raise MissionFileError(f"{path}:1: neither a QGroundControl .plan nor a 'QGC WPL 110' file")
    if not plan.items:
        raise MissionFileError(f"{path}: the mission has no items")
    return plan

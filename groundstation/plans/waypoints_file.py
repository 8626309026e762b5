"""Mission Planner's `.waypoints` ("QGC WPL 110"): one tab-separated line per item — index,
current, frame, command, params 1-4, latitude, longitude, altitude, autocontinue — with home as
line 0 (current 1, absolute frame), numbers written as Mission Planner writes them."""
from __future__ import annotations

from pathlib import Path

from .items import FRAME_GLOBAL, NAV_WAYPOINT


def _number(value: float) -> str:
    return f"{value:.8f}" if value == value else "0.00000000"  # MP writes NaN as 0


def waypoints_text(home: tuple, items: list) -> str:
    lines = ["QGC WPL 110",
             "\t".join(["0", "1", str(FRAME_GLOBAL), str(NAV_WAYPOINT)] + [_number(0.0)] * 4
                       + [_number(home[0]), _number(home[1]), f"{home[2]:.6f}", "1"])]
    for index, it in enumerate(items, start=1):
        lines.append("\t".join([str(index), "0", str(it.frame), str(it.command)]
                               + [_number(p) for p in it.params]
                               + [_number(it.lat_deg), _number(it.lon_deg), f"{it.alt_m:.6f}",
                                  str(int(it.autocontinue))]))
    return "\r\n".join(lines) + "\r\n"


def write_waypoints(path: Path, home: tuple, items: list) -> None:
    Path(path).write_bytes(waypoints_text(home, items).encode())

"""A mission with a waypoint at a height above terrain (MAV_FRAME_GLOBAL_TERRAIN_ALT, and its _INT
form), on a vehicle with no terrain data: TERRAIN_ENABLE at its default and no ground station
serving terrain tiles, as a test bench usually is.

Per frame, from a fresh boot: upload takeoff (relative), the terrain waypoint 20 m north, a
relative waypoint, land; try to arm in GUIDED; MISSION_START; watch 15 s. Facts: the upload's
result, the arm's COMMAND_ACK and the texts it brings, whether the vehicle armed, MISSION_START's
result, the texts (but the periodic PreArm reports) and items reached while watched, and
whether it moved.
"""
from __future__ import annotations

import math

from ..client import mav
from ..facts import Trace
from .mission_navgeo import ALT_M, Flight, _boot
from .missions import upload
from .states import GUIDED
from .surface_mission import Geometry
from .texts import said

AREA = "mission_terrain"
REL = mav.MAV_FRAME_GLOBAL_RELATIVE_ALT
FRAMES = {"terrain_alt": mav.MAV_FRAME_GLOBAL_TERRAIN_ALT, "terrain_alt_int": mav.MAV_FRAME_GLOBAL_TERRAIN_ALT_INT}
WATCH_S = 15.0


def _items(geo: Geometry, frame: int) -> list[tuple]:
    return [(mav.MAV_CMD_NAV_TAKEOFF, REL, 0, 0, 0, 0, 0, 0, ALT_M),
            (mav.MAV_CMD_NAV_WAYPOINT, frame, 0, 0, 0, 0, *geo.latlon((20.0, 0.0)), ALT_M),
            (mav.MAV_CMD_NAV_WAYPOINT, REL, 0, 0, 0, 0, *geo.latlon((0.0, 20.0)), ALT_M),
            (mav.MAV_CMD_NAV_LAND, REL, 0, 0, 0, 0, 0, 0, 0.0)]


def _try(trace: Trace, client, frame: int) -> None:
    pos0 = client.last["GLOBAL_POSITION_INT"]
    geo = Geometry(pos0.lat, pos0.lon)
    trace.fact("upload", upload(client, _items(geo, frame)))
    client.set_mode(GUIDED)
    client.texts.clear()
    trace.fact("arm.result", client.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1))
    client.idle(1.0)
    trace.fact("arm.said", said([text for _, _, text in client.texts if not text.startswith("PreArm")]))
    trace.fact("armed", client.armed)
    client.log.clear()
    client.logging = True
    start = client.now_ms
    trace.fact("start", client.command(mav.MAV_CMD_MISSION_START))
    client.idle(WATCH_S)
    client.logging = False
    flight = Flight(geo, list(client.log))
    trace.fact("said", said([text for _, text in flight.texts if not text.startswith("PreArm")]))
    trace.fact("reached", [m.seq for _, m in flight.of("MISSION_ITEM_REACHED")])
    trace.fact("moved_over_2m", max((math.hypot(*p[1]) for p in flight.positions if p[0] >= start), default=0.0) > 2.0)


def run(target) -> dict[str, Trace]:
    traces: dict[str, Trace] = {}
    try:
        for name, frame in FRAMES.items():
            client = _boot(target)
            _try(traces.setdefault(name, Trace()), client, frame)
    finally:
        target.close()
    return traces

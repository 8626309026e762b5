"""The do-items of issue 29 measured where surface_mission's one-item facts cannot see them.

speed_mid_leg  AUTO cruising a 200 m leg north at WPNAV_SPEED; DO_CHANGE_SPEED 3 m/s sent as a
               command 40 m along it: the speed before, and 2 s and 6 s after (ArduCopter
               re-plans the leg in flight, SCurve::set_speed_max).
roi_two_legs   DO_SET_ROI_LOCATION 40 m west of the start, then legs north and east: the heading
               in the middle of each leg (the nose stays on the point leg after leg), and after
               DO_SET_ROI_NONE in the middle of a last leg east (the default heading again).
jump_tag_cmd   DO_JUMP_TAG sent as a command while AUTO flies to a far waypoint: its result and
               the item current after it (the one after the tag).
"""
from __future__ import annotations

import math

from ..client import Client, mav
from ..facts import Tol, Trace
from .missions import upload
from .states import GUIDED
from .surface_mission import ALT_M, Geometry, item

AREA = "mission_doitems"
LIMIT_S = 90.0
HEADING = Tol(abs=15.0, why="yaw still settling and the bearing changing along the leg: a few degrees; "
                            "an ROI kept or lost differs by 90")
SPEED = Tol(abs=0.8, why="speed within half a metre per second of the plan; the old and the new speed "
                         "differ by several m/s")
STREAMS_US = {mav.MAVLINK_MSG_ID_MISSION_CURRENT: 100_000, mav.MAVLINK_MSG_ID_GLOBAL_POSITION_INT: 100_000}


def _start(client: Client, items: list) -> Geometry:
    client.request_streams(2)
    for msg_id, interval in STREAMS_US.items():
        client.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, msg_id, interval)
    client.wait(lambda: "GLOBAL_POSITION_INT" in client.last, 10, what="position")
    return Geometry(client.last["GLOBAL_POSITION_INT"].lat, client.last["GLOBAL_POSITION_INT"].lon)


def _fly(client: Client, items: list, trace: Trace) -> None:
    trace.fact("upload", upload(client, items))
    client.set_mode(GUIDED)
    client.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    client.try_wait(lambda: client.armed, 10)
    trace.fact("start", client.command(mav.MAV_CMD_MISSION_START))


def _here(client: Client, geo: Geometry) -> tuple[float, float, float, float]:
    """(north, east, groundspeed, heading in degrees) from the last GLOBAL_POSITION_INT."""
    m = client.last["GLOBAL_POSITION_INT"]
    n, e = geo.ne(m.lat, m.lon)
    return n, e, math.hypot(m.vx, m.vy) / 100.0, (m.hdg / 100.0) % 360.0


def speed_mid_leg(client: Client, trace: Trace) -> None:
    geo = _start(client, [])
    items = [item(mav.MAV_CMD_NAV_TAKEOFF, geo, alt=ALT_M), item(mav.MAV_CMD_NAV_WAYPOINT, geo, at=(0.5, 0.0), alt=ALT_M),
             item(mav.MAV_CMD_NAV_WAYPOINT, geo, at=(200.0, 0.0), alt=ALT_M), item(mav.MAV_CMD_NAV_LAND, geo)]
    _fly(client, items, trace)
    client.wait(lambda: _here(client, geo)[0] > 40.0, LIMIT_S, what="40 m along the leg")
    trace.fact("speed_before_ms", round(_here(client, geo)[2], 1), SPEED)
    trace.fact("change", client.command(mav.MAV_CMD_DO_CHANGE_SPEED, 1, 3, -1))
    client.idle(2.0)
    trace.fact("speed_2s_ms", round(_here(client, geo)[2], 1), SPEED)
    client.idle(4.0)
    trace.fact("speed_6s_ms", round(_here(client, geo)[2], 1), SPEED)


def roi_two_legs(client: Client, trace: Trace) -> None:
    geo = _start(client, [])
    wp = lambda n, e: item(mav.MAV_CMD_NAV_WAYPOINT, geo, at=(n, e), alt=ALT_M)  # noqa: E731
    items = [item(mav.MAV_CMD_NAV_TAKEOFF, geo, alt=ALT_M), wp(0.5, 0.0),
             item(mav.MAV_CMD_DO_SET_ROI_LOCATION, geo, at=(0.0, -40.0)), wp(30.0, 0.0), wp(30.0, 30.0),
             item(mav.MAV_CMD_DO_SET_ROI_NONE, geo), wp(30.0, 70.0), item(mav.MAV_CMD_NAV_LAND, geo)]
    _fly(client, items, trace)
    client.wait(lambda: _here(client, geo)[0] > 15.0, LIMIT_S, what="the middle of the leg north")
    trace.fact("heading_leg_north_deg", round(_here(client, geo)[3]), HEADING)
    client.wait(lambda: _here(client, geo)[1] > 15.0, LIMIT_S, what="the middle of the leg east")
    trace.fact("heading_leg_east_deg", round(_here(client, geo)[3]), HEADING)
    client.wait(lambda: _here(client, geo)[1] > 50.0, LIMIT_S, what="the middle of the last leg")
    trace.fact("heading_after_none_deg", round(_here(client, geo)[3]), HEADING)


def jump_tag_cmd(client: Client, trace: Trace) -> None:
    geo = _start(client, [])
    items = [item(mav.MAV_CMD_NAV_TAKEOFF, geo, alt=ALT_M), item(mav.MAV_CMD_NAV_WAYPOINT, geo, at=(80.0, 0.0), alt=ALT_M),
             item(mav.MAV_CMD_JUMP_TAG, geo, (4, 0, 0, 0)), item(mav.MAV_CMD_NAV_WAYPOINT, geo, at=(0.0, 20.0), alt=ALT_M),
             item(mav.MAV_CMD_NAV_LAND, geo)]
    _fly(client, items, trace)
    client.wait(lambda: client.last["MISSION_CURRENT"].seq == 2, LIMIT_S, what="the far waypoint current")
    trace.fact("jump", client.command(mav.MAV_CMD_DO_JUMP_TAG, 4))
    trace.fact("missing_tag", client.command(mav.MAV_CMD_DO_JUMP_TAG, 9))
    client.idle(2.0)
    trace.fact("current_after", client.last["MISSION_CURRENT"].seq)


PROBES = {"speed_mid_leg": speed_mid_leg, "roi_two_legs": roi_two_legs, "jump_tag_cmd": jump_tag_cmd}


def run(target) -> dict[str, Trace]:
    traces = {}
    try:
        for name, probe in PROBES.items():
            client = target.boot()
            trace = traces[name] = Trace()
            probe(client, trace)
    finally:
        target.close()
    return traces

"""A mission interrupted and resumed with DO_SET_RESUME_REPEAT_DIST (issue 29): ArduCopter's
AP_Mission flies back over the last metres flown before it goes on.

The mission: takeoff 10 m, DO_SET_RESUME_REPEAT_DIST, waypoint A (20 m north), B (20 m north, 40 m
east), C (40 m east), land. On the leg A-B, once 25 m east, the ground station switches to LOITER,
waits 4 s and switches back to AUTO. Facts: the texts from the interruption on, the items reached,
MISSION_CURRENT as it changed, how far back east the vehicle went after the resume (the rewound
point: 15 m east with 10 m, A itself with 50 m, no rewind at all with 0) and where it was left.
"""
from __future__ import annotations

from ..client import mav
from ..facts import Tol, Trace
from .surface_mission import ALT_M, STREAMS_US, Geometry, boot_watched, held_seqs, item
from .missions import upload
from .states import GUIDED
from .texts import said

AREA = "mission_resume"
AUTO, LOITER = 3, 5
A, B, C = (20.0, 0.0), (20.0, 40.0), (0.0, 40.0)
LEFT_AT_EAST_M = 25.0
LOITER_S = 4.0

PROBES = {"repeat_10m": 10, "repeat_50m": 50, "repeat_0m": 0}  # probe -> DO_SET_RESUME_REPEAT_DIST's metres

TOL_M = Tol(abs=1.5, why="positions read at 10 Hz beats while flying up to 5 m/s; a rewind not flown differs by 10 m")


def fly(client, repeat_m: int, trace: Trace) -> None:
    pos0 = client.last["GLOBAL_POSITION_INT"]
    geo = Geometry(pos0.lat, pos0.lon)
    items = [item(mav.MAV_CMD_NAV_TAKEOFF, geo, alt=ALT_M),
             item(mav.MAV_CMD_DO_SET_RESUME_REPEAT_DIST, geo, (repeat_m, 0, 0, 0)),
             item(mav.MAV_CMD_NAV_WAYPOINT, geo, at=A, alt=ALT_M),
             item(mav.MAV_CMD_NAV_WAYPOINT, geo, at=B, alt=ALT_M),
             item(mav.MAV_CMD_NAV_WAYPOINT, geo, at=C, alt=ALT_M),
             item(mav.MAV_CMD_NAV_LAND, geo, at=C)]
    trace.fact("upload", upload(client, items))
    client.set_mode(GUIDED)
    client.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    client.try_wait(lambda: client.armed, 10)
    client.command(mav.MAV_CMD_MISSION_START)

    def east():
        p = client.last["GLOBAL_POSITION_INT"]
        return geo.ne(p.lat, p.lon)[1]
    client.wait(lambda: east() >= LEFT_AT_EAST_M, 60, what="the leg A-B past 25 m east")
    left_east = east()
    client.log.clear()
    client.logging = True
    client.set_mode(LOITER)
    client.idle(LOITER_S)
    client.set_mode(AUTO)
    client.wait(lambda: not client.armed, 120, what="the landing")
    client.logging = False
    # up to the disarm (its text comes first; the heartbeat up to a second later): a disarmed
    # vehicle's mission resets to its first item, reported or not before the log ends by timing
    log = client.log
    disarmed = next((k for k, (_, m) in enumerate(log)
                     if (m.get_type() == "STATUSTEXT" and m.text.startswith("Disarming"))
                     or (m.get_type() == "HEARTBEAT" and m.get_srcComponent() == 1
                         and not m.base_mode & mav.MAV_MODE_FLAG_SAFETY_ARMED)), len(log))
    log = log[:disarmed]

    def of(kind):
        return [m for _, m in log if m.get_type() == kind]

    trace.fact("said", said([m.text for m in of("STATUSTEXT")]))
    trace.fact("reached", [m.seq for m in of("MISSION_ITEM_REACHED")])
    trace.fact("current_seq_seen", held_seqs([m.seq for m in of("MISSION_CURRENT")]))
    trace.fact("left_east_m", round(left_east, 1), TOL_M)
    # after the resume: the east-most point is the loiter's, then the rewind flies west
    track = [geo.ne(m.lat, m.lon) for m in of("GLOBAL_POSITION_INT")]
    trace.fact("least_east_after_m", round(min(e for _, e in track), 1) if track else None, TOL_M)


def run(target) -> dict[str, Trace]:
    traces: dict[str, Trace] = {}
    try:
        for probe, repeat_m in PROBES.items():
            fly(boot_watched(target, STREAMS_US), repeat_m, traces.setdefault(probe, Trace()))
    finally:
        target.close()
    return traces

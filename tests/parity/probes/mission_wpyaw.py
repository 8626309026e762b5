"""Where AUTO points the nose on waypoint legs and in a mission's RTL, for each WP_YAW_BEHAVIOR.

One mission per value (0 never turns, 1 faces the next waypoint and home, 2 the same but holds
its heading in the RTL, 3 looks along the ground course), flown from a fresh boot with the value
set by PARAM_SET: takeoff 10 m; a waypoint 20 m east; one 20 m north-east of it (a 45° corner);
RTL. Facts per probe: the heading at arming, in the middle of each leg, at the corner (the
sample nearest the first waypoint), in the middle of the way home, and during the last metres of
the descent over home; the seconds from the RTL item's start to the landing; texts and items.

Headings are degrees in (-180, 180] (none of them near the wrap).
"""
from __future__ import annotations

import math

from ..client import mav
from ..facts import Tol, Trace
from .mission_navgeo import ALT_M, TAKEOFF, WP, Flight, _boot, _fly, mission_facts

AREA = "mission_wpyaw"
RTL = mav.MAV_CMD_NAV_RETURN_TO_LAUNCH
FIRST, SECOND = (0.0, 20.0), (20.0, 40.0)
PLAN = [
    (TAKEOFF, (0, 0, 0, 0), None, ALT_M),
    (WP, (0, 0, 0, 0), FIRST, ALT_M),
    (WP, (0, 0, 0, 0), SECOND, ALT_M),
    (RTL, (0, 0, 0, 0), None, 0.0),
]
BEHAVIOURS = (0, 1, 2, 3)

TOL_LEG = Tol(abs=6.0, why="mid-leg heading: both face the leg's direction, or hold; within the "
                           "heading's settling and the track's wobble")
TOL_CORNER = Tol(abs=20.0, why="the heading while passing the corner's point, turning at some 30-90 deg/s: "
                               "a 10 Hz sample and a corner cut a little earlier or later differ by tens of "
                               "degrees; facing the old leg, the new one or holding differ by 45 or more")
TOL_RTL = Tol(abs=8.0, why="heading on the way home or in the descent: facing home, the armed heading or "
                           "the last leg's differ by 45 degrees or more")
TOL_RTL_S = Tol(abs=4.0, rel=0.12, why="RTL climbs, returns, loiters RTL_LOIT_TIME (and turns back to the "
                                       "armed heading where it does) and descends: each stage at the "
                                       "controllers' own pace")


def _deg(hdg: int) -> float:
    """GLOBAL_POSITION_INT's hdg (centidegrees 0..35999) as degrees in (-180, 180]."""
    d = hdg / 100.0
    return round(d - 360.0 if d > 180.0 else d, 1)


def _median(values: list[float]) -> float | None:
    if not values:
        return None
    s = sorted(values)
    return s[len(s) // 2]


def _along(p: tuple[float, float], a: tuple[float, float], b: tuple[float, float]) -> float:
    """Where p is along a-b (0 at a, 1 at b)."""
    ax, ay = b[0] - a[0], b[1] - a[1]
    return ((p[0] - a[0]) * ax + (p[1] - a[1]) * ay) / (ax * ax + ay * ay)


def _mid_heading(positions: list, a: tuple[float, float], b: tuple[float, float]) -> float | None:
    """The median heading while the vehicle is 35-65 % of the way from a to b."""
    return _median([_deg(p[4]) for p in positions if p[4] != 65535 and 0.35 <= _along(p[1], a, b) <= 0.65])


def _facts(trace: Trace, flight: Flight) -> None:
    positions = flight.positions
    known = [p for p in positions if p[4] != 65535]
    trace.fact("heading_start_deg", _deg(known[0][4]) if known else None, TOL_LEG)
    leg1, leg2, rtl = flight.window(2), flight.window(3), flight.window(4)
    if leg1 is None or leg2 is None or rtl is None:
        return
    trace.fact("heading_leg1_deg", _mid_heading(flight.during(*leg1), (0.0, 0.0), FIRST), TOL_LEG)
    trace.fact("heading_leg2_deg", _mid_heading(flight.during(*leg2), FIRST, SECOND), TOL_LEG)
    near = [p for p in flight.during(leg1[0], leg2[1]) if p[4] != 65535]
    corner = min(near, key=lambda p: math.hypot(p[1][0] - FIRST[0], p[1][1] - FIRST[1]), default=None)
    trace.fact("heading_corner_deg", _deg(corner[4]) if corner else None, TOL_CORNER)
    home_run = flight.during(*rtl)
    trace.fact("heading_return_deg", _mid_heading(home_run, SECOND, (0.0, 0.0)), TOL_RTL)
    low = [_deg(p[4]) for p in home_run if p[4] != 65535 and p[2] < 3.0 and math.hypot(*p[1]) < 3.0]
    trace.fact("heading_descent_deg", _median(low), TOL_RTL)
    disarmed = next((t for t, text in flight.texts if text == "Disarming motors"), None)
    trace.fact("rtl_seconds", None if disarmed is None else round((disarmed - rtl[0]) / 1000.0, 1), TOL_RTL_S)


def run(target) -> dict[str, Trace]:
    traces: dict[str, Trace] = {}
    try:
        for behaviour in BEHAVIOURS:
            client = _boot(target)
            trace = traces[f"wp_yaw_{behaviour}"] = Trace()
            trace.fact("set_WP_YAW_BEHAVIOR", client.set_param("WP_YAW_BEHAVIOR", float(behaviour)))
            geo, (result, log) = _fly(client, PLAN)
            flight = Flight(geo, log)
            mission_facts(trace, flight, result)
            _facts(trace, flight)
    finally:
        target.close()
    return traces

"""AUTO's timed and conditional mission items measured beyond the surface table (issue 29): how
long a delay holds, when a condition lets the next "do" item go, where CONDITION_YAW turns the nose
and how long the turn takes, what NAV_ATTITUDE_TIME, NAV_SCRIPT_TIME and NAV_GUIDED_ENABLE do to
the vehicle, and how NAV_PAYLOAD_PLACE descends, waits and climbs back with no gripper.

Each probe flies surface_mission's mission (takeoff 10 m, waypoint A 20 m north, the item under
test, waypoint B 20 m north 20 m east, land) with its own parameters, watched as that area
watches it (its Window), and reads from the same log: the seconds between MISSION_ITEM_REACHED
for A and for the item (a condition's wait; a delay's hold), the distance to B when a condition
was met, the heading when the item ended and at B, the lowest and highest altitude while the item
was current, the horizontal drift while it was current, and the texts with their figures masked
(a thrust figure is each airframe's own).
"""
from __future__ import annotations

import math
import re

from ..client import mav
from ..facts import Tol, Trace
from .missions import REL
from .surface_mission import (ALT_M, LEG_B, OFF_PATH, STREAMS_US, Geometry, Spec, _spec, boot_watched, build,
                              fly_mission, held_seqs)
from .texts import said

AREA = "mission_navtime"

# probe -> (the command, its spec, extra facts watched)
PROBES: dict[str, tuple[str, Spec]] = {
    "nav_delay_5s": ("MAV_CMD_NAV_DELAY", _spec(5, -1, -1, -1)),
    "cond_delay_4s": ("MAV_CMD_CONDITION_DELAY", _spec(4)),
    "cond_distance_8m": ("MAV_CMD_CONDITION_DISTANCE", _spec(8)),
    # to south at the default rate, the shorter way (absolute)
    "cond_yaw_abs_south": ("MAV_CMD_CONDITION_YAW", _spec(180, 0, 0, 0)),
    # by 90 degrees counter-clockwise at 30 deg/s (relative)
    "cond_yaw_rel_ccw_90": ("MAV_CMD_CONDITION_YAW", _spec(90, 30, -1, 1)),
    # 4 s level, nose to 270, 1 m/s climb
    "attitude_time_4s": ("MAV_CMD_NAV_ATTITUDE_TIME", _spec(4, 0, 0, 270, x=1)),
    "script_time_4s": ("MAV_CMD_NAV_SCRIPT_TIME", _spec(0, 4, 0, 0)),
    # guided enable off: nothing to hand over, the mission goes on
    "guided_enable_off": ("MAV_CMD_NAV_GUIDED_ENABLE", _spec(0)),
    "guided_enable_on": ("MAV_CMD_NAV_GUIDED_ENABLE", _spec(1, hold_s=6.0)),
    # after DO_GUIDED_LIMITS of 5 s (alt 0..0 and horizontal 0: no other limit): ends at its timeout
    "guided_enable_limited_5s": ("MAV_CMD_NAV_GUIDED_ENABLE", _spec(1, limit_s=90.0)),
    "payload_place": ("MAV_CMD_NAV_PAYLOAD_PLACE", _spec(0, at=OFF_PATH, alt=ALT_M, limit_s=120.0)),
    # at most 4 m down: it climbs back without touching down
    "payload_place_4m": ("MAV_CMD_NAV_PAYLOAD_PLACE", _spec(4, limit_s=120.0)),
}

LIMITED = {"guided_enable_limited_5s": (5, 0, 0, 0)}  # probe -> DO_GUIDED_LIMITS' params 1..4

TOL_S = Tol(abs=1.0, rel=0.1, why="a timer's start and end are read at the 10 Hz stream's beats and the "
                                  "items around it end where each controller counts a point reached")
TOL_TURN_S = Tol(abs=1.5, rel=0.2, why="a turn's end waits for the heading to settle within 2 degrees: the yaw "
                                       "loops' settling differs; a turn at the wrong rate differs by seconds")
TOL_DIST = Tol(abs=1.5, why="read at 10 Hz beats while flying up to 5 m/s")
TOL_HEADING = Tol(abs=10.0, why="the nose still settling by a few degrees; a turn the wrong way differs by 90 or more")
TOL_ALT = Tol(abs=1.0, why="altitude overshoot and where a climb or touchdown counts as done differ by under a metre")
TOL_DRIFT = Tol(abs=2.0, why="holding a point or an attitude drifts a little either way; flying off is metres more")
TOL_PLACE_S = Tol(abs=4.0, rel=0.15, why="the descent's speed-up, its thrust calibration and the touchdown's "
                                         "detection differ by seconds between airframes; the steps are the same")

NUMBER = re.compile(r"-?\d+\.\d+|(?<=: )-?\d+$")


def masked(texts: list[str]) -> list[str]:
    """The texts with decimal figures as '#', and a continuation chunk (a STATUSTEXT longer than 50
    characters goes in pieces; only figures overflow here) joined to its text."""
    joined: list[str] = []
    for text in texts:
        if joined and re.fullmatch(r"\d+", text) and joined[-1].endswith("."):
            joined[-1] += text
        else:
            joined.append(text)
    return [NUMBER.sub("#", t) for t in joined]


def fly(client, probe: str, command: str, spec: Spec, trace: Trace) -> None:
    pos0 = client.last["GLOBAL_POSITION_INT"]
    geo = Geometry(pos0.lat, pos0.lon)
    items, seq, b_seq = build(command, spec, geo)
    if probe in LIMITED:  # DO_GUIDED_LIMITS just before the command
        items.insert(seq - 1, (mav.MAV_CMD_DO_GUIDED_LIMITS, REL, *LIMITED[probe], 0, 0, 0.0))
        seq, b_seq = seq + 1, b_seq + 1
    uploaded, _, log = fly_mission(client, items, spec, seq)
    trace.fact("upload", uploaded)

    def of(kind):
        return [(t, m) for t, m in log if m.get_type() == kind]

    reached = of("MISSION_ITEM_REACHED")
    currents = of("MISSION_CURRENT")
    trace.fact("reached", [m.seq for _, m in reached])
    trace.fact("current_seq_seen", held_seqs([m.seq for _, m in currents]))
    trace.fact("said", masked(said([m.text for _, m in of("STATUSTEXT")])))

    positions = [(t, geo.ne(m.lat, m.lon), m.relative_alt / 1000.0, m.hdg) for t, m in of("GLOBAL_POSITION_INT")]
    end_ms = log[-1][0] if log else client.now_ms
    at_a = next((t for t, m in reached if m.seq == seq - 1), None)
    at_item = next((t for t, m in reached if m.seq == seq), None)
    # the item current: from its first beat to the first beat of another. An item that ends at
    # once (NAV_GUIDED_ENABLE off) is current for one loop of the vehicle's (2.5 ms on ArduCopter,
    # a 10 ms tick on Firefly): a single beat that happens to fall in it says nothing, so an item
    # seen in one beat only counts as passed through.
    beats = [t for t, m in currents if m.seq == seq]
    first = beats[0] if len(beats) > 1 else None
    last = next((t for t, m in currents if first is not None and t > first and m.seq != seq), end_ms)
    during = [p for p in positions if first is not None and first <= p[0] <= last]

    def heading_at(t_ms):
        known = [p[3] for p in positions if p[0] <= t_ms and p[3] != 65535]
        return round(known[-1] / 100.0) % 360 if known else None

    is_condition = command.startswith("MAV_CMD_CONDITION")
    if is_condition:
        # a condition is met when its item is reported reached; A's report starts it
        trace.fact("seconds_to_met", round((at_item - at_a) / 1000.0, 1) if at_item and at_a else None,
                   TOL_TURN_S if command.endswith("YAW") else TOL_S)
        if at_item is not None:
            here = [p for p in positions if p[0] <= at_item]
            if here and command.endswith("DISTANCE"):
                ne = here[-1][1]
                trace.fact("distance_to_b_when_met_m", round(math.hypot(LEG_B[0] - ne[0], LEG_B[1] - ne[1]), 1),
                           TOL_DIST)
            if command.endswith("YAW"):
                trace.fact("heading_when_met_deg", heading_at(at_item), TOL_HEADING)
        at_b = next((t for t, m in reached if m.seq == b_seq), None)
        if command.endswith("YAW") and at_b is not None:
            trace.fact("heading_at_b_deg", heading_at(at_b), TOL_HEADING)
        return
    trace.fact("seconds_current", round((last - first) / 1000.0, 1) if first is not None else None,
               TOL_PLACE_S if "PAYLOAD" in command else TOL_S)
    if during:
        start = during[0][1]
        trace.fact("drift_max_m", round(max(math.hypot(p[1][0] - start[0], p[1][1] - start[1]) for p in during), 1),
                   TOL_DRIFT)
        trace.fact("min_alt_m", round(min(p[2] for p in during), 1), TOL_ALT)
        trace.fact("max_alt_m", round(max(p[2] for p in during), 1), TOL_ALT)
        trace.fact("heading_end_deg", heading_at(last), TOL_HEADING)


def run(target) -> dict[str, Trace]:
    traces: dict[str, Trace] = {}
    try:
        for probe, (command, spec) in PROBES.items():
            fly(boot_watched(target, STREAMS_US), probe, command, spec, traces.setdefault(probe, Trace()))
    finally:
        target.close()
    return traces


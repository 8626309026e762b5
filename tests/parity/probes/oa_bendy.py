"""Object avoidance's BendyRuler (OA_TYPE 1) round fence obstacles, as ArduCopter flies it.

BendyRuler sees the fence (exclusion circles and polygons, inclusion ones, the circle round home)
and the obstacle database fed by a proximity sensor; these probes give it fence obstacles only.
Each probe on a fresh vehicle booted with OA_TYPE 1 and FENCE_ENABLE 1 (the default FENCE_TYPE 7,
FENCE_MARGIN 2, OA_MARGIN_MAX 5), an exclusion fence uploaded, taken off in GUIDED to 10 m, then
sent 100 m north (straight through the obstacle) by a GUIDED position target (GUID_OPTIONS 64, the
waypoint navigator) or a mission. The obstacles lie off the line as in the area `oa` (a 10 m
circle 4 m east, a 20 m square 3 m east), so that one way round is the better.

Facts per flight: the track (every second of vehicle time), its length, the furthest it went off
the line to the goal, the closest it came to the obstacle's boundary, whether it entered it,
whether and when the destination was reached (MISSION_ITEM_REACHED from the start of the leg),
and the texts (BendyRuler says none).

guided_circle          GUIDED round the exclusion circle.
auto_circle            AUTO: takeoff, a waypoint 100 m north, round the circle.
auto_square            the same round the exclusion square.
auto_circle_lookahead  OA_BR_LOOKAHEAD 30 (15 by default): it turns away sooner.
auto_circle_centred    the circle on the line (the two ways round equal), OA_BR_CONT_ANGLE 20 and
                       OA_BR_CONT_RATIO 1.1: whichever side BendyRuler takes, it keeps to it.
rtl_circle             GUIDED (position controller) straight through the circle to 100 m north
                       (FENCE_ACTION 0), then RTL: the return bends round it.
auto_circle_type3      OA_TYPE 3 (Dijkstra with BendyRuler) with no proximity sensor: BendyRuler
                       sees only proximity obstacles then, so Dijkstra's corners round the fence.
oa_type1_set_late      OA_TYPE set to 1 after boot: arming refused until a reboot.
"""
from __future__ import annotations

import math

from ..client import Client
from ..facts import PathTol, Tol, Trace
from .avoid import Recorder
from .booting import each_on_a_fresh_vehicle
from .oa import (ALT_M, CIRCLE, GOAL, SQUARE_OBSTACLE, Obstacle, Reached, _every_second, _fence, _goto, arrival_facts,
                 fly_back, fly_mission, landing_facts, set_late)
from .states import RTL, reach_flying

AREA = "oa_bendy"
FIREFLY_SPEEDUP = "10"  # as the area `oa`: a loaded machine drops ACKs at 20x
BOOT = {"OA_TYPE": 1, "FENCE_ENABLE": 1}
CIRCLE_OBSTACLE = Obstacle(circle=CIRCLE)
CENTRED_OBSTACLE = Obstacle(circle=(50.0, 0.0, 10.0))
PROBES_PARAMS = {
    "guided_circle": {**BOOT, "GUID_OPTIONS": 64},
    "auto_circle": BOOT,
    "auto_square": BOOT,
    "auto_circle_lookahead": {**BOOT, "OA_BR_LOOKAHEAD": 30},
    "auto_circle_centred": {**BOOT, "OA_BR_CONT_ANGLE": 20, "OA_BR_CONT_RATIO": 1.1},
    "rtl_circle": {**BOOT, "FENCE_ACTION": 0},
    "auto_circle_type3": {**BOOT, "OA_TYPE": 3},
    "auto_circle_vertical": {**BOOT, "OA_BR_TYPE": 2},
    "oa_type1_set_late": None,
}

TRACK = PathTol(abs=3.0, why="the bent path flown: each vehicle's own position controller chasing a target "
                             "BendyRuler moves once a second (its thread's phase is each vehicle's own)")
TARGETS = PathTol(abs=4.0, why="BendyRuler's points, each the look-ahead from where the vehicle was at a plan: "
                                "the vehicles' own places then (up to 2.5 m apart, see CLOSEST) and plan phases")
CORNER = PathTol(abs=0.5, points=True, why="Dijkstra's corners, the same geometry on both")
CLOSEST = Tol(abs=1.5, why="how near the track comes to the obstacle: BendyRuler's margin less each vehicle's lag "
                           "behind a target moved once a second. Firefly passes a circle 0.2-0.9 m nearer: its leg "
                           "gathers speed a little sooner (1.5 m further on 5 s after the first plan, 15.4 m against "
                           "13.9 m, measured from ArduCopter's PSCN log), so each plan's bend starts that much nearer")
LENGTH = Tol(abs=6.0, rel=0.05, why="the path's length: the same bend, each vehicle's own turns")
OFF_LINE = Tol(abs=2.0, why="the furthest off the line: how far each swings out round the obstacle")
ARRIVAL = Tol(abs=5.0, rel=0.1, why="the flight time: two position controllers chasing targets moved once a "
                                    "second, and the legs' start and stop")


def _path_length(track) -> float:
    return sum(math.hypot(b[1] - a[1], b[2] - a[2]) for a, b in zip(track, track[1:]))


def _off_line(track, start, goal) -> float:
    """The furthest the track goes from the line start-goal (signed: east of a northward line +)."""
    dn, de = goal[0] - start[0], goal[1] - start[1]
    span = math.hypot(dn, de) or 1.0
    sides = [((p[2] - start[1]) * dn - (p[1] - start[0]) * de) / span for p in track]
    return max(sides, key=abs)


def _flight_facts(trace: Trace, c: Client, rec: Recorder, reached: Reached, start_ms: int, seq: int,
                  obstacle: Obstacle, goal=GOAL) -> None:
    track = rec.since((start_ms - rec.t0_ms) / 1000.0)
    trace.fact("track", _every_second(track), TRACK)
    trace.fact("path_length_m", round(_path_length(track), 1), LENGTH)
    trace.fact("off_line_m", round(_off_line(track, track[0][1:3], goal), 1), OFF_LINE)
    trace.fact("closest_to_obstacle_m", round(min(obstacle.distance(p[1:3]) for p in track), 1), CLOSEST)
    trace.fact("crossed_fence", any(obstacle.inside(p[1:3]) for p in track))
    arrival_facts(c, trace, reached, track, start_ms, seq, goal, ARRIVAL)


def _fly_auto(c: Client, trace: Trace, obstacle: Obstacle, flight_s: float, corners: bool = False) -> None:
    rec, targets, reached, start_ms = fly_mission(c, trace, obstacle.items(c), [GOAL], flight_s)
    if corners:
        trace.fact("corners", targets.corners(GOAL), CORNER)
    else:
        trace.fact("targets", _targets_every_second(targets), TARGETS)
    _flight_facts(trace, c, rec, reached, start_ms, 2, obstacle)


# ----- the probes -----------------------------------------------------------------------------
def guided_circle(c: Client, trace: Trace) -> None:
    _fence(c, trace, CIRCLE_OBSTACLE.items(c))
    rec, reached = Recorder(c), Reached(c)
    with c.listening(rec), c.listening(reached):
        reach_flying(c, ALT_M)
        start_ms = c.now_ms
        _goto(c, *GOAL)
        c.idle(45.0)
    _flight_facts(trace, c, rec, reached, start_ms, 0, CIRCLE_OBSTACLE)


def auto_circle(c: Client, trace: Trace) -> None:
    _fly_auto(c, trace, CIRCLE_OBSTACLE, 45.0)


def auto_square(c: Client, trace: Trace) -> None:
    _fly_auto(c, trace, SQUARE_OBSTACLE, 45.0)


def auto_circle_lookahead(c: Client, trace: Trace) -> None:
    _fly_auto(c, trace, CIRCLE_OBSTACLE, 45.0)


def auto_circle_centred(c: Client, trace: Trace) -> None:
    _fly_auto(c, trace, CENTRED_OBSTACLE, 45.0)


def auto_circle_type3(c: Client, trace: Trace) -> None:
    _fly_auto(c, trace, CIRCLE_OBSTACLE, 45.0, corners=True)


def auto_circle_vertical(c: Client, trace: Trace) -> None:
    rec, _, reached, start_ms = fly_mission(c, trace, CIRCLE_OBSTACLE.items(c), [GOAL], 45.0)
    track = rec.since((start_ms - rec.t0_ms) / 1000.0)
    trace.fact("heights", _heights_every_second(track), PathTol(abs=3.0, why="the climb BendyRuler asks for, "
                                                                             "each vehicle's own"))
    _flight_facts(trace, c, rec, reached, start_ms, 2, CIRCLE_OBSTACLE)


def _targets_every_second(targets) -> list:
    """The POSITION_TARGET_GLOBAL_INT positions, one a second from the first (BendyRuler's points
    while it avoids, the waypoint else)."""
    out, next_s = [], -math.inf
    for t, n, e in targets.seen:
        if t >= next_s:
            out.append([round(n, 1), round(e, 1)])
            next_s = t + 1.0
    return out


def _heights_every_second(track) -> list:
    out, next_s = [], -math.inf
    for p in track:
        if p[0] >= next_s:
            out.append([round(p[0] - track[0][0]), round(p[3], 1)])
            next_s = p[0] + 1.0
    return out


def rtl_circle(c: Client, trace: Trace) -> None:
    """Out through the circle in GUIDED, back round it in RTL: the bend, how near, when it landed."""
    track, _, start_ms, landed_ms = fly_back(c, trace, CIRCLE_OBSTACLE, RTL, 90.0)
    trace.fact("track", _every_second(track), TRACK)
    trace.fact("path_length_m", round(_path_length(track), 1), LENGTH)
    trace.fact("off_line_m", round(_off_line(track, track[0][1:3], (0.0, 0.0)), 1), OFF_LINE)
    trace.fact("closest_to_obstacle_m", round(min(CIRCLE_OBSTACLE.distance(p[1:3]) for p in track), 1), CLOSEST)
    trace.fact("crossed_fence", any(CIRCLE_OBSTACLE.inside(p[1:3]) for p in track))
    landing_facts(c, trace, track, start_ms, landed_ms, "the return's bend")


def oa_type1_set_late(c: Client, trace: Trace) -> None:
    set_late(c, trace, 1)


PROBES = {"guided_circle": guided_circle, "auto_circle": auto_circle, "auto_square": auto_square,
          "auto_circle_lookahead": auto_circle_lookahead, "auto_circle_centred": auto_circle_centred,
          "rtl_circle": rtl_circle, "auto_circle_type3": auto_circle_type3,
          "auto_circle_vertical": auto_circle_vertical, "oa_type1_set_late": oa_type1_set_late}


def run(target) -> dict[str, Trace]:
    return each_on_a_fresh_vehicle(target, PROBES, PROBES_PARAMS)

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
auto_circle_vertical   OA_BR_TYPE 2: the vertical search, which no climb gets over the circle with.
auto_pole_proximity    no fence (FENCE_ENABLE 0); a companion (PRX1_TYPE 2) reports a pole of radius
                       POLE[2] 4 m east of the line by OBSTACLE_DISTANCE (72 sectors of 5 degrees,
                       body frame, out to 30 m, 10 Hz of vehicle time): BendyRuler bends round the
                       obstacle database those readings fill (SITL's own lidar, PRX1_TYPE 10, feeds
                       no database).
auto_pole_type3        the same with OA_TYPE 3: BendyRuler round the pole, Dijkstra (no fence:
                       nothing to plan) after.
oa_type1_set_late      OA_TYPE set to 1 after boot: arming refused until a reboot.
"""
from __future__ import annotations

import math

from ..client import Client, mav
from ..facts import PathTol, Tol, Trace
from .avoid import Recorder
from .booting import each_on_a_fresh_vehicle
from .missions import upload
from .nav_flight import ne_alt
from ..targets import wait_armable
from .oa import (ALT_M, CIRCLE, GOAL, SQUARE_OBSTACLE, Obstacle, Reached, Targets, _ask_targets, _every_second, _fence,
                 _goto, _mission, arrival_facts, fly_back, fly_mission, landing_facts, set_late)
from .proximity import _streams
from .states import AUTO, RTL, reach_flying

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
    "auto_pole_proximity": {"OA_TYPE": 1, "FENCE_ENABLE": 0, "PRX1_TYPE": 2, "AVOID_ENABLE": 0},
    "auto_pole_type3": {"OA_TYPE": 3, "FENCE_ENABLE": 0, "PRX1_TYPE": 2, "AVOID_ENABLE": 0},
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


POLE = (50.0, 4.0, 2.0)  # north, east, radius
POLE_RANGE_CM = (20, 3000)
POLE_EVERY_MS = 100


class PoleCompanion:
    """A companion computer (component 196) reporting the pole by OBSTACLE_DISTANCE every
    POLE_EVERY_MS of vehicle time, from the vehicle's last position and heading."""

    def __init__(self, c: Client):
        self.c, self.sent_ms = c, -POLE_EVERY_MS

    def __call__(self, msg) -> None:
        c = self.c
        if c.now_ms - self.sent_ms < POLE_EVERY_MS or "GLOBAL_POSITION_INT" not in c.last or "ATTITUDE" not in c.last \
                or "HOME_POSITION" not in c.last:
            return
        self.sent_ms = c.now_ms
        n, e, _ = ne_alt(c)
        heading = c.last["ATTITUDE"].yaw
        none = POLE_RANGE_CM[1] + 1
        distances = []
        for j in range(72):
            bearing = heading + math.radians(j * 5.0)
            d = _ray_to_circle((n, e), bearing, POLE)
            distances.append(none if d is None or d * 100 > POLE_RANGE_CM[1]
                             else max(round(d * 100), POLE_RANGE_CM[0]))
        link = c.conn.mav
        old = link.srcSystem, link.srcComponent
        link.srcSystem, link.srcComponent = 1, mav.MAV_COMP_ID_OBSTACLE_AVOIDANCE
        try:
            link.obstacle_distance_send(c.now_ms * 1000, mav.MAV_DISTANCE_SENSOR_LASER, distances, 5, *POLE_RANGE_CM,
                                        0.0, 0.0, mav.MAV_FRAME_BODY_FRD)
        finally:
            link.srcSystem, link.srcComponent = old


def _ray_to_circle(p, bearing: float, circle) -> float | None:
    """How far along `bearing` [rad] from p the ray meets the circle, or None."""
    cn, ce, r = circle
    un, ue = math.cos(bearing), math.sin(bearing)
    fn, fe = p[0] - cn, p[1] - ce
    b = fn * un + fe * ue
    disc = b * b - (fn * fn + fe * fe - r * r)
    if disc < 0.0:
        return None
    t = -b - math.sqrt(disc)
    return t if t > 0.0 else None


def auto_pole_proximity(c: Client, trace: Trace) -> None:
    """Booted without streams: the companion feeds the sensor before the pre-arm checks can pass."""
    pole = Obstacle(circle=POLE)
    companion = PoleCompanion(c)
    with c.listening(companion):
        _streams(c)
        wait_armable(c)
    trace.fact("mission_upload", upload(c, _mission(c, [GOAL])))
    rec, targets, reached = Recorder(c), Targets(c), Reached(c)
    with c.listening(rec), c.listening(targets), c.listening(reached), c.listening(companion):
        _ask_targets(c)
        reach_flying(c, ALT_M)
        start_ms = c.now_ms
        c.set_mode(AUTO)
        c.idle(45.0)
    trace.fact("targets", _targets_every_second(targets), TARGETS)
    _flight_facts(trace, c, rec, reached, start_ms, 2, pole)


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
          "auto_circle_vertical": auto_circle_vertical,
          "auto_pole_proximity": auto_pole_proximity, "auto_pole_type3": auto_pole_proximity, "oa_type1_set_late": oa_type1_set_late}


def run(target) -> dict[str, Trace]:
    """Each probe on a fresh vehicle; auto_pole_proximity's booted without waiting to be armable
    (its proximity sensor has no data until the companion starts)."""
    fed_later = {"auto_pole_proximity", "auto_pole_type3"}
    traces = each_on_a_fresh_vehicle(target, {k: v for k, v in PROBES.items() if k not in fed_later}, PROBES_PARAMS)
    traces.update(each_on_a_fresh_vehicle(target, {k: v for k, v in PROBES.items() if k in fed_later}, PROBES_PARAMS,
                                          streams_hz=None))
    return traces

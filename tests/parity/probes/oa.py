"""Object avoidance's path planner round the fence (OA_TYPE 2, Dijkstra), as ArduCopter flies it.

Each probe on a fresh vehicle booted with OA_TYPE 2 and FENCE_ENABLE 1 (the default FENCE_TYPE 7,
OA_MARGIN_MAX 5), an exclusion or inclusion fence uploaded as fence items, taken off in GUIDED to
10 m, then sent 100 m north (straight through the obstacle) by a GUIDED position target or a
mission. The obstacles lie off the line (a 20 m square centred 3 m east, a 10 m circle 4 m east),
so that one way round is the shorter: a fence square across the line gives two equal ways, and
which one each vehicle takes hangs on centimetres.

Facts per flight: the corners of the bent path (the POSITION_TARGET_GLOBAL_INT positions held for
2 s or more, the destination itself left out), the closest the track comes to the obstacle's
boundary, whether it entered it, the track (every second), whether and when the destination was
reached (MISSION_ITEM_REACHED from the target's sending), and the texts.

guided_position        GUID_OPTIONS 0 (ArduCopter's default: the position controller, not the
                       waypoint navigator): no planning, straight through (FENCE_ACTION 0).
guided_wpnav_square    GUID_OPTIONS 64 (waypoint navigation for position targets): round the square.
guided_wpnav_circle    the same round an exclusion circle.
auto_square            a mission: takeoff, a waypoint 100 m north.
auto_two_waypoints     on to a second waypoint 40 m east of the first.
auto_fast_waypoints    OA_OPTIONS 5 (bit 2, fast waypoints): through the corners without stopping.
auto_inclusion_notch   an inclusion polygon with a notch cut across the line from the west.
auto_no_path           the waypoint inside the exclusion square: "Dijkstra: could not find path"
                       (again every 5.1 s), held where it was.
auto_repeated_vertex   the exclusion square uploaded with a vertex twice: "Dijkstra: overlapping polygon
                       points" (again every 5.1 s), held where it was.
guided_no_path         GUIDED targets inside the square (a SET_POSITION_TARGET_GLOBAL_INT, then a
                       DO_REPOSITION), with both GUID_OPTIONS: refused (the fence's check).
rtl_round_square       GUIDED (position controller) straight through the square to 100 m north
                       (FENCE_ACTION 0), then RTL: the return goes round it.
smart_rtl_round_square the same with SMART_RTL, whose way back is the straight line flown.
oa_type_set_late       OA_TYPE set to 2 after boot: arming refused until a reboot.
reposition_beyond_fence without OA, FENCE_ENABLE 1 (FENCE_TYPE 7): DO_REPOSITION with the change-mode
                       flag, disarmed in AUTO and in STABILIZE, to points beyond the circle fence
                       (500 m), above the ceiling (120 m) and inside (50 m): FAILED with the mode
                       kept (the destination is checked before the mode changes), else GUIDED.
"""
from __future__ import annotations

import math

from ..client import Client, mav
from ..facts import PathTol, Tol, Trace
from .avoid import Recorder
from .booting import each_on_a_fresh_vehicle
from .missions import upload
from .nav_flight import EARTH_M_PER_DEG, POSITION_ONLY, SMART_RTL
from .states import AUTO, GUIDED, RTL, STABILIZE, reach_flying
from .texts import said

AREA = "oa"
# Flown at 10x: at 20x, on a loaded machine, the client missed an ACK or a MISSION_ACK in about one
# run of the area in three (its socket overflowing while it waited for a CPU)
FIREFLY_SPEEDUP = "10"
ALT_M = 10.0
GOAL = (100.0, 0.0)
SQUARE = (50.0, 3.0, 10.0)  # centre north, east, half side
CIRCLE = (50.0, 4.0, 10.0)  # centre north, east, radius
NOTCH = ((-20, -40), (40, -40), (40, 20), (60, 20), (60, -40), (120, -40), (120, 40), (-20, 40))
HELD_S = 2.0  # a target held this long is a corner (a stop's target while planning is held under 1 s)
EXCLUSION_POLY = mav.MAV_CMD_NAV_FENCE_POLYGON_VERTEX_EXCLUSION
INCLUSION_POLY = mav.MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION
EXCLUSION_CIRCLE = mav.MAV_CMD_NAV_FENCE_CIRCLE_EXCLUSION
BOOT = {"OA_TYPE": 2, "FENCE_ENABLE": 1}
WPNAV = {**BOOT, "GUID_OPTIONS": 64}
PROBES_PARAMS = {
    "guided_position": {**BOOT, "FENCE_ACTION": 0},
    "guided_wpnav_square": WPNAV,
    "guided_wpnav_circle": WPNAV,
    "auto_square": BOOT,
    "auto_two_waypoints": BOOT,
    "auto_fast_waypoints": {**BOOT, "OA_OPTIONS": 5},
    "auto_inclusion_notch": BOOT,
    "auto_no_path": BOOT,
    "auto_repeated_vertex": BOOT,
    "guided_no_path": BOOT,
    "rtl_round_square": {**BOOT, "FENCE_ACTION": 0},
    "smart_rtl_round_square": {**BOOT, "FENCE_ACTION": 0},
    "oa_type_set_late": None,
    "reposition_beyond_fence": {"FENCE_ENABLE": 1},
}

CORNER = PathTol(abs=0.5, points=True, why="the planner's corners, the same geometry on both: lat/lon rounding "
                                           "and where each vehicle was when it planned (a first leg from there)")
CLOSEST = Tol(abs=0.7, why="how near the track comes to the obstacle: the corners' margin less each navigator's "
                           "overshoot of its stop at a corner")
TRACK = PathTol(abs=2.5, why="the bent path flown: the same corners, each vehicle's own stops and starts at them")
ARRIVAL = Tol(abs=4.0, rel=0.1, why="the flight time: a stop at each corner until the next plan (ArduCopter's "
                                    "planner thread, about once a second at its own phase), two navigators")


def _ne_to_latlon(c: Client, n: float, e: float) -> tuple[int, int]:
    h = c.last["HOME_POSITION"]
    return (h.latitude + round(n / EARTH_M_PER_DEG * 1e7),
            h.longitude + round(e / (EARTH_M_PER_DEG * math.cos(math.radians(h.latitude * 1e-7))) * 1e7))


def _latlon_to_ne(c: Client, lat: int, lon: int) -> tuple[float, float]:
    h = c.last["HOME_POSITION"]
    return ((lat - h.latitude) * 1e-7 * EARTH_M_PER_DEG,
            (lon - h.longitude) * 1e-7 * EARTH_M_PER_DEG * math.cos(math.radians(h.latitude * 1e-7)))


def _polygon(c: Client, command: int, vertices) -> list:
    return [(command, mav.MAV_FRAME_GLOBAL, len(vertices), 0, 0, 0, *_ne_to_latlon(c, n, e), 0) for n, e in vertices]


def _square_vertices(cn: float, ce: float, half: float) -> tuple:
    return (cn - half, ce - half), (cn + half, ce - half), (cn + half, ce + half), (cn - half, ce + half)


def _segment_distance(p, a, b) -> float:
    dn, de = b[0] - a[0], b[1] - a[1]
    span = dn * dn + de * de
    t = 0.0 if span == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * dn + (p[1] - a[1]) * de) / span))
    return math.hypot(p[0] - a[0] - t * dn, p[1] - a[1] - t * de)


def _inside_polygon(p, vertices) -> bool:
    inside, (x, y) = False, p
    for (x1, y1), (x2, y2) in zip(vertices, vertices[1:] + vertices[:1]):
        if (y1 > y) != (y2 > y) and x < (x2 - x1) * (y - y1) / (y2 - y1) + x1:
            inside = not inside
    return inside


class Obstacle:
    """The fence's obstacle in the local frame: a polygon's vertices or a circle."""

    def __init__(self, vertices=None, circle=None):
        self.vertices, self.circle = (list(vertices) if vertices else None), circle

    def items(self, c: Client, inclusion: bool = False) -> list:
        if self.circle is not None:
            n, e, r = self.circle
            return [(EXCLUSION_CIRCLE, mav.MAV_FRAME_GLOBAL, r, 0, 0, 0, *_ne_to_latlon(c, n, e), 0)]
        return _polygon(c, INCLUSION_POLY if inclusion else EXCLUSION_POLY, self.vertices)

    def distance(self, p) -> float:
        if self.circle is not None:
            n, e, r = self.circle
            return abs(math.hypot(p[0] - n, p[1] - e) - r)
        v = self.vertices
        return min(_segment_distance(p, v[i], v[(i + 1) % len(v)]) for i in range(len(v)))

    def inside(self, p) -> bool:
        if self.circle is not None:
            n, e, r = self.circle
            return math.hypot(p[0] - n, p[1] - e) < r
        return _inside_polygon(p, self.vertices)


SQUARE_OBSTACLE = Obstacle(_square_vertices(*SQUARE))


class Targets:
    """POSITION_TARGET_GLOBAL_INT's positions, (vehicle s, north, east) as each came."""

    def __init__(self, c: Client):
        self.c, self.t0_ms, self.seen = c, c.now_ms, []

    def __call__(self, msg) -> None:
        if msg.get_type() == "POSITION_TARGET_GLOBAL_INT" and "HOME_POSITION" in self.c.last:
            self.seen.append(((self.c.now_ms - self.t0_ms) / 1000.0, *_latlon_to_ne(self.c, msg.lat_int, msg.lon_int)))

    def corners(self, goal) -> list:
        """The positions held HELD_S or more, in turn, less the goal."""
        runs: list[list] = []  # [start s, end s, north, east]
        for t, n, e in self.seen:
            if runs and math.hypot(n - runs[-1][2], e - runs[-1][3]) < 0.05:
                runs[-1][1] = t
            else:
                runs.append([t, t, n, e])
        return [[round(n, 1), round(e, 1)] for start, end, n, e in runs
                if end - start >= HELD_S and math.hypot(n - goal[0], e - goal[1]) > 0.5]


class Reached:
    """MISSION_ITEM_REACHED seqs, with the vehicle ms each came at."""

    def __init__(self, c: Client):
        self.c, self.seen = c, []

    def __call__(self, msg) -> None:
        if msg.get_type() == "MISSION_ITEM_REACHED":
            self.seen.append((msg.seq, self.c.now_ms))


def _ask_targets(c: Client) -> None:
    c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_POSITION_TARGET_GLOBAL_INT, 100_000)


def _fence(c: Client, trace: Trace, items: list) -> None:
    c.wait(lambda: "HOME_POSITION" in c.last, 60, what="home")
    trace.fact("fence_upload", upload(c, items, kind=mav.MAV_MISSION_TYPE_FENCE))
    c.idle(1.0)


def _goto(c: Client, n: float, e: float) -> None:
    lat, lon = _ne_to_latlon(c, n, e)
    c.conn.mav.set_position_target_global_int_send(0, 1, 1, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, POSITION_ONLY,
                                                   lat, lon, ALT_M, 0, 0, 0, 0, 0, 0, 0, 0)


def _flight_facts(trace: Trace, c: Client, rec: Recorder, targets: Targets, reached: Reached, start_ms: int,
                  seq: int, obstacle: Obstacle | None, goal=GOAL, inclusion: bool = False) -> None:
    start_s = (start_ms - rec.t0_ms) / 1000.0
    track = rec.since(start_s)
    trace.fact("corners", targets.corners(goal), CORNER)
    if obstacle is not None:
        trace.fact("closest_to_obstacle_m", round(min(obstacle.distance(p[1:3]) for p in track), 1), CLOSEST)
        trace.fact("crossed_fence", any(obstacle.inside(p[1:3]) != inclusion for p in track))
    trace.fact("track", _every_second(track), TRACK)
    arrival_facts(c, trace, reached, track, start_ms, seq, goal, ARRIVAL)
    trace.fact("dijkstra_texts", sum(t.startswith("Dijkstra") for t in c.texts_since(start_ms)),
               Tol(abs=1.0, why="said again every 5 s or so, at each vehicle's planning times"))


def arrival_facts(c: Client, trace: Trace, reached: Reached, track: list, start_ms: int, seq: int, goal,
                  arrival: Tol) -> None:
    """Whether and when (from start_ms) the item `seq` was reached, how far from `goal` the
    track ended, and what was said."""
    at = next((ms for s, ms in reached.seen if s == seq and ms >= start_ms), None)
    trace.fact("reached", at is not None)
    trace.fact("reached_after_s", None if at is None else round((at - start_ms) / 1000.0, 1), arrival)
    end = track[-1]
    trace.fact("end.distance_to_goal_m", round(math.hypot(end[1] - goal[0], end[2] - goal[1]), 1),
               Tol(abs=1.0, why="arrived, or held short of it"))
    trace.fact("said", said(c.texts_since(start_ms)))


def _every_second(track) -> list:
    out, next_s = [], -math.inf
    for p in track:
        if p[0] >= next_s:
            out.append([round(p[1], 1), round(p[2], 1)])
            next_s = p[0] + 1.0
    return out


def _fly_guided(c: Client, trace: Trace, obstacle: Obstacle, flight_s: float) -> None:
    _fence(c, trace, obstacle.items(c))
    rec, targets, reached = Recorder(c), Targets(c), Reached(c)
    with c.listening(rec), c.listening(targets), c.listening(reached):
        _ask_targets(c)
        reach_flying(c, ALT_M)
        start_ms = c.now_ms
        _goto(c, *GOAL)
        c.idle(flight_s)
    _flight_facts(trace, c, rec, targets, reached, start_ms, 0, obstacle)


def _mission(c: Client, points) -> list:
    items = [(mav.MAV_CMD_NAV_TAKEOFF, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, 0, 0, 0, 0, 0, 0, ALT_M)]
    return items + [(mav.MAV_CMD_NAV_WAYPOINT, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, 0, 0, 0, 0,
                     *_ne_to_latlon(c, n, e), ALT_M) for n, e in points]


def _fly_auto(c: Client, trace: Trace, fence: list, points, flight_s: float, obstacle: Obstacle | None,
              inclusion: bool = False) -> None:
    rec, targets, reached, start_ms = fly_mission(c, trace, fence, points, flight_s)
    _flight_facts(trace, c, rec, targets, reached, start_ms, len(points) + 1, obstacle, goal=points[-1],
                  inclusion=inclusion)


def fly_mission(c: Client, trace: Trace, fence: list, points, flight_s: float) -> tuple:
    """`fence` uploaded, a mission of a takeoff and waypoints at `points`, taken off in GUIDED
    and flown in AUTO for flight_s: (the Recorder, Targets and Reached that listened, and the
    vehicle ms AUTO was set at)."""
    _fence(c, trace, fence)
    trace.fact("mission_upload", upload(c, _mission(c, points)))
    rec, targets, reached = Recorder(c), Targets(c), Reached(c)
    with c.listening(rec), c.listening(targets), c.listening(reached):
        _ask_targets(c)
        reach_flying(c, ALT_M)
        start_ms = c.now_ms
        c.set_mode(AUTO)
        c.idle(flight_s)
    return rec, targets, reached, start_ms


# ----- the probes -----------------------------------------------------------------------------
def guided_position(c: Client, trace: Trace) -> None:
    _fly_guided(c, trace, SQUARE_OBSTACLE, 30.0)


def guided_wpnav_square(c: Client, trace: Trace) -> None:
    _fly_guided(c, trace, SQUARE_OBSTACLE, 50.0)


def guided_wpnav_circle(c: Client, trace: Trace) -> None:
    _fly_guided(c, trace, Obstacle(circle=CIRCLE), 40.0)


def auto_square(c: Client, trace: Trace) -> None:
    _fly_auto(c, trace, SQUARE_OBSTACLE.items(c), [GOAL], 50.0, SQUARE_OBSTACLE)


def auto_two_waypoints(c: Client, trace: Trace) -> None:
    _fly_auto(c, trace, SQUARE_OBSTACLE.items(c), [GOAL, (100.0, 40.0)], 65.0, SQUARE_OBSTACLE)


def auto_fast_waypoints(c: Client, trace: Trace) -> None:
    _fly_auto(c, trace, SQUARE_OBSTACLE.items(c), [GOAL], 40.0, SQUARE_OBSTACLE)


def auto_inclusion_notch(c: Client, trace: Trace) -> None:
    notch = Obstacle(NOTCH)
    _fly_auto(c, trace, notch.items(c, inclusion=True), [GOAL], 50.0, notch, inclusion=True)


def auto_no_path(c: Client, trace: Trace) -> None:
    _fly_auto(c, trace, SQUARE_OBSTACLE.items(c), [SQUARE[:2]], 22.0, None)


def auto_repeated_vertex(c: Client, trace: Trace) -> None:
    vertices = _square_vertices(*SQUARE)
    _fly_auto(c, trace, _polygon(c, EXCLUSION_POLY, (vertices[0], *vertices)), [GOAL], 22.0, None)


def guided_no_path(c: Client, trace: Trace) -> None:
    _fence(c, trace, SQUARE_OBSTACLE.items(c))
    inside = SQUARE[:2]
    rec = Recorder(c)
    with c.listening(rec):
        reach_flying(c, ALT_M)
        for options in (0, 64):
            trace.fact(f"options_{options}.set", c.set_param("GUID_OPTIONS", options))
            start_ms = c.now_ms
            _goto(c, *inside)
            c.idle(5.0)
            lat, lon = _ne_to_latlon(c, *inside)
            trace.fact(f"options_{options}.reposition",
                       c.command_int(mav.MAV_CMD_DO_REPOSITION, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, -1, 0, 0,
                                     math.nan, lat, lon, ALT_M))
            c.idle(5.0)
            track = rec.since((start_ms - rec.t0_ms) / 1000.0)
            trace.fact(f"options_{options}.moved_m", round(max(math.hypot(p[1] - track[0][1], p[2] - track[0][2])
                                                               for p in track), 1),
                       Tol(abs=0.5, why="a hover's drift"))
            trace.fact(f"options_{options}.mode", c.mode)
            trace.fact(f"options_{options}.said", said(c.texts_since(start_ms)))


def _return_round(c: Client, trace: Trace, mode: int, flight_s: float) -> None:
    """Out through the square in GUIDED, back round it in `mode`: where it turned, how near it
    came, when it landed."""
    track, targets, start_ms, landed_ms = fly_back(c, trace, SQUARE_OBSTACLE, mode, flight_s)
    trace.fact("corners", targets.corners((0.0, 0.0)), CORNER)
    trace.fact("closest_to_obstacle_m", round(min(SQUARE_OBSTACLE.distance(p[1:3]) for p in track), 1), CLOSEST)
    trace.fact("crossed_fence", any(SQUARE_OBSTACLE.inside(p[1:3]) for p in track))
    trace.fact("track", _every_second(track), TRACK)
    landing_facts(c, trace, track, start_ms, landed_ms, "the return's stops at the corners")


def fly_back(c: Client, trace: Trace, obstacle: Obstacle, mode: int, flight_s: float) -> tuple:
    """Out through `obstacle` (uploaded as the fence) in GUIDED to GOAL, then `mode` until
    disarmed: (the track from the mode change, the targets since, its vehicle ms, the disarm's
    vehicle ms or None)."""
    _fence(c, trace, obstacle.items(c))
    rec, targets = Recorder(c), Targets(c)
    with c.listening(rec), c.listening(targets):
        _ask_targets(c)
        reach_flying(c, ALT_M)
        _goto(c, *GOAL)
        c.idle(25.0)
        start_ms = c.now_ms
        targets.seen.clear()
        c.set_mode(mode)
        c.try_wait(lambda: not c.armed, flight_s)
        landed_ms = c.now_ms if not c.armed else None
    return rec.since((start_ms - rec.t0_ms) / 1000.0), targets, start_ms, landed_ms


def landing_facts(c: Client, trace: Trace, track: list, start_ms: int, landed_ms: int | None, way: str) -> None:
    """When a return landed (`way`: what shapes it besides each vehicle's climb and descent),
    where, and what was said."""
    trace.fact("disarmed_after_s", None if landed_ms is None else round((landed_ms - start_ms) / 1000.0, 1),
               Tol(abs=6.0, rel=0.1, why=f"{way} and each vehicle's climb, descent and touchdown (airframes differ)"))
    trace.fact("end.distance_from_home_m", round(math.hypot(track[-1][1], track[-1][2]), 1),
               Tol(abs=1.5, why="where each lands, within the last point's reach"))
    trace.fact("said", said(c.texts_since(start_ms)))


def rtl_round_square(c: Client, trace: Trace) -> None:
    _return_round(c, trace, RTL, 90.0)


def smart_rtl_round_square(c: Client, trace: Trace) -> None:
    _return_round(c, trace, SMART_RTL, 90.0)


def oa_type_set_late(c: Client, trace: Trace) -> None:
    set_late(c, trace, 2)


def set_late(c: Client, trace: Trace, oa_type: int) -> None:
    """OA_TYPE set after boot, then an arm: refused until a reboot makes the planner."""
    trace.fact("set", c.set_param("OA_TYPE", oa_type))
    c.set_mode(GUIDED)
    c.wait(lambda: c.mode == GUIDED, 5, what="GUIDED")
    since = c.now_ms
    trace.fact("arm", c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1))
    c.idle(1.0)
    trace.fact("said", said(c.texts_since(since)))
    trace.fact("armed", c.armed)


def reposition_beyond_fence(c: Client, trace: Trace) -> None:
    c.wait(lambda: "HOME_POSITION" in c.last, 60, what="home")
    for mode, name in ((AUTO, "auto"), (STABILIZE, "stabilize")):
        for where, (north, alt) in (("beyond_circle", (500.0, ALT_M)), ("above_ceiling", (50.0, 120.0)),
                                    ("inside", (50.0, ALT_M))):
            c.set_mode(mode)
            c.wait(lambda: c.mode == mode, 5, what="the mode")
            lat, lon = _ne_to_latlon(c, north, 0.0)
            trace.fact(f"{name}.{where}.result", c.command_int(mav.MAV_CMD_DO_REPOSITION,
                                                               mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, -1,
                                                               mav.MAV_DO_REPOSITION_FLAGS_CHANGE_MODE, 0, math.nan,
                                                               lat, lon, alt))
            c.fresh_heartbeat()
            trace.fact(f"{name}.{where}.mode", c.mode)


PROBES = {"guided_position": guided_position, "guided_wpnav_square": guided_wpnav_square,
          "guided_wpnav_circle": guided_wpnav_circle, "auto_square": auto_square,
          "auto_two_waypoints": auto_two_waypoints, "auto_fast_waypoints": auto_fast_waypoints,
          "auto_inclusion_notch": auto_inclusion_notch, "auto_no_path": auto_no_path,
          "auto_repeated_vertex": auto_repeated_vertex,
          "guided_no_path": guided_no_path, "rtl_round_square": rtl_round_square,
          "smart_rtl_round_square": smart_rtl_round_square, "oa_type_set_late": oa_type_set_late,
          "reposition_beyond_fence": reposition_beyond_fence}


def run(target) -> dict[str, Trace]:
    return each_on_a_fresh_vehicle(target, PROBES, PROBES_PARAMS)

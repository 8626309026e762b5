"""How AUTO flies NAV_LOITER_TURNS, NAV_LOITER_TO_ALT and NAV_SPLINE_WAYPOINT, measured in flight.

surface_mission tries each command once between two waypoints; this area measures what those
items do with the vehicle, in three missions flown from a fresh boot (armed in GUIDED, started by
MISSION_START, watched until the vehicle lands and disarms or a vehicle-time limit):

  circles   takeoff 10 m; LOITER_TURNS radius 0 here (the circle navigator's radius at boot); 2
            turns of 10 m clockwise round a point 15 m north; 1 turn of 5 m counter-clockwise round
            a point 25 m east of it; 0 turns of 5 m; 1 turn, radius 0, here, 2 m higher; land
  to_alt    takeoff 10 m; LOITER_TO_ALT 20 m north at 20 m; LOITER_TO_ALT here at 6 m; a waypoint;
            land
  splines   takeoff 10 m; spline waypoints round a 20 m square (the middle one 4 m higher), a
            waypoint home; land
  wp_spline   takeoff; a waypoint 20 m north; a spline to 10 m past it, off to the east; a waypoint
              back west of that; land
  rate_param  CIRCLE_RATE set to 10 by PARAM_SET after boot; takeoff; 1 turn of 10 m; land

Per item (facts "itemN.*", N its seq): the seconds from its "Mission: N" text to the next one,
and for a loiter the circling phase's (from its first "starting circle" text) mean radius and spread round the centre it flew,
how far that centre is from the item's point, the turns flown round it (signed: + clockwise seen
from above) and the nose's turns, the seconds between the "starting circle" texts (one turn
each); for a loiter to altitude the height and distance from its point at its end and its fastest
climb and descent; for the splines the largest distance from the straight legs and beyond the
square, and the time round it; for the waypoint before a spline the slowest speed by it.
"""
from __future__ import annotations

import math

from ..client import Client, mav
from ..facts import Tol, Trace
from .missions import upload
from .states import GUIDED
from .surface_mission import Geometry, held_seqs, item
from .texts import said

AREA = "mission_navgeo"
ALT_M = 10.0
LIMIT_S = 260.0
STREAMS_US = {mav.MAVLINK_MSG_ID_MISSION_CURRENT: 100_000, mav.MAVLINK_MSG_ID_GLOBAL_POSITION_INT: 100_000}

TURNS, TO_ALT, SPLINE = mav.MAV_CMD_NAV_LOITER_TURNS, mav.MAV_CMD_NAV_LOITER_TO_ALT, mav.MAV_CMD_NAV_SPLINE_WAYPOINT
WP, TAKEOFF, LAND = mav.MAV_CMD_NAV_WAYPOINT, mav.MAV_CMD_NAV_TAKEOFF, mav.MAV_CMD_NAV_LAND

# (command, params 1-4, (north, east) or None for lat/lon 0, altitude)
MISSIONS: dict[str, list[tuple]] = {
    "circles": [
        (TAKEOFF, (0, 0, 0, 0), None, ALT_M),
        (TURNS, (1, 0, 0, 0), None, ALT_M),
        (TURNS, (2, 0, 10, 0), (15.0, 0.0), ALT_M),
        (TURNS, (1, 0, -5, 0), (15.0, 25.0), ALT_M),
        (TURNS, (0, 0, 5, 0), (0.0, 25.0), ALT_M),
        (TURNS, (1, 0, 0, 0), None, ALT_M + 2.0),
        (LAND, (0, 0, 0, 0), None, 0.0),
    ],
    "to_alt": [
        (TAKEOFF, (0, 0, 0, 0), None, ALT_M),
        (TO_ALT, (0, 0, 0, 0), (20.0, 0.0), 20.0),
        (TO_ALT, (0, 0, 0, 0), None, 6.0),
        (WP, (0, 0, 0, 0), (20.0, 20.0), ALT_M),
        (LAND, (0, 0, 0, 0), None, 0.0),
    ],
    "splines": [
        (TAKEOFF, (0, 0, 0, 0), None, ALT_M),
        (SPLINE, (0, 0, 0, 0), (20.0, 0.0), ALT_M),
        (SPLINE, (0, 0, 0, 0), (20.0, 20.0), ALT_M + 4.0),
        (SPLINE, (0, 0, 0, 0), (0.0, 20.0), ALT_M),
        (WP, (0, 0, 0, 0), (0.0, 0.0), ALT_M),
        (LAND, (0, 0, 0, 0), None, 0.0),
    ],
    # a plain waypoint before a spline: ArduCopter passes it at the speed the spline starts with
    "wp_spline": [
        (TAKEOFF, (0, 0, 0, 0), None, ALT_M),
        (WP, (0, 0, 0, 0), (20.0, 0.0), ALT_M),
        (SPLINE, (0, 0, 0, 0), (30.0, 10.0), ALT_M),
        (WP, (0, 0, 0, 0), (20.0, 20.0), ALT_M),
        (LAND, (0, 0, 0, 0), None, 0.0),
    ],
    # CIRCLE_RATE set after boot: does AUTO's circle take it?
    "rate_param": [
        (TAKEOFF, (0, 0, 0, 0), None, ALT_M),
        (TURNS, (1, 0, 10, 0), (15.0, 0.0), ALT_M),
        (LAND, (0, 0, 0, 0), None, 0.0),
    ],
}
PARAMS_SET = {"rate_param": {"CIRCLE_RATE": 10.0}}  # by PARAM_SET once booted, before the upload
SQUARE = [(0.0, 0.0), (20.0, 0.0), (20.0, 20.0), (0.0, 20.0), (0.0, 0.0)]

TOL_SECONDS = Tol(abs=3.0, rel=0.12, why="the item's time includes flying to its edge or point at the "
                                         "controller's own speed; the circle's rate itself is the same")
TOL_TURN_S = Tol(abs=1.0, rel=0.06, why="one turn at the same angular rate and ramp; texts are read at 10 Hz "
                                        "beats and the ramp starts when the edge counts as reached")
TOL_RADIUS = Tol(abs=0.8, why="the position controller chases a point moving round the circle with no "
                              "velocity fed forward: both fly a little inside it, by their own lag")
TOL_SPREAD = Tol(abs=1.5, why="the first turn starts from the edge as the wp leg left it; a different "
                              "radius differs by metres")
TOL_CENTRE = Tol(abs=1.5, why="centroid of the flown circle; a circle placed elsewhere differs by its radius")
TOL_TURNS = Tol(abs=0.15, why="turns flown from the first 'starting circle' text to the item's end, "
                              "sampled at 10 Hz; a direction or a turn more differs by 1")
TOL_ALT = Tol(abs=1.0, why="where the height counts as reached and its overshoot differ by under a metre")
TOL_DIST = Tol(abs=1.5, why="the point counts as reached within the waypoint radius (2 m)")
TOL_CLIMB = Tol(abs=0.6, rel=0.15, why="peak vertical speed: both are limited by WPNAV_SPEED_UP/DN; how "
                                       "close each gets to it in a short climb differs")
TOL_PASS = Tol(abs=0.8, why="the slowest speed near a waypoint, from 10 Hz samples: passing it and "
                              "stopping at it differ by metres a second")
TOL_OFF = Tol(abs=1.5, rel=0.2, why="the spline's bulge off the straight legs: same curve, the controllers "
                                    "track it within a metre or so")
TOL_TRACK_S = Tol(abs=3.0, rel=0.1, why="time round the square: speed along the curve is limited by the "
                                        "same speeds and accelerations, shaped differently at its ends")


def _boot(target) -> Client:
    return streaming(target.boot())


def streaming(client: Client) -> Client:
    """MISSION_CURRENT and positions at 10 Hz, the rest at 2 Hz."""
    client.request_streams(2)
    for msg_id, interval in STREAMS_US.items():
        client.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, msg_id, interval)
    client.wait(lambda: "MISSION_CURRENT" in client.last and "GLOBAL_POSITION_INT" in client.last,
                10, what="MISSION_CURRENT and position")
    return client


def _fly(client: Client, plan: list[tuple]) -> tuple[Geometry, list]:
    pos0 = client.last["GLOBAL_POSITION_INT"]
    geo = Geometry(pos0.lat, pos0.lon)
    return geo, fly(client, [item(cmd, geo, params, at, alt) for cmd, params, at, alt in plan])


def fly(client: Client, items: list, limit_s: float = LIMIT_S) -> list:
    """Upload, arm, start; [the MISSION_ACK, the log until disarmed after the flight or limit_s]."""
    result = upload(client, items)
    client.set_mode(GUIDED)
    client.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    client.try_wait(lambda: client.armed, 10)
    client.log.clear()
    client.logging = True
    start = client.now_ms
    client.command(mav.MAV_CMD_MISSION_START)
    client.wait(lambda: (client.now_ms - start > 5000 and not client.armed) or client.now_ms - start > limit_s * 1000,
                limit_s + 20, what="the mission's end")
    client.logging = False
    return [result, list(client.log)]


class Flight:
    """The log of one mission, read item by item."""

    def __init__(self, geo: Geometry, log: list):
        self.geo, self.log = geo, log
        self.end_ms = log[-1][0] if log else 0
        self.currents = self.of("MISSION_CURRENT")
        # (time, (north, east), altitude, descent speed, heading, ground speed)
        self.positions = [(t, geo.ne(m.lat, m.lon), m.relative_alt / 1000.0, m.vz / 100.0, m.hdg,
                           math.hypot(m.vx, m.vy) / 100.0) for t, m in self.of("GLOBAL_POSITION_INT")]
        self.texts = [(t, m.text) for t, m in self.of("STATUSTEXT")]

    def of(self, kind: str) -> list:
        return [(t, m) for t, m in self.log if m.get_type() == kind]

    def window(self, seq: int) -> tuple[int, int] | None:
        """From AP_Mission's "Mission: N ..." text starting item N (sent in the tick it starts, so
        more exact than the 10 Hz MISSION_CURRENT beats) to the next such text, or the end."""
        starts = [(t, text) for t, text in self.texts if text.startswith("Mission: ") and text[9:10].isdigit()]
        first = next((i for i, (_, text) in enumerate(starts) if text.split()[1] == str(seq)), None)
        if first is None:
            return None
        last = starts[first + 1][0] if first + 1 < len(starts) else self.end_ms
        return starts[first][0], last

    def texts_of(self, seq: int) -> list[tuple[int, str]]:
        """The texts said while item `seq` ran (after its own "Mission: N" text)."""
        window = self.window(seq)
        if window is None:
            return []
        inside = [(t, text) for t, text in self.texts if window[0] <= t <= window[1]]
        begun = next((i for i, (_, text) in enumerate(inside) if text.startswith(f"Mission: {seq} ")), len(inside))
        following = next((i for i, (_, text) in enumerate(inside) if i > begun and text.startswith("Mission: ")
                          and text[9:10].isdigit()), len(inside))
        return inside[begun + 1:following]

    def during(self, start: int, end: int) -> list:
        return [p for p in self.positions if start <= p[0] <= end]


def _signed_turns(points: list[tuple[float, float]], centre: tuple[float, float]) -> float:
    """Turns round `centre`, + clockwise seen from above (north towards east)."""
    total, prev = 0.0, None
    for n, e in points:
        a = math.atan2(e - centre[1], n - centre[0])
        if prev is not None:
            total += (a - prev + math.pi) % (2 * math.pi) - math.pi
        prev = a
    return total / (2 * math.pi)


def _heading_turns(headings: list[int]) -> float:
    total, prev = 0.0, None
    for h in headings:
        if h == 65535:
            continue
        if prev is not None:
            total += (h - prev + 18000) % 36000 - 18000
        prev = h
    return total / 36000.0


def _timed_window(trace: Trace, flight: Flight, seq: int) -> tuple[int, int] | None:
    """Item seq's window, its length recorded as the fact seconds_current."""
    window = flight.window(seq)
    trace.fact(f"item{seq}.seconds_current", None if window is None else round((window[1] - window[0]) / 1000.0, 1),
               TOL_SECONDS)
    return window


def _circle_facts(trace: Trace, flight: Flight, seq: int, point: tuple[float, float] | None) -> None:
    window = _timed_window(trace, flight, seq)
    if window is None:
        return
    first, last = window
    starts = [t for t, text in flight.texts_of(seq) if text.startswith("Mission: starting circle")]
    trace.fact(f"item{seq}.turn_seconds", [round((b - a) / 1000.0, 1) for a, b in zip(starts, starts[1:])], TOL_TURN_S)
    here = flight.during(first, first + 300)
    origin = here[0][1] if here else (0.0, 0.0)
    # A circle of 0 turns is over in the tick it begins: nothing of it to measure.
    circling = flight.during(starts[0], last) if starts and last - starts[0] >= 1000 else []
    if not circling:
        return
    pts = [p[1] for p in circling]
    centre = (sum(p[0] for p in pts) / len(pts), sum(p[1] for p in pts) / len(pts))
    radii = [math.hypot(p[0] - centre[0], p[1] - centre[1]) for p in pts]
    mean = sum(radii) / len(radii)
    trace.fact(f"item{seq}.radius_mean_m", round(mean, 1), TOL_RADIUS)
    trace.fact(f"item{seq}.radius_spread_m", round(max(radii) - min(radii), 1), TOL_SPREAD)
    ref = point if point is not None else origin
    trace.fact(f"item{seq}.centre_off_m", round(math.hypot(centre[0] - ref[0], centre[1] - ref[1]), 1), TOL_CENTRE)
    trace.fact(f"item{seq}.turns_flown", round(_signed_turns(pts, centre), 2) if mean > 1.0 else 0.0, TOL_TURNS)
    trace.fact(f"item{seq}.nose_turns", round(_heading_turns([p[4] for p in circling]), 2), TOL_TURNS)
    trace.fact(f"item{seq}.alt_end_m", round(circling[-1][2], 1), TOL_ALT)


def _to_alt_facts(trace: Trace, flight: Flight, seq: int, point: tuple[float, float] | None) -> None:
    window = _timed_window(trace, flight, seq)
    if window is None:
        return
    during = flight.during(*window)
    if not during:
        return
    ref = point if point is not None else during[0][1]
    end = during[-1]
    trace.fact(f"item{seq}.alt_end_m", round(end[2], 1), TOL_ALT)
    trace.fact(f"item{seq}.dist_end_m", round(math.hypot(end[1][0] - ref[0], end[1][1] - ref[1]), 1), TOL_DIST)
    trace.fact(f"item{seq}.climb_max_ms", round(max(-p[3] for p in during), 1), TOL_CLIMB)
    trace.fact(f"item{seq}.descent_max_ms", round(max(p[3] for p in during), 1), TOL_CLIMB)


def _off_polyline(p: tuple[float, float], corners: list[tuple[float, float]]) -> float:
    best = math.inf
    for a, b in zip(corners, corners[1:]):
        ax, ay = b[0] - a[0], b[1] - a[1]
        t = max(0.0, min(1.0, ((p[0] - a[0]) * ax + (p[1] - a[1]) * ay) / (ax * ax + ay * ay)))
        best = min(best, math.hypot(p[0] - a[0] - t * ax, p[1] - a[1] - t * ay))
    return best


def _span(trace: Trace, flight: Flight, fact: str, first_seq: int, end_seq: int,
          tol: Tol) -> tuple[int, int] | None:
    """From item first_seq's start to item end_seq's, its seconds recorded as `fact`."""
    first, end = flight.window(first_seq), flight.window(end_seq)
    span = None if first is None or end is None else (first[0], end[0])
    trace.fact(fact, None if span is None else round((span[1] - span[0]) / 1000.0, 1), tol)
    return span


def _spline_facts(trace: Trace, flight: Flight) -> None:
    span = _span(trace, flight, "splines.seconds_round", 2, 5, TOL_TRACK_S)
    if span is None:
        return
    for seq, leg in ((2, SQUARE[0:2]), (3, SQUARE[1:3]), (4, SQUARE[2:4])):
        window = flight.window(seq)
        during = flight.during(*window) if window else []
        trace.fact(f"item{seq}.off_leg_max_m",
                   round(max((_off_polyline(p[1], leg) for p in during), default=0.0), 1), TOL_OFF)
    during = flight.during(*span)
    outside = [max(-p[1][0], p[1][0] - 20.0, -p[1][1], p[1][1] - 20.0, 0.0) for p in during]
    trace.fact("splines.outside_square_max_m", round(max(outside, default=0.0), 1), TOL_OFF)
    trace.fact("splines.off_square_max_m", round(max((_off_polyline(p[1], SQUARE) for p in during), default=0.0), 1),
               TOL_OFF)
    trace.fact("item3.alt_max_m", round(max((p[2] for p in during), default=0.0), 1), TOL_ALT)


def _wp_spline_facts(trace: Trace, flight: Flight) -> None:
    """The waypoint A (20, 0) before the spline to (30, 10): the slowest speed within 3 m of A,
    the spline's time and its bulge off the straight line A-(30, 10)."""
    spline = _span(trace, flight, "wp_spline.seconds_spline", 3, 4, TOL_SECONDS)
    if spline is None:
        return
    near_a = [p for p in flight.during(spline[0] - 5000, spline[1]) if math.hypot(p[1][0] - 20.0, p[1][1]) < 3.0]
    trace.fact("wp_spline.speed_at_a_min_ms", round(min(p[5] for p in near_a), 1) if near_a else None, TOL_PASS)
    trace.fact("item3.off_leg_max_m", round(max((_off_polyline(p[1], [(20.0, 0.0), (30.0, 10.0)])
                                                 for p in flight.during(*spline)), default=0.0), 1), TOL_OFF)


def mission_facts(trace: Trace, flight: Flight, upload_result) -> None:
    """The upload's result, the items reached, the current items seen and the texts said."""
    trace.fact("upload", upload_result)
    trace.fact("reached", [m.seq for _, m in flight.of("MISSION_ITEM_REACHED")])
    # up to the disarm: whether the reset to item 1 after it shows depends on when the window ends
    disarmed = next((t for t, text in flight.texts if text == "Disarming motors"), flight.end_ms)
    # and from item 1: how long seq 0 shows after an upload is not these items' business
    trace.fact("current_seq_seen", held_seqs([m.seq for t, m in flight.currents if t <= disarmed and m.seq]))
    trace.fact("said", said([text for _, text in flight.texts]))


def run(target) -> dict[str, Trace]:
    traces: dict[str, Trace] = {}
    try:
        for name, plan in MISSIONS.items():
            client = _boot(target)
            trace = traces[name] = Trace()
            for param, value in PARAMS_SET.get(name, {}).items():
                trace.fact(f"set_{param}", client.set_param(param, value))
            geo, (result, log) = _fly(client, plan)
            flight = Flight(geo, log)
            mission_facts(trace, flight, result)
            for seq, (cmd, _, at, _) in enumerate(plan, start=1):
                if cmd == TURNS:
                    _circle_facts(trace, flight, seq, at)
                elif cmd == TO_ALT:
                    _to_alt_facts(trace, flight, seq, at)
            if name == "splines":
                _spline_facts(trace, flight)
            elif name == "wp_spline":
                _wp_spline_facts(trace, flight)
    finally:
        target.close()
    return traces

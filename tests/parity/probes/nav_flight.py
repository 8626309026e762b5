"""Measured flight of the navigating modes (issue 28): a SMART_RTL retrace and a CIRCLE, flown the
same way on both vehicles and reduced to figures a client would notice.

SMART_RTL: armed and taken off at home, the vehicle flies a route in GUIDED whose fourth leg
crosses its first (a loop SmartRTL prunes), then SMART_RTL takes it back. Its track from the
mode change to the disarm is resampled at equal steps along its length: every sample within
2 m of ArduCopter's, and the loop cut out as ArduCopter cuts it.

CIRCLE: from a hover at 10 m, nose north, CIRCLE with its defaults (10 m radius, 20 deg/s) while
the pilot's sticks are held centred by RC override (SITL's own throttle reads the bottom of the
stick: the vehicle would sink). A circle fitted to the track gives the centre, the radius and
the period; how long the first quarter takes shows the rate's ramp-up.
"""
from __future__ import annotations

import math
import threading
import time
from contextlib import contextmanager

from ..client import Client, mav
from ..facts import Tol, Trace
from .states import HOVER_ALT_M, reach_flying
from .texts import said

AREA = "nav_flight"
EARTH_M_PER_DEG = 111_195.0
SMART_RTL, CIRCLE = 21, 7
POSITION_ONLY = 0b110111111000  # SET_POSITION_TARGET_GLOBAL_INT: position only
# The route out (metres north, east of home, height above home): the leg C->D crosses home->A
# at (20, 0), a loop SmartRTL's pruning cuts.
ROUTE = ((40.0, 0.0, 10.0), (40.0, 20.0, 14.0), (20.0, 20.0, 14.0), (20.0, -10.0, 10.0), (30.0, -10.0, 10.0))
CROSSING = (20.0, 0.0)
ARRIVED_M = 1.0
SAMPLES = 24  # points the retrace is resampled at, equally spaced along it
CIRCLE_S = 30.0  # vehicle seconds of circling recorded
FIT_FROM_S = 3.0  # the circle is fitted from here on (after the ramp-up)
RC_EVERY_S = 0.02  # wall seconds between RC overrides: well inside both vehicles' timeouts at 20x

PATH_TOL = Tol(abs=2.0, why="the retrace within 2 m of ArduCopter's (issue 28): the same points, "
                            "corners cut by two navigators")
NEAR_TOL = Tol(abs=1.5, why="how near a point of the route the retrace passes: corners are cut a little "
                            "differently")
TIME_TOL = Tol(abs=2.0, rel=0.15, why="different airframe and controller tuning")
CENTRE_TOL = Tol(abs=1.0, why="the centre the radius ahead of where the vehicle stops: a metre for the stop")
BEARING_TOL = Tol(abs=10.0, why="the centre straight ahead of the nose, within the fit's error")
RADIUS_TOL = Tol(abs=1.0, why="the radius flown: position tracking differs by under a metre")
PERIOD_TOL = Tol(abs=0.5, rel=0.05, why="the orbit's rate: 20 deg/s on both, capped by the same limits")
RAMP_TOL = Tol(abs=0.8, why="the first quarter: the rate's ramp-up plus how fast the vehicle follows it")
FACING_TOL = Tol(abs=5.0, why="the nose on the centre within degrees: yaw tracking differs")
ALT_TOL = Tol(abs=0.5, why="height held within half a metre with the sticks centred")


def ne_alt(c: Client) -> tuple[float, float, float]:
    p, h = c.last["GLOBAL_POSITION_INT"], c.last["HOME_POSITION"]
    dn = (p.lat - h.latitude) * 1e-7 * EARTH_M_PER_DEG
    de = (p.lon - h.longitude) * 1e-7 * EARTH_M_PER_DEG * math.cos(math.radians(h.latitude * 1e-7))
    return dn, de, p.relative_alt / 1000.0


def goto(c: Client, north: float, east: float, alt: float) -> None:
    h = c.last["HOME_POSITION"]
    lat = h.latitude + round(north / EARTH_M_PER_DEG * 1e7)
    lon = h.longitude + round(east / (EARTH_M_PER_DEG * math.cos(math.radians(h.latitude * 1e-7))) * 1e7)
    c.conn.mav.set_position_target_global_int_send(0, 1, 1, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, POSITION_ONLY,
                                                   lat, lon, alt, 0, 0, 0, 0, 0, 0, 0, 0)

    def there():
        n, e, a = ne_alt(c)
        return math.dist((n, e, a), (north, east, alt)) < ARRIVED_M
    c.wait(there, 60, what=f"arrival at {north:g} N {east:g} E")
    c.idle(1.0)


class Track:
    """(vehicle seconds, north, east, alt, yaw) at every GLOBAL_POSITION_INT while listening, and
    when the mode change was answered and the vehicle disarmed: each stamped as it came, so a
    client that falls behind a vehicle at 20x and reads seconds of messages at once still sees
    when each thing happened."""

    def __init__(self, c: Client):
        self.c = c
        self.t0_ms = c.now_ms
        self.points: list[tuple[float, float, float, float, float]] = []
        self.ack_s: float | None = None
        self.disarmed_s: float | None = None

    def __call__(self, msg) -> None:
        kind, now_s = msg.get_type(), (self.c.now_ms - self.t0_ms) / 1000.0
        if kind == "GLOBAL_POSITION_INT" and "HOME_POSITION" in self.c.last:
            att = self.c.last.get("ATTITUDE")
            self.points.append((now_s, *ne_alt(self.c), att.yaw if att else 0.0))
        elif kind == "COMMAND_ACK" and msg.command == mav.MAV_CMD_DO_SET_MODE and self.ack_s is None:
            self.ack_s = now_s
        elif kind == "HEARTBEAT" and not msg.base_mode & mav.MAV_MODE_FLAG_SAFETY_ARMED and self.disarmed_s is None:
            self.disarmed_s = now_s


def resample(points: list[tuple[float, float, float]], count: int) -> list[tuple[float, float, float]]:
    """`count` points equally spaced along the polyline through `points` (3D length)."""
    lengths = [0.0]
    for a, b in zip(points, points[1:]):
        lengths.append(lengths[-1] + math.dist(a, b))
    total = lengths[-1]
    out, i = [], 0
    for k in range(count):
        at = total * k / (count - 1)
        while i < len(points) - 2 and lengths[i + 1] < at:
            i += 1
        span = lengths[i + 1] - lengths[i]
        f = 0.0 if span <= 0 else min(max((at - lengths[i]) / span, 0.0), 1.0)
        a, b = points[i], points[i + 1]
        out.append(tuple(a[j] + f * (b[j] - a[j]) for j in range(3)))
    return out


def nearest_m(points, north: float, east: float) -> float:
    return min(math.hypot(n - north, e - east) for n, e, *_ in points)


def smart_rtl(c: Client, trace: Trace) -> None:
    reach_flying(c, HOVER_ALT_M)
    for point in ROUTE:
        goto(c, *point)
    track = Track(c)
    with c.listening(track):
        start = c.now_ms
        trace.fact("result", c.set_mode(SMART_RTL))
        c.wait(lambda: not c.armed, 180, what="SMART_RTL landing and disarming")
    ack_s, disarmed_s = track.ack_s or 0.0, track.disarmed_s or 0.0
    flown = [(n, e, a) for t, n, e, a, _ in track.points if t <= disarmed_s]
    samples = resample(flown, SAMPLES)
    trace.fact("retrace_north_m", [s[0] for s in samples], PATH_TOL)
    trace.fact("retrace_east_m", [s[1] for s in samples], PATH_TOL)
    trace.fact("retrace_alt_m", [s[2] for s in samples], PATH_TOL)
    trace.fact("nearest_crossing_m", nearest_m(flown, *CROSSING), NEAR_TOL)
    trace.fact("nearest_first_corner_m", nearest_m(flown, *ROUTE[0][:2]), NEAR_TOL)
    trace.fact("touchdown_from_home_m", math.hypot(*flown[-1][:2]), NEAR_TOL)
    trace.fact("duration_s", disarmed_s - ack_s, TIME_TOL)
    trace.fact("said", said(c.texts_since(start)))


@contextmanager
def sticks_centred(c: Client):
    """RC override of the four sticks at 1500 us, resent from a thread every RC_EVERY_S of wall
    time whatever the probe is doing (a vehicle at 20x runs out an override's timeout in a tenth
    of a wall second)."""
    stop = threading.Event()

    def send():
        while not stop.is_set():
            c.conn.mav.rc_channels_override_send(1, 1, 1500, 1500, 1500, 1500, 0, 0, 0, 0)
            time.sleep(RC_EVERY_S)
    sender = threading.Thread(target=send, daemon=True)
    sender.start()
    try:
        yield
    finally:
        stop.set()
        sender.join()


def fit_circle(points) -> tuple[float, float, float]:
    """Least-squares circle (Kasa) through (north, east) points: (centre n, centre e, radius)."""
    n_mean = sum(p[0] for p in points) / len(points)
    e_mean = sum(p[1] for p in points) / len(points)
    suu = suv = svv = suuu = svvv = suvv = svuu = 0.0
    for n, e in points:
        u, v = n - n_mean, e - e_mean
        suu += u * u
        suv += u * v
        svv += v * v
        suuu += u * u * u
        svvv += v * v * v
        suvv += u * v * v
        svuu += v * u * u
    det = suu * svv - suv * suv
    uc = (0.5 * (suuu + suvv) * svv - 0.5 * (svvv + svuu) * suv) / det
    vc = (0.5 * (svvv + svuu) * suu - 0.5 * (suuu + suvv) * suv) / det
    radius = math.sqrt(uc * uc + vc * vc + (suu + svv) / len(points))
    return n_mean + uc, e_mean + vc, radius


def circle(c: Client, trace: Trace) -> None:
    reach_flying(c, HOVER_ALT_M)
    c.command(mav.MAV_CMD_CONDITION_YAW, 0, 0, 1, 0)  # nose north, whatever the landing left
    c.wait(lambda: abs(c.last["ATTITUDE"].yaw) < math.radians(1), 20, what="the nose north")
    c.idle(2.0)
    with sticks_centred(c):
        track = Track(c)
        with c.listening(track):
            n0, e0, alt0 = ne_alt(c)
            heading0 = c.last["ATTITUDE"].yaw
            trace.fact("result", c.set_mode(CIRCLE))
            c.wait(lambda: track.ack_s is not None and bool(track.points) and track.points[-1][0] - track.ack_s > CIRCLE_S,
                   CIRCLE_S + 5, what="the circle's time")
    start_s = track.ack_s or 0.0
    points = [(t - start_s, n, e, a, y) for t, n, e, a, y in track.points if start_s <= t <= start_s + CIRCLE_S]
    cn, ce, radius = fit_circle([(n, e) for t, n, e, _, _ in points if t >= FIT_FROM_S])
    trace.fact("centre_from_entry_m", math.hypot(cn - n0, ce - e0), CENTRE_TOL)
    bearing = math.degrees(math.atan2(ce - e0, cn - n0) - heading0)
    trace.fact("centre_bearing_off_nose_deg", (bearing + 180.0) % 360.0 - 180.0, BEARING_TOL)
    trace.fact("radius_m", radius, RADIUS_TOL)
    # The angle travelled about the fitted centre, unwrapped: the first quarter and one turn.
    travelled, last = [], None
    for t, n, e, _, _ in points:
        angle = math.atan2(e - ce, n - cn)
        if last is not None:
            step = (angle - last[1] + math.pi) % (2 * math.pi) - math.pi
            travelled.append((t, travelled[-1][1] + step if travelled else step))
        last = (t, angle)
    quarter = next((t for t, a in travelled if abs(a) >= math.pi / 2), math.inf)
    trace.fact("first_quarter_s", quarter, RAMP_TOL)
    at_fit = next(a for t, a in travelled if t >= FIT_FROM_S)
    turn = next((t for t, a in travelled if abs(a - at_fit) >= 2 * math.pi), math.inf)
    trace.fact("period_s", turn - FIT_FROM_S, PERIOD_TOL)
    off = [abs((math.degrees(math.atan2(ce - e, cn - n) - y) + 180.0) % 360.0 - 180.0)
           for t, n, e, _, y in points if t >= FIT_FROM_S]
    trace.fact("nose_off_centre_deg", sum(off) / len(off), FACING_TOL)
    trace.fact("alt_change_m", points[-1][3] - alt0, ALT_TOL)
    trace.fact("mode_after", c.mode)


def mission_item(command: int, north: float = 0.0, east: float = 0.0, alt: float = 0.0, located: bool = True):
    """(command, frame, p1..p4, x, y, z) at a point north/east of home (or no point)."""
    h = None
    x = y = 0
    if located:
        h = MISSION_HOME
        x = h[0] + round(north / EARTH_M_PER_DEG * 1e7)
        y = h[1] + round(east / (EARTH_M_PER_DEG * math.cos(math.radians(h[0] * 1e-7))) * 1e7)
    return command, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, 0, 0, 0, 0, x, y, alt


MISSION_HOME = (0, 0)  # home (lat, lon in 1e-7 degrees), set once HOME_POSITION has come


def landing_mission() -> list:
    """Out to two waypoints, then a landing sequence: DO_LAND_START (no location of its own: the
    next waypoint's counts), a waypoint and a landing."""
    return [mission_item(mav.MAV_CMD_NAV_TAKEOFF, alt=10.0, located=False),
            mission_item(mav.MAV_CMD_NAV_WAYPOINT, *LANDING_ROUTE[0]),
            mission_item(mav.MAV_CMD_NAV_WAYPOINT, *LANDING_ROUTE[1]),
            mission_item(mav.MAV_CMD_DO_LAND_START, located=False),
            mission_item(mav.MAV_CMD_NAV_WAYPOINT, *LANDING_ROUTE[2]),
            mission_item(mav.MAV_CMD_NAV_LAND, *LANDING_ROUTE[3])]


LANDING_ROUTE = ((40.0, 0.0, 10.0), (40.0, 30.0, 10.0), (15.0, 30.0, 10.0), (15.0, 15.0, 0.0))


def return_path_mission() -> list:
    """The same route with a return path instead: DO_RETURN_PATH_START after the first waypoint.
    From a hover at home the nearest leg of it is the last (to the landing), joined there."""
    mission = landing_mission()
    mission[3] = mission[2]
    mission[2] = mission_item(mav.MAV_CMD_DO_RETURN_PATH_START, located=False)
    return mission


class Beats:
    """The custom mode of every HEARTBEAT and the seq of every MISSION_CURRENT, stamped."""

    def __init__(self, c: Client):
        self.c = c
        self.modes: list[tuple[int, int, bool]] = []  # (ms, custom_mode, armed)
        self.current: list[tuple[int, int]] = []

    def __call__(self, msg) -> None:
        kind = msg.get_type()
        if kind == "HEARTBEAT":
            self.modes.append((self.c.now_ms, msg.custom_mode, bool(msg.base_mode & mav.MAV_MODE_FLAG_SAFETY_ARMED)))
        elif kind == "MISSION_CURRENT":
            self.current.append((self.c.now_ms, msg.seq))


def auto_rtl(c: Client, trace: Trace, how: str, mission=landing_mission) -> None:
    """From a hover at home with `mission` loaded, AUTO RTL asked for `how` (by mode number, or by
    MAV_CMD_DO_LAND_START): what it answers and reports, and where it flies."""
    from .missions import upload
    reach_flying(c, HOVER_ALT_M)
    global MISSION_HOME
    h = c.last["HOME_POSITION"]
    MISSION_HOME = (h.latitude, h.longitude)
    trace.fact("upload", upload(c, mission()))
    c.idle(1.0)  # the upload's own text said before the mode change
    track, beats = Track(c), Beats(c)
    with c.listening(track), c.listening(beats):
        start = c.now_ms
        if how == "mode":
            trace.fact("result", c.set_mode(27))
        else:
            trace.fact("result", c.command(mav.MAV_CMD_DO_LAND_START))
        acked = c.now_ms
        c.wait(lambda: any(t >= acked + 1000 for t, _ in beats.current)
               and any(t >= acked + 1000 for t, _, _ in beats.modes), 10, what="MISSION_CURRENT and HEARTBEAT")
        trace.fact("said", said(c.texts_since(start, 1.0)))
        # A second on: a HEARTBEAT built just before the change can reach the client after the ACK.
        trace.fact("mode_after", next(m for t, m, _ in beats.modes if t >= acked + 1000))
        trace.fact("mission_current_after", next(seq for t, seq in beats.current if t >= acked + 1000))
        c.wait(lambda: not c.armed, 120, what="AUTO RTL landing and disarming")
        c.fresh_heartbeat()
    disarmed_ms = next(t for t, _, armed in beats.modes if not armed)
    trace.fact("modes_while_armed", sorted({m for t, m, armed in beats.modes if t >= acked + 1000 and armed}))
    trace.fact("mode_after_disarm", beats.modes[-1][1])
    flown = [(n, e) for t, n, e, _, _ in track.points if t <= (disarmed_ms - track.t0_ms) / 1000.0]
    trace.fact("nearest_third_waypoint_m", nearest_m(flown, *LANDING_ROUTE[2][:2]), NEAR_TOL)
    trace.fact("nearest_second_waypoint_m", nearest_m(flown, *LANDING_ROUTE[1][:2]), NEAR_TOL)
    trace.fact("touchdown_from_land_point_m", math.dist(flown[-1], LANDING_ROUTE[3][:2]), NEAR_TOL)


def run(target) -> dict[str, Trace]:
    traces = {"SMART_RTL": Trace(), "CIRCLE": Trace(), "AUTO_RTL": Trace(), "DO_LAND_START": Trace(),
              "AUTO_RTL_RETURN_PATH": Trace()}
    c = target.boot()
    try:
        c.conn.mav.command_long_send(1, 1, mav.MAV_CMD_REQUEST_MESSAGE, 0, 242, 0, 0, 0, 0, 0, 0)
        c.wait(lambda: "HOME_POSITION" in c.last, 10, what="HOME_POSITION")
        smart_rtl(c, traces["SMART_RTL"])
        circle(c, traces["CIRCLE"])
        auto_rtl(c, traces["AUTO_RTL"], "mode")
        auto_rtl(c, traces["DO_LAND_START"], "command")
        auto_rtl(c, traces["AUTO_RTL_RETURN_PATH"], "mode", return_path_mission)
    finally:
        target.close()
    return traces


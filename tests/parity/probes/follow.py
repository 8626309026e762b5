"""FOLLOW behind a lead vehicle that this client plays itself: GLOBAL_POSITION_INT (or
FOLLOW_TARGET) sent with the lead's own system id at 10 Hz of vehicle time, the lead moving along
a straight line at a few m/s. The vehicle hovers in GUIDED, hears the lead for two seconds, then
is switched to FOLLOW. Read off GLOBAL_POSITION_INT at 10 Hz, in vehicle time from the ACK: how
far the vehicle is from the lead's point plus the offset at 5, 10 and 20 s, its speed and heading,
its texts, and what it does once the lead falls silent (ArduCopter flies on along the lead's last
velocity until its 3 s timeout, then stops)."""
from __future__ import annotations

import math

from ..client import Client, ProbeTimeout, mav
from ..facts import Tol, Trace
from .states import GUIDED, reach_flying

AREA = "follow"
# The client is the lead: at Firefly's usual 20x a client held up for 150 ms of wall time is a lead
# silent for 3 s of vehicle time, which FOLLOW rightly takes as lost. At 5x that takes 600 ms.
FIREFLY_SPEEDUP = "5"
FOLLOW = 23
LEAD_SYSID = 2
SEND_EVERY_MS = 100  # the lead's 10 Hz
HOME_LAT, HOME_LON, HOME_ALT_M = -35.363261, 149.165230, 584.0
M_PER_E7 = 0.011131884502145034  # ArduPilot's LOCATION_SCALING_FACTOR: metres per 1e-7 degree of latitude
HEARD_BEFORE_S = 2.0  # the lead is heard this long before FOLLOW
SAMPLES_S = (5.0, 10.0, 20.0)
FOLLOWED_S = 25.0  # then the lead falls silent
SILENT_WATCH_S = 10.0
LEAD_GAP_MAX_MS = 400  # a probe whose lead went unheard longer (its client held up) is run again

CATCHING = Tol(abs=1.5, rel=0.3, why="distance 5 s in, still closing the gap to the lead's point: how hard each "
                                      "position controller chases a shaped target differs (ArduCopter lags it more)")
TRACKING = Tol(abs=0.3, why="distance to the lead's point once caught up: both track within centimetres; "
                            "the 10 Hz samples and the controllers' lag give a few tenths")
SPEED = Tol(abs=0.5, rel=0.1, why="ground speed read at 10 Hz: the controllers' overshoot differs")
HEADING = Tol(abs=3.0, why="heading in degrees: the yaw loops' lag behind a turning target differs")
DRIFTING_HEADING = Tol(abs=15.0, why="heading in degrees with none asked for (FOLL_YAW_BEHAVE 0), which ArduCopter "
                                     "lets the lean turn: the drift grows with the lean, and airframes and "
                                     "controllers lean differently (measured: 4-12 degrees apart)")
DRIFT = Tol(abs=0.6, rel=0.05, why="how far it flies on and stops after the lead falls silent: the same 3 s on "
                                   "the lead's velocity, then each position controller's stop")
HEIGHT = Tol(abs=0.3, why="height error: the vertical controllers differ")
REPORTED_DISTANCE = Tol(abs=2.0, rel=0.05, why="NAV_CONTROLLER_OUTPUT's whole metres to the waypoint")
REPORTED_BEARING = Tol(abs=300.0, why="NAV_CONTROLLER_OUTPUT's bearing, which ArduCopter 4.7 sends in "
                                       "centidegrees in FOLLOW: 3 degrees, as HEADING")
DEVIATION = Tol(abs=1.0, rel=0.3, why="the largest miss once caught up, as the lead turns or stops: how far each "
                                      "position controller overshoots a shaped target")


def ne_of(lat: float, lon: float) -> tuple[float, float]:
    """Metres north and east of home, on ArduPilot's flat-earth scale."""
    return ((lat - HOME_LAT) * 1e7 * M_PER_E7,
            (lon - HOME_LON) * 1e7 * M_PER_E7 * math.cos(math.radians(HOME_LAT)))


def lat_lon_e7(n: float, e: float) -> tuple[int, int]:
    return (round(HOME_LAT * 1e7 + n / M_PER_E7),
            round(HOME_LON * 1e7 + e / (M_PER_E7 * math.cos(math.radians(HOME_LAT)))))


def wrap_deg(angle: float) -> float:
    return (angle + 180.0) % 360.0 - 180.0


class Lead:
    """The lead vehicle: at (n0, e0) and `rel_alt_m` above home when it starts, then flying
    `legs` one after the other, each (seconds, speed m/s, course degrees), and still after the
    last; it reports `hdg_deg` as its heading (None: its course), every SEND_EVERY_MS of vehicle
    time from `start()` until `silence()`."""

    def __init__(self, c: Client, n0: float, e0: float, rel_alt_m: float, legs: list[tuple[float, float, float]],
                 hdg_deg: float | None = None, as_follow_target: bool = False):
        self.c = c
        self.link = mav.MAVLink(c.conn, srcSystem=LEAD_SYSID, srcComponent=1)
        self.n0, self.e0, self.rel_alt_m = n0, e0, rel_alt_m
        self.legs = [(seconds, speed * math.cos(math.radians(course)), speed * math.sin(math.radians(course)), course)
                     for seconds, speed, course in legs]
        self.hdg_deg = hdg_deg
        self.as_follow_target = as_follow_target
        self.start_ms: int | None = None
        self.sent_ms = -SEND_EVERY_MS
        self.last_sent_ms: int | None = None
        self.largest_gap_ms = 0  # between two reports while speaking: the client held up
        self.speaking = False

    def start(self) -> None:
        self.start_ms = self.c.now_ms
        self.speaking = True
        self.send()

    def silence(self) -> None:
        self.speaking = False

    def state(self, t_ms: int) -> tuple[float, float, float, float, float]:
        """(n, e, vn, ve, course) at vehicle time t_ms; it stops where it fell silent."""
        assert self.start_ms is not None
        end = t_ms if self.speaking or self.last_sent_ms is None else min(t_ms, self.last_sent_ms)
        left = (end - self.start_ms) / 1000.0
        n, e, course = self.n0, self.e0, 0.0
        for seconds, vn, ve, course in self.legs:
            dt = min(left, seconds)
            n, e, left = n + vn * dt, e + ve * dt, left - dt
            if left <= 0.0:
                return n, e, vn, ve, course
        return n, e, 0.0, 0.0, course

    def at(self, t_ms: int) -> tuple[float, float]:
        n, e, _, _, _ = self.state(t_ms)
        return n, e

    def __call__(self, msg) -> None:
        if self.speaking and self.c.now_ms - self.sent_ms >= SEND_EVERY_MS:
            self.send()

    def send(self) -> None:
        now = self.c.now_ms
        if self.last_sent_ms is not None:
            self.largest_gap_ms = max(self.largest_gap_ms, now - self.last_sent_ms)
        self.sent_ms = self.last_sent_ms = now
        n, e, vn, ve, course = self.state(now)
        hdg = course if self.hdg_deg is None else self.hdg_deg
        lat, lon = lat_lon_e7(n, e)
        if self.as_follow_target:
            yaw = math.radians(hdg)
            q = [math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)]
            self.link.follow_target_send(now, 1 | 2 | 8, lat, lon, HOME_ALT_M + self.rel_alt_m,
                                         [vn, ve, 0.0], [0.0, 0.0, 0.0], q, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], 0)
        else:
            self.link.global_position_int_send(now, lat, lon, round((HOME_ALT_M + self.rel_alt_m) * 1000),
                                               round(self.rel_alt_m * 1000), round(vn * 100), round(ve * 100), 0,
                                               round(hdg % 360 * 100))


def set_param(c: Client, name: str, value: float) -> None:
    """PARAM_SET, and its echo among the PARAM_VALUEs that follow: ArduCopter echoes every element
    of a vector (FOLL_OFS_X, _Y, _Z) when one is set, so the last value need not be this one, and
    nothing when the value does not change (FOLL_SYSID taken automatically): then it is read."""
    seen = []

    def echo(msg) -> None:
        if msg.get_type() == "PARAM_VALUE" and msg.param_id == name and math.isclose(msg.param_value, value,
                                                                                       abs_tol=1e-4):
            seen.append(msg)
    with c.listening(echo):
        c.conn.mav.param_set_send(1, 1, name.encode(), value, mav.MAV_PARAM_TYPE_REAL32)
        if c.try_wait(lambda: bool(seen), 2):
            return
        c.conn.mav.param_request_read_send(1, 1, name.encode(), -1)
        if not c.try_wait(lambda: bool(seen), 3):
            raise ProbeTimeout(f"{name} not set to {value:g}")


def vehicle_ne(c: Client) -> tuple[float, float]:
    m = c.last["GLOBAL_POSITION_INT"]
    return ne_of(m.lat / 1e7, m.lon / 1e7)


def follow(c: Client, trace: Trace, params: dict, lead_from_vehicle: tuple[float, float],
           legs: list[tuple[float, float, float]], offset: tuple[float, float, float] | None,
           hdg_deg: float | None = None, as_follow_target: bool = False, settled_from_s: float = 10.0,
           heading_tol: Tol = HEADING) -> int:
    """Hovering in GUIDED, the lead `lead_from_vehicle` (n, e) from the vehicle at its height,
    then FOLLOW; `offset` (n, e, d) is where the vehicle should be from the lead (None: the one it
    loads itself, where the lead was from it as it entered FOLLOW). Distances sampled from
    `settled_from_s` on are held to the steady tolerance; before, it may still be catching up.
    Returns the longest the lead went unheard while speaking (vehicle ms): a client held up."""
    reach_flying(c)
    for name, value in params.items():
        set_param(c, name, value)
    c.fresh("GLOBAL_POSITION_INT")
    n, e = vehicle_ne(c)
    alt = c.rel_alt_m()
    lead = Lead(c, n + lead_from_vehicle[0], e + lead_from_vehicle[1], alt, legs, hdg_deg, as_follow_target)
    log: list[tuple[int, object]] = []

    def record(msg) -> None:
        if msg.get_type() in ("GLOBAL_POSITION_INT", "STATUSTEXT", "COMMAND_ACK", "HEARTBEAT", "NAV_CONTROLLER_OUTPUT",
                              "POSITION_TARGET_GLOBAL_INT"):
            log.append((c.now_ms, msg))
    with c.listening(lead), c.listening(record):
        lead.start()
        c.idle(HEARD_BEFORE_S)
        sent = c.now_ms
        trace.fact("result", c.set_mode(FOLLOW))
        acked = next((t for t, m in log if m.get_type() == "COMMAND_ACK" and m.command == mav.MAV_CMD_DO_SET_MODE
                      and t >= sent), sent)
        c.wait(lambda: c.now_ms >= acked + FOLLOWED_S * 1000, FOLLOWED_S + 5, what="following")
        lead.silence()
        silent_ms = lead.last_sent_ms
        c.wait(lambda: c.now_ms >= silent_ms + SILENT_WATCH_S * 1000, SILENT_WATCH_S + 5, what="after the lead")
    positions = [(t, m) for t, m in log if m.get_type() == "GLOBAL_POSITION_INT"]

    def sample(at_ms: float):
        return min(positions, key=lambda tm: abs(tm[0] - at_ms))

    if offset is None:  # the one it loads: where the lead was from it when it entered FOLLOW
        t, m = sample(acked)
        ln, le = lead.at(t)
        vn, ve = ne_of(m.lat / 1e7, m.lon / 1e7)
        offset = (vn - ln, ve - le, 0.0)

    def error(t: int, m) -> tuple[float, float]:
        """Horizontal distance to the lead's point plus offset; height error (+ = too low)."""
        ln, le = lead.at(t)
        vn, ve = ne_of(m.lat / 1e7, m.lon / 1e7)
        height = (lead.rel_alt_m - offset[2]) - m.relative_alt / 1000.0
        return math.hypot(ln + offset[0] - vn, le + offset[1] - ve), height

    trace.fact("said", [m.text for t, m in log if m.get_type() == "STATUSTEXT" and t >= sent])
    for s in SAMPLES_S:
        t, m = sample(acked + s * 1000)
        distance, height = error(t, m)
        trace.fact(f"distance_at_{s:g}s_m", distance, CATCHING if s < settled_from_s else TRACKING)
        trace.fact(f"speed_at_{s:g}s_m_s", math.hypot(m.vx, m.vy) / 100.0, SPEED)
        trace.fact(f"heading_at_{s:g}s_deg", wrap_deg(m.hdg / 100.0), heading_tol)
    trace.fact("height_error_at_20s_m", error(*sample(acked + 20_000))[1], HEIGHT)
    # What it reports of where it flies: NAV_CONTROLLER_OUTPUT's waypoint, POSITION_TARGET_GLOBAL_INT
    nav = [(t, m) for t, m in log if m.get_type() == "NAV_CONTROLLER_OUTPUT" and acked < t <= silent_ms]
    t20 = acked + 20_000
    if nav:
        _, m = min(nav, key=lambda tm: abs(tm[0] - t20))
        trace.fact("nav_wp_dist_at_20s_m", m.wp_dist, REPORTED_DISTANCE)
        trace.fact("nav_target_bearing_at_20s_deg", m.target_bearing, REPORTED_BEARING)
    targets = [(t, m) for t, m in log if m.get_type() == "POSITION_TARGET_GLOBAL_INT" and acked < t <= silent_ms]
    if targets:
        t, m = min(targets, key=lambda tm: abs(tm[0] - t20))
        ln, le = lead.at(t)
        tn, te = ne_of(m.lat_int / 1e7, m.lon_int / 1e7)
        # A lead still turning or stopping at 20 s moves the target a few tenths per sample
        trace.fact("position_target_from_lead_point_m", math.hypot(ln + offset[0] - tn, le + offset[1] - te),
                   CATCHING if settled_from_s > 20 else TRACKING)
    else:
        trace.fact("position_target_from_lead_point_m", None)
    later = [error(t, m)[0] for t, m in positions if acked + 10_000 <= t <= silent_ms]
    trace.fact("largest_distance_after_10s_m", max(later, default=None), DEVIATION)
    # Once the lead is silent: how far on it flies, and its speed as it stops
    t0, m0 = sample(silent_ms)
    p0 = ne_of(m0.lat / 1e7, m0.lon / 1e7)
    for s in (2.0, 5.0, SILENT_WATCH_S):
        t, m = sample(silent_ms + s * 1000)
        p = ne_of(m.lat / 1e7, m.lon / 1e7)
        trace.fact(f"silent_{s:g}s_moved_m", math.hypot(p[0] - p0[0], p[1] - p0[1]), DRIFT)
        trace.fact(f"silent_{s:g}s_speed_m_s", math.hypot(m.vx, m.vy) / 100.0, SPEED)
    beats = [m for t, m in log if m.get_type() == "HEARTBEAT" and t >= silent_ms + (SILENT_WATCH_S - 1.5) * 1000]
    trace.fact("mode_after_silence", beats[-1].custom_mode if beats else None)
    c.set_mode(GUIDED)
    c.wait(lambda: c.mode == GUIDED, 5, what="GUIDED")
    return lead.largest_gap_ms


R45 = math.radians(45)
# name: (parameters, the lead from the vehicle (n, e), its legs, the offset expected (None: the one
# FOLLOW loads), and follow()'s other arguments)
PROBES = {
    # A lead 10 m north, moving east at 3 m/s; the vehicle is to keep 6 m south of it and 2 m
    # above, facing it (FOLL_YAW_BEHAVE's default).
    "ned_offset_face_lead": ({"FOLL_SYSID": LEAD_SYSID, "FOLL_OFS_X": -6, "FOLL_OFS_Y": 0, "FOLL_OFS_Z": -2},
                             (10.0, 0.0), [(math.inf, 3.0, 90.0)], (-6.0, 0.0, -2.0), {}),
    # No offsets and FOLL_SYSID 0: it takes the first sender and keeps its distance (the offset
    # it loads itself), with the lead's heading (it reports 45 degrees, moving north).
    "own_offset_same_heading": ({"FOLL_SYSID": 0, "FOLL_OFS_X": 0, "FOLL_OFS_Y": 0, "FOLL_OFS_Z": 0,
                                 "FOLL_YAW_BEHAVE": 2},
                                (0.0, 8.0), [(math.inf, 2.0, 0.0)], None, {"hdg_deg": 45.0}),
    # FOLLOW_TARGET, offsets relative to the lead's heading: 5 m behind it as it flies north-east
    # at 4 m/s; nose along the flight.
    "relative_offset_follow_target": ({"FOLL_SYSID": LEAD_SYSID, "FOLL_OFS_TYPE": 1, "FOLL_OFS_X": -5,
                                       "FOLL_OFS_Y": 0, "FOLL_OFS_Z": 0, "FOLL_YAW_BEHAVE": 3},
                                      (5.0 * math.cos(R45), 5.0 * math.sin(R45)), [(math.inf, 4.0, 45.0)],
                                      (-5.0 * math.cos(R45), -5.0 * math.sin(R45), 0.0), {"as_follow_target": True}),
    # A lead that turns and stops: east at 4 m/s, north from 8 s after FOLLOW, still from 18 s
    # (speaking on); the vehicle 5 m south of it, no heading asked for (ArduCopter's drifts).
    "lead_turns_and_stops": ({"FOLL_SYSID": LEAD_SYSID, "FOLL_OFS_TYPE": 0, "FOLL_OFS_X": -5, "FOLL_OFS_Y": 0,
                              "FOLL_OFS_Z": 0, "FOLL_YAW_BEHAVE": 0},
                             (5.0, 0.0), [(10.0, 4.0, 90.0), (10.0, 4.0, 0.0)], (-5.0, 0.0, 0.0),
                             {"settled_from_s": math.inf, "heading_tol": DRIFTING_HEADING}),
}
ATTEMPTS = 3


def run(target) -> dict[str, Trace]:
    traces = {}
    c = target.boot()
    try:
        set_param(c, "FOLL_ENABLE", 1)
        for name, (params, lead_from, legs, offset, more) in PROBES.items():
            for _ in range(ATTEMPTS):  # a client held up left the lead silent: that run says nothing
                traces[name] = Trace()
                if follow(c, traces[name], params, lead_from, legs, offset, **more) <= LEAD_GAP_MAX_MS:
                    break
    finally:
        target.close()
    return traces

"""FOLLOW behind a lead vehicle that this client plays itself: GLOBAL_POSITION_INT (or
FOLLOW_TARGET) sent with the lead's own system id at 10 Hz of vehicle time, the lead moving along
a straight line at a few m/s. The vehicle hovers in GUIDED, hears the lead for two seconds, then
is switched to FOLLOW. Read off GLOBAL_POSITION_INT at 10 Hz, in vehicle time from the ACK: how
far the vehicle is from the lead's point plus the offset at 5, 10 and 20 s, its speed and heading,
its texts, and what it does once the lead falls silent (ArduCopter flies on along the lead's last
velocity until its 3 s timeout, then stops)."""
from __future__ import annotations

import math

from ..client import Client, mav
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

CATCHING = Tol(abs=1.5, rel=0.3, why="distance 5 s in, still closing the gap to the lead's point: how hard each "
                                      "position controller chases a shaped target differs (ArduCopter lags it more)")
TRACKING = Tol(abs=0.3, why="distance to the lead's point once caught up: both track within centimetres; "
                            "the 10 Hz samples and the controllers' lag give a few tenths")
SPEED = Tol(abs=0.5, rel=0.1, why="ground speed read at 10 Hz: the controllers' overshoot differs")
HEADING = Tol(abs=3.0, why="heading in degrees: the yaw loops' lag behind a turning target differs")
DRIFT = Tol(abs=0.6, rel=0.05, why="how far it flies on and stops after the lead falls silent: the same 3 s on "
                                   "the lead's velocity, then each position controller's stop")
HEIGHT = Tol(abs=0.3, why="height error: the vertical controllers differ")


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
    """The lead vehicle: at (n0, e0) and `rel_alt_m` above home when it starts, moving at
    `speed_m_s` along `course_deg`, reporting `hdg_deg` as its heading; it speaks every
    SEND_EVERY_MS of vehicle time from `start()` until `silence()`."""

    def __init__(self, c: Client, n0: float, e0: float, rel_alt_m: float, speed_m_s: float, course_deg: float,
                 hdg_deg: float | None = None, as_follow_target: bool = False):
        self.c = c
        self.link = mav.MAVLink(c.conn, srcSystem=LEAD_SYSID, srcComponent=1)
        self.n0, self.e0, self.rel_alt_m = n0, e0, rel_alt_m
        self.vn = speed_m_s * math.cos(math.radians(course_deg))
        self.ve = speed_m_s * math.sin(math.radians(course_deg))
        self.hdg_deg = course_deg if hdg_deg is None else hdg_deg
        self.as_follow_target = as_follow_target
        self.start_ms: int | None = None
        self.sent_ms = -SEND_EVERY_MS
        self.last_sent_ms: int | None = None
        self.speaking = False

    def start(self) -> None:
        self.start_ms = self.c.now_ms
        self.speaking = True
        self.send()

    def silence(self) -> None:
        self.speaking = False

    def at(self, t_ms: int) -> tuple[float, float]:
        """Where the lead is at vehicle time t_ms (it stops where it fell silent)."""
        assert self.start_ms is not None
        end = t_ms if self.speaking or self.last_sent_ms is None else min(t_ms, self.last_sent_ms)
        dt = (end - self.start_ms) / 1000.0
        return self.n0 + self.vn * dt, self.e0 + self.ve * dt

    def __call__(self, msg) -> None:
        if self.speaking and self.c.now_ms - self.sent_ms >= SEND_EVERY_MS:
            self.send()

    def send(self) -> None:
        now = self.c.now_ms
        self.sent_ms = self.last_sent_ms = now
        n, e = self.at(now)
        lat, lon = lat_lon_e7(n, e)
        if self.as_follow_target:
            yaw = math.radians(self.hdg_deg)
            q = [math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)]
            self.link.follow_target_send(now, 1 | 2 | 8, lat, lon, HOME_ALT_M + self.rel_alt_m,
                                         [self.vn, self.ve, 0.0], [0.0, 0.0, 0.0], q, [0.0, 0.0, 0.0],
                                         [0.0, 0.0, 0.0], 0)
        else:
            self.link.global_position_int_send(now, lat, lon, round((HOME_ALT_M + self.rel_alt_m) * 1000),
                                               round(self.rel_alt_m * 1000), round(self.vn * 100),
                                               round(self.ve * 100), 0, round(self.hdg_deg % 360 * 100))


def vehicle_ne(c: Client) -> tuple[float, float]:
    m = c.last["GLOBAL_POSITION_INT"]
    return ne_of(m.lat / 1e7, m.lon / 1e7)


def follow(c: Client, trace: Trace, params: dict, lead_from_vehicle: tuple[float, float], speed_m_s: float,
           course_deg: float, offset: tuple[float, float, float] | None, hdg_deg: float | None = None,
           as_follow_target: bool = False) -> None:
    """Hovering in GUIDED, the lead `lead_from_vehicle` (n, e) from the vehicle at its height,
    then FOLLOW; `offset` (n, e, d) is where the vehicle should be from the lead (None: the one it
    loads itself, where the lead was from it as it entered FOLLOW)."""
    reach_flying(c)
    for name, value in params.items():
        c.set_param(name, value)
    c.fresh("GLOBAL_POSITION_INT")
    n, e = vehicle_ne(c)
    alt = c.rel_alt_m()
    lead = Lead(c, n + lead_from_vehicle[0], e + lead_from_vehicle[1], alt, speed_m_s, course_deg, hdg_deg,
                as_follow_target)
    log: list[tuple[int, object]] = []

    def record(msg) -> None:
        if msg.get_type() in ("GLOBAL_POSITION_INT", "STATUSTEXT", "COMMAND_ACK", "HEARTBEAT"):
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
        trace.fact(f"distance_at_{s:g}s_m", distance, CATCHING if s < 10 else TRACKING)
        trace.fact(f"speed_at_{s:g}s_m_s", math.hypot(m.vx, m.vy) / 100.0, SPEED)
        trace.fact(f"heading_at_{s:g}s_deg", wrap_deg(m.hdg / 100.0), HEADING)
    trace.fact("height_error_at_20s_m", error(*sample(acked + 20_000))[1], HEIGHT)
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


def run(target) -> dict[str, Trace]:
    traces = {"ned_offset_face_lead": Trace(), "own_offset_same_heading": Trace(),
              "relative_offset_follow_target": Trace()}
    c = target.boot()
    try:
        c.set_param("FOLL_ENABLE", 1)
        # A lead 10 m north, moving east at 3 m/s; the vehicle is to keep 6 m south of it and 2 m
        # above, facing it (FOLL_YAW_BEHAVE's default).
        follow(c, traces["ned_offset_face_lead"],
               {"FOLL_SYSID": LEAD_SYSID, "FOLL_OFS_X": -6, "FOLL_OFS_Y": 0, "FOLL_OFS_Z": -2},
               (10.0, 0.0), 3.0, 90.0, (-6.0, 0.0, -2.0))
        # No offsets and FOLL_SYSID 0: it takes the first sender and keeps its distance (the
        # offset it loads itself), with the lead's heading (it reports 45 degrees, moving north).
        follow(c, traces["own_offset_same_heading"],
               {"FOLL_SYSID": 0, "FOLL_OFS_X": 0, "FOLL_OFS_Y": 0, "FOLL_OFS_Z": 0, "FOLL_YAW_BEHAVE": 2},
               (0.0, 8.0), 2.0, 0.0, None, hdg_deg=45.0)
        # FOLLOW_TARGET, offsets relative to the lead's heading: 5 m behind it as it flies
        # north-east at 4 m/s; nose along the flight.
        follow(c, traces["relative_offset_follow_target"],
               {"FOLL_SYSID": LEAD_SYSID, "FOLL_OFS_TYPE": 1, "FOLL_OFS_X": -5, "FOLL_OFS_Y": 0, "FOLL_OFS_Z": 0,
                "FOLL_YAW_BEHAVE": 3},
               (5.0 * math.cos(math.radians(45)), 5.0 * math.sin(math.radians(45))), 4.0, 45.0,
               (-5.0 * math.cos(math.radians(45)), -5.0 * math.sin(math.radians(45)), 0.0), as_follow_target=True)
    finally:
        target.close()
    return traces

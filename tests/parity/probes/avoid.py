"""Simple avoidance against the geofence (AC_Avoid with AVOID_ENABLE's fence bit, the default), as
ArduCopter flies it: the pilot's or a companion's velocity is limited so the vehicle stops
FENCE_MARGIN inside the fence instead of breaching it. Each probe on a fresh vehicle, with the
fence's FENCE_* set at boot and FENCE_ACTION 0 (report only) unless said; the sticks held by RC
override (throttle and yaw at mid, so LOITER holds its height), the vehicle taken off in GUIDED
to 10 m facing north (WP_YAW_BEHAVIOR 0: a GUIDED position target leaves the nose north).

loiter_circle          circle fence, 40 m, margin 2: LOITER, pitch stick full forward (north) for
                       25 s: where it stops, how fast it flew, where it is 3 s after the stick is
                       released, the fence texts and FENCE_STATUS.
loiter_circle_stop     AVOID_BEHAVE 1 (stop), the stick full forward and full right: where it stops.
loiter_slide           AVOID_BEHAVE 0 (slide, the default), from 20 m west of home, the stick full
                       forward and half right (about 26 degrees east of north): where it first
                       meets the margin, and how far round the circle it slides in 25 s.
guided_velocity_polygon an inclusion square +-30 m about home uploaded as fence items (FENCE_TYPE 4,
                       FENCE_ENABLE set after the upload); GUIDED velocity targets of 3 m/s north
                       at 5 Hz for 25 s: where it slows and stops.
altitude_max           FENCE_TYPE 1, FENCE_ALT_MAX 20, margin 2: LOITER from 10 m, the throttle
                       stick full up for 20 s: the height it stops at.
avoid_off              loiter_circle with AVOID_ENABLE 0 and FENCE_ACTION 1: through the fence,
                       the breach text, RTL.
backup                 the circle fence; GUIDED to 39 m north (inside the margin: a position
                       target is not limited), then LOITER with the sticks centred: whether it
                       backs out of the margin at AVOID_BACKUP_SPD.

The breach itself (AC_Fence::check, fence.cpp's fence_check), AVOID_ENABLE 0 so nothing holds the
vehicle in; each from the LOITER switch on: the texts with their severities, the modes in turn,
HEARTBEAT's system_status, SYS_STATUS's geofence bit (present, enabled, healthy) and FENCE_STATUS
(breach_status, breach_type, breach_mitigation; breach_count the last) before, while and after outside,
"while" and "after" cut by the flown track a second clear of the crossing:
breach_rtl             avoid_off (FENCE_ACTION 1) flown on until RTL has brought it back inside and
                       10 s more: the clearing, breach_time against the crossing.
breach_brake           FENCE_ACTION 4: BRAKE, and what 12 s outside in BRAKE says.
manual_recovery        FENCE_ACTION 1: as RTL takes over, LOITER by MAV_CMD_DO_SET_MODE while still
                       outside and the stick at 40 % forward (about 5 m/s, away from home; slower
                       than full so the next breach comes well inside the 100 m past the fence
                       where ArduCopter lands instead): when the fence takes over again (the
                       ten-second manual recovery, then the next 20 m backup fence), where, how far.
report_only            FENCE_ACTION 0: the stick half forward to 63 m (past the backup fence 20 m
                       beyond the first breach, short of the next): the texts, the count, LOITER kept.
alt_breach             FENCE_TYPE 1, FENCE_ALT_MAX 20, FENCE_ACTION 1: LOITER's throttle full up
                       through the ceiling: the text, RTL, breach_type, back below.
"""
from __future__ import annotations

import math
import statistics

from ..client import Client, mav
from ..facts import PathTol, Tol, Trace
from .booting import each_on_a_fresh_vehicle
from .missions import upload
from .nav_flight import EARTH_M_PER_DEG, goto, ne_alt
from .pilot import MID, Sticks
from .states import LOITER, reach_flying
from .texts import BACKGROUND

AREA = "avoid"
RTL = 6
FULL_FORWARD, FULL_RIGHT, HALF_RIGHT, FULL_UP = 1000, 2000, 1750, 2000
HOLD_S = 25.0
RADIUS_M, MARGIN_M = 40.0, 2.0
SQUARE_M = 30.0
VELOCITY_ONLY = 0b110111000111  # SET_POSITION_TARGET_LOCAL_NED: vx, vy, vz only
TARGET_EVERY_MS = 200  # a companion's velocity targets at 5 Hz of vehicle time

CIRCLE = {"FENCE_ENABLE": 1, "FENCE_TYPE": 2, "FENCE_RADIUS": RADIUS_M, "FENCE_MARGIN": MARGIN_M, "FENCE_ACTION": 0,
          "WP_YAW_BEHAVIOR": 0}
PROBES_PARAMS = {
    "loiter_circle": CIRCLE,
    "loiter_circle_stop": {**CIRCLE, "AVOID_BEHAVE": 1},
    "loiter_slide": {**CIRCLE, "AVOID_BEHAVE": 0},
    "guided_velocity_polygon": {"FENCE_ENABLE": 0, "FENCE_TYPE": 4, "FENCE_MARGIN": MARGIN_M, "FENCE_ACTION": 0,
                                "WP_YAW_BEHAVIOR": 0},
    "altitude_max": {"FENCE_ENABLE": 1, "FENCE_TYPE": 1, "FENCE_ALT_MAX": 20, "FENCE_MARGIN": MARGIN_M,
                     "FENCE_ACTION": 0, "WP_YAW_BEHAVIOR": 0},
    "avoid_off": {**CIRCLE, "AVOID_ENABLE": 0, "FENCE_ACTION": 1},
    "backup": CIRCLE,
    "breach_rtl": {**CIRCLE, "AVOID_ENABLE": 0, "FENCE_ACTION": 1},
    "breach_brake": {**CIRCLE, "AVOID_ENABLE": 0, "FENCE_ACTION": 4},
    "manual_recovery": {**CIRCLE, "AVOID_ENABLE": 0, "FENCE_ACTION": 1},
    "report_only": {**CIRCLE, "AVOID_ENABLE": 0, "FENCE_ACTION": 0},
    "alt_breach": {"FENCE_ENABLE": 1, "FENCE_TYPE": 1, "FENCE_ALT_MAX": 20, "FENCE_MARGIN": MARGIN_M,
                   "FENCE_ACTION": 1, "AVOID_ENABLE": 0, "WP_YAW_BEHAVIOR": 0},
}
ALT_MAX_M = 20.0
RECOVER_PITCH = 1300  # 40 % forward: LOITER's speed about 40 % of LOIT_SPEED
HALF_FORWARD = 1250
REPORT_ONLY_TO_M = 63.0  # past the backup fence (the first breach + 20 m), short of the next (+40 m)
AFTER_INSIDE_S = 10.0
BRAKE_OUTSIDE_S = 12.0  # past the ten seconds of manual recovery the switch to BRAKE starts

STOP = Tol(abs=1.0, why="where avoidance stops it: the margin (radius - FENCE_MARGIN) plus each position "
                        "controller's overshoot of its shaped stop, and 10 Hz telemetry at up to 1 m/s")
PLACE = Tol(abs=1.5, why="a point on the margin's circle: the stop, and the stick's direction within a few degrees")
BEARING = Tol(abs=5.0, why="the direction of the pilot's stick (deadzone, lean-angle mixing) within degrees")
SPEED = Tol(abs=1.0, rel=0.15, why="LOITER's top speed on the way out (under LOIT_SPEED: capped by the distance "
                                   "left, to the margin or within 40 m), as two loiter shapers reach it")
SLOWING = Tol(abs=1.0, rel=0.25, why="the speed on the way in to the margin: avoidance's sqrt-controller "
                                     "shaping, followed by two velocity controllers")
HEIGHT = Tol(abs=0.7, why="the climb stopped by FENCE_ALT_MAX - FENCE_MARGIN: the vertical stop's overshoot")
RATE = Tol(abs=0.4, why="PILOT_SPEED_UP, reached by each vertical controller")
BREACH = Tol(abs=2.0, why="the fence checked at 25 Hz at ~10 m/s, and the text stamped on its arrival")
OVERSHOOT = Tol(abs=5.0, why="how far past the fence RTL's stop carries it: LOITER's speed and RTL's braking")
STAMP = Tol(abs=0.5, why="FENCE_STATUS.breach_time (ms since boot) against the crossing seen in 10 Hz "
                         "GLOBAL_POSITION_INT: 25 Hz checks, the estimate's lag")
OUTSIDE = Tol(abs=3.0, rel=0.2, why="how long RTL takes to bring it back inside: the overshoot, the climb to "
                                    "RTL_ALT and the return speed of two navigators")
RECOVERY = Tol(abs=3.0, why="when the fence takes over again: the ten seconds of manual recovery, then the next "
                            "backup fence, 20 m (about 4 s at LOITER's 40 % speed) further out")
RECOVERY_M = Tol(abs=15.0, why="where the fence takes over again: a backup fence, set 20 m past where the last "
                               "one was crossed; where the backups fall hangs on the speed at each 25 Hz check")
COUNT = Tol(abs=1.0, why="breach_count counts the backup fences crossed too: one more or less where the "
                         "overshoot or the recovery's run ends near a backup fence")
CEILING = Tol(abs=1.0, why="the height at the ceiling's breach and the climb past it: 25 Hz checks at "
                           "PILOT_SPEED_UP, RTL's stop")
BACKUP = Tol(abs=0.6, why="backing out of the margin at AVOID_BACKUP_SPD (0.75 m/s): a second's timing is "
                          "0.75 m; a distance held where it stopped is the controllers' drift")


# ----- helpers --------------------------------------------------------------------------------
class Recorder:
    """(vehicle s, north, east, relative alt, horizontal speed, climb rate) at every
    GLOBAL_POSITION_INT while listening, stamped as it came."""

    def __init__(self, c: Client):
        self.c = c
        self.t0_ms = c.now_ms
        self.points: list[tuple[float, float, float, float, float, float]] = []

    def __call__(self, msg) -> None:
        if msg.get_type() == "GLOBAL_POSITION_INT" and "HOME_POSITION" in self.c.last:
            n, e, alt = ne_alt(self.c)
            self.points.append(((self.c.now_ms - self.t0_ms) / 1000.0, n, e, alt, math.hypot(msg.vx, msg.vy) / 100,
                                -msg.vz / 100))

    def since(self, t_s: float) -> list:
        return [p for p in self.points if p[0] >= t_s]

    def now_s(self) -> float:
        return (self.c.now_ms - self.t0_ms) / 1000.0


class Companion:
    """SET_POSITION_TARGET_LOCAL_NED velocities sent every TARGET_EVERY_MS of vehicle time while
    `velocity` is set, driven by the vehicle's messages."""

    def __init__(self, c: Client):
        self.c = c
        self.velocity: tuple[float, float, float] | None = None
        self.sent_ms = -TARGET_EVERY_MS

    def __call__(self, msg) -> None:
        if self.velocity is not None and self.c.now_ms - self.sent_ms >= TARGET_EVERY_MS:
            self.sent_ms = self.c.now_ms
            self.c.conn.mav.set_position_target_local_ned_send(0, 1, 1, mav.MAV_FRAME_LOCAL_NED, VELOCITY_ONLY,
                                                               0, 0, 0, *self.velocity, 0, 0, 0, 0, 0)


def _distance(p) -> float:
    return math.hypot(p[1], p[2])


def _bearing(p) -> float:
    return math.degrees(math.atan2(p[2], p[1]))


def _fence_texts(c: Client, since_ms: int) -> list[str]:
    return [t for t in c.texts_since(since_ms) if "ence" in t]


def _fence_status(c: Client):
    """FENCE_STATUS's breach_status sent from now on (None: none streamed)."""
    if not c.try_wait(lambda: "FENCE_STATUS" in c.last, 3):
        return None
    seen = c.received.get("FENCE_STATUS", 0)
    if not c.try_wait(lambda: c.received.get("FENCE_STATUS", 0) > seen, 3):
        return None
    return c.last["FENCE_STATUS"].breach_status


def _mode_now(c: Client) -> int:
    c.fresh_heartbeat()
    return c.mode


def _first(points, condition):
    return next((p for p in points if condition(p)), None)


def _slowed_at(points, along, fast: float, slow: float = 1.0):
    """`along(p)` where the speed first falls below `slow` after having exceeded `fast`."""
    peak = False
    for p in points:
        if p[4] > fast:
            peak = True
        elif peak and p[4] < slow:
            return round(along(p), 1)
    return None


def _in_loiter(c: Client, sticks: Sticks) -> None:
    """LOITER with the sticks held centred (the receiver's own throttle is at the bottom)."""
    sticks.hold(MID, MID, MID, MID)
    c.set_mode(LOITER)
    c.wait(lambda: c.mode == LOITER, 5, what="LOITER")
    c.idle(2.0)


def _fly_stick(c: Client, trace: Trace, roll: int, pitch: int, start_ne: tuple[float, float] | None = None,
               hold_s: float = HOLD_S):
    """Up at 10 m (first flown to start_ne in GUIDED), LOITER, the stick held for hold_s, released
    for 3 s; (the track, the stick's release [s], LOITER's start [vehicle ms])."""
    sticks, rec = Sticks(c), Recorder(c)
    with c.listening(sticks), c.listening(rec):
        reach_flying(c, 10.0)  # the throttle at rest: ArduCopter will not arm with it at mid
        if start_ne is not None:
            goto(c, *start_ne, 10.0)
        trace.fact("start.heading_deg", round(math.degrees(c.last["ATTITUDE"].yaw)), Tol(abs=5.0))
        since_ms = c.now_ms
        _in_loiter(c, sticks)
        pushed_s = rec.now_s()
        sticks.hold(roll, pitch, MID, MID)
        c.idle(hold_s)
        released_s = rec.now_s()
        sticks.hold(MID, MID, MID, MID)
        c.idle(3.0)
        trace.fact("texts", _fence_texts(c, since_ms))
        trace.fact("fence_status.breach_status", _fence_status(c))
        trace.fact("mode_after", _mode_now(c))
    return rec.since(pushed_s), released_s, since_ms


def _stick_facts(trace: Trace, track: list, released_s: float) -> None:
    held = [p for p in track if p[0] <= released_s]
    trace.fact("farthest_m", round(max(map(_distance, held)), 1), STOP)
    trace.fact("released.distance_m", round(_distance(held[-1]), 1), STOP)
    trace.fact("released.north_m", round(held[-1][1], 1), PLACE)
    trace.fact("released.east_m", round(held[-1][2], 1), PLACE)
    trace.fact("after_release.distance_m", round(_distance(track[-1]), 1), STOP)
    trace.fact("fastest_m_s", round(max(p[4] for p in held), 1), SPEED)


# ----- the probes -----------------------------------------------------------------------------
def loiter_circle(c: Client, trace: Trace) -> None:
    track, released_s, _ = _fly_stick(c, trace, MID, FULL_FORWARD)
    _stick_facts(trace, track, released_s)
    for ring in (30, 35):
        p = _first(track, lambda p: _distance(p) >= ring)
        trace.fact(f"speed_at_{ring}m_m_s", None if p is None else round(p[4], 1), SLOWING)
    trace.fact("slowed_below_1_m_s_at_m", _slowed_at(track, _distance, 3.0), STOP)


def loiter_circle_stop(c: Client, trace: Trace) -> None:
    track, released_s, _ = _fly_stick(c, trace, FULL_RIGHT, FULL_FORWARD)
    _stick_facts(trace, track, released_s)
    p = _first(track, lambda p: _distance(p) >= 10.0)
    trace.fact("outbound.bearing_deg", None if p is None else round(_bearing(p)), BEARING)


def loiter_slide(c: Client, trace: Trace) -> None:
    track, released_s, _ = _fly_stick(c, trace, HALF_RIGHT, FULL_FORWARD, start_ne=(0.0, -20.0))
    _stick_facts(trace, track, released_s)
    edge = RADIUS_M - MARGIN_M - 1.0
    met = _first(track, lambda p: _distance(p) >= edge)
    trace.fact("met_margin.bearing_deg", None if met is None else round(_bearing(met)), BEARING)
    held = [p for p in track if p[0] <= released_s]
    trace.fact("released.bearing_deg", round(_bearing(held[-1])), BEARING)
    ten = _first(held, lambda p: p[0] >= met[0] + 10.0) if met is not None else None
    trace.fact("met_margin_plus_10s.bearing_deg", None if ten is None else round(_bearing(ten)),
               Tol(abs=8.0, why="how fast it slides: the tangential speed avoidance lets through"))
    trace.fact("track", _path(held), PathTol(abs=3.0, why="the path bent along the margin: where the slide "
                                                          "starts (the stopping distance) within a few metres, "
                                                          "and LOITER's own acceleration (Firefly's is AC_Loiter's "
                                                          "drag and brake without its jerk shaping)"))


def _path(points, every_s: float = 1.0) -> list:
    """[north, east] every `every_s` of the track (rounded to decimetres)."""
    out, next_s = [], -math.inf
    for p in points:
        if p[0] >= next_s:
            out.append([round(p[1], 1), round(p[2], 1)])
            next_s = p[0] + every_s
    return out


def _square(c: Client) -> list:
    h = c.last["HOME_POSITION"]
    dlat = round(SQUARE_M / EARTH_M_PER_DEG * 1e7)
    dlon = round(SQUARE_M / (EARTH_M_PER_DEG * math.cos(math.radians(h.latitude * 1e-7))) * 1e7)
    corners = ((-1, -1), (1, -1), (1, 1), (-1, 1))
    return [(mav.MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION, mav.MAV_FRAME_GLOBAL, len(corners), 0, 0, 0,
             h.latitude + sn * dlat, h.longitude + se * dlon, 0) for sn, se in corners]


def guided_velocity_polygon(c: Client, trace: Trace) -> None:
    c.wait(lambda: "HOME_POSITION" in c.last, 60, what="home")
    trace.fact("upload", upload(c, _square(c), kind=mav.MAV_MISSION_TYPE_FENCE))
    trace.fact("enable", c.set_param("FENCE_ENABLE", 1))
    c.idle(1.0)
    companion, rec = Companion(c), Recorder(c)
    with c.listening(companion), c.listening(rec):
        reach_flying(c, 10.0)
        since_ms = c.now_ms
        pushed_s = rec.now_s()
        companion.velocity = (3.0, 0.0, 0.0)
        c.idle(HOLD_S)
        companion.velocity = None
        released_s = rec.now_s()
        c.idle(3.0)
        trace.fact("texts", _fence_texts(c, since_ms))
        trace.fact("fence_status.breach_status", _fence_status(c))
        trace.fact("mode_after", _mode_now(c))
    track = rec.since(pushed_s)
    held = [p for p in track if p[0] <= released_s]
    trace.fact("farthest_north_m", round(max(p[1] for p in held), 1), STOP)
    trace.fact("released.north_m", round(held[-1][1], 1), STOP)
    trace.fact("released.east_m", round(held[-1][2], 1), Tol(abs=0.7, why="straight north: drift"))
    cruise = [p[4] for p in held if 5.0 < p[1] < 15.0]
    trace.fact("cruise_m_s", round(statistics.median(cruise), 2) if cruise else None,
               Tol(abs=0.2, why="the 3 m/s asked for"))
    for north in (20, 25):
        p = _first(held, lambda p: p[1] >= north)
        trace.fact(f"speed_at_{north}m_north_m_s", None if p is None else round(p[4], 1), SLOWING)
    trace.fact("slowed_below_1_m_s_at_north_m", _slowed_at(held, lambda p: p[1], 2.0), STOP)
    # (no fact 3 s after the release: GUIDED's velocity timeout falls there, and the reference
    # itself read 25.6 to 28.0 m north across runs)


def altitude_max(c: Client, trace: Trace) -> None:
    sticks, rec = Sticks(c), Recorder(c)
    with c.listening(sticks), c.listening(rec):
        reach_flying(c, 10.0)  # the throttle at rest: ArduCopter will not arm with it at mid
        since_ms = c.now_ms
        _in_loiter(c, sticks)
        pushed_s = rec.now_s()
        sticks.hold(MID, MID, FULL_UP, MID)
        c.idle(20.0)
        released_s = rec.now_s()
        sticks.hold(MID, MID, MID, MID)
        c.idle(3.0)
        trace.fact("texts", _fence_texts(c, since_ms))
        trace.fact("fence_status.breach_status", _fence_status(c))
        trace.fact("mode_after", _mode_now(c))
    track = rec.since(pushed_s)
    held = [p for p in track if p[0] <= released_s]
    trace.fact("highest_m", round(max(p[3] for p in held), 1), HEIGHT)
    trace.fact("released.alt_m", round(held[-1][3], 1), HEIGHT)
    trace.fact("after_release.alt_m", round(track[-1][3], 1), HEIGHT)
    climbing = [p[5] for p in held if 11.0 < p[3] < 14.0]
    trace.fact("climb_m_s", round(statistics.median(climbing), 2) if climbing else None, RATE)
    p = _first(held, lambda p: p[3] >= 16.0)
    trace.fact("climb_at_16m_m_s", None if p is None else round(p[5], 1), SLOWING)


def avoid_off(c: Client, trace: Trace) -> None:
    sticks, rec = Sticks(c), Recorder(c)
    with c.listening(sticks), c.listening(rec):
        reach_flying(c, 10.0)  # the throttle at rest: ArduCopter will not arm with it at mid
        since_ms = c.now_ms
        _in_loiter(c, sticks)
        pushed_s = rec.now_s()
        sticks.hold(MID, FULL_FORWARD, MID, MID)
        c.try_wait(lambda: any("ence" in t for t in c.texts_since(since_ms)) and c.mode != LOITER, HOLD_S)
        breach_ms = next((stamp for stamp, _, text in c.texts if stamp >= since_ms and "ence" in text), None)
        sticks.hold(MID, MID, MID, MID)
        c.idle(8.0)
        trace.fact("texts", _fence_texts(c, since_ms))
        trace.fact("fence_status.breach_status", _fence_status(c))
        trace.fact("mode_after", _mode_now(c))
    track = rec.since(pushed_s)
    at = None if breach_ms is None else _first(track, lambda p: p[0] >= (breach_ms - rec.t0_ms) / 1000.0)
    trace.fact("breach_at_m", None if at is None else round(_distance(at), 1), BREACH)
    trace.fact("farthest_m", round(max(map(_distance, track)), 1), OVERSHOOT)
    trace.fact("fastest_m_s", round(max(p[4] for p in track), 1), SPEED)


def backup(c: Client, trace: Trace) -> None:
    sticks, rec = Sticks(c), Recorder(c)
    with c.listening(sticks), c.listening(rec):
        reach_flying(c, 10.0)  # the throttle at rest: ArduCopter will not arm with it at mid
        goto(c, RADIUS_M - 1.0, 0.0, 10.0)
        c.wait(lambda: math.hypot(c.last["GLOBAL_POSITION_INT"].vx, c.last["GLOBAL_POSITION_INT"].vy) < 20, 20,
               what="GUIDED's stop")
        c.idle(2.0)
        sticks.hold(MID, MID, MID, MID)
        since_ms = c.now_ms
        c.set_mode(LOITER)
        c.wait(lambda: c.mode == LOITER, 5, what="LOITER")
        loiter_s = rec.now_s()
        c.idle(10.5)
        trace.fact("texts", _fence_texts(c, since_ms))
        trace.fact("fence_status.breach_status", _fence_status(c))
        trace.fact("mode_after", _mode_now(c))
    track = rec.since(loiter_s)
    trace.fact("start.distance_m", round(_distance(track[0]), 1), Tol(abs=0.5, why="GUIDED's arrival within a metre"))
    for s in (1, 3, 6, 10):
        p = _first(track, lambda p: p[0] >= loiter_s + s)
        trace.fact(f"at_{s}s.distance_m", None if p is None else round(_distance(p), 1), BACKUP)
    trace.fact("fastest_m_s", round(max(p[4] for p in track if p[0] >= loiter_s + 0.5), 2),
               Tol(abs=0.3, why="AVOID_BACKUP_SPD, or a hover's drift"))


# ----- the breach itself ----------------------------------------------------------------------
class Watch(Recorder):
    """Recorder's track, and HEARTBEAT's (mode, system_status), SYS_STATUS's geofence bits
    [present, enabled, healthy] and FENCE_STATUS's fields, each stamped as it came."""

    def __init__(self, c: Client):
        super().__init__(c)
        self.beats: list[tuple[float, int, int]] = []
        self.geofence: list[tuple[float, list]] = []
        self.fence: list[tuple[float, object]] = []

    def __call__(self, msg) -> None:
        super().__call__(msg)
        kind, t = msg.get_type(), self.now_s()
        if kind == "HEARTBEAT":
            self.beats.append((t, msg.custom_mode, msg.system_status))
        elif kind == "SYS_STATUS":
            bit = mav.MAV_SYS_STATUS_GEOFENCE
            self.geofence.append((t, [int(bool(getattr(msg, f"onboard_control_sensors_{f}") & bit))
                                      for f in ("present", "enabled", "health")]))
        elif kind == "FENCE_STATUS":
            self.fence.append((t, msg))

    def at_ms(self, stamp_ms: int) -> float:
        return (stamp_ms - self.t0_ms) / 1000.0


def _runs(values) -> list:
    """The values with repeats in a row folded."""
    out = []
    for v in values:
        if not out or out[-1] != v:
            out.append(v)
    return out


def _fence_fields(m) -> list:
    """FENCE_STATUS's [breach_status, breach_type, breach_mitigation] (breach_count on its own:
    it counts the backup fences crossed too, which an overshoot may just reach or not)."""
    return [m.breach_status, m.breach_type, m.breach_mitigation]


def _texts(c: Client, since_ms: int) -> list:
    """[severity, text] of every STATUSTEXT since since_ms, background chatter left out."""
    return [[sev, text] for stamp, sev, text in c.texts
            if stamp >= since_ms and not any(p.search(text) for p in BACKGROUND)]


def _text_times(c: Client, since_ms: int, word: str) -> list[int]:
    return [stamp for stamp, _, text in c.texts if stamp >= since_ms and word in text]


def _crossings(track, outside) -> tuple[float | None, float | None]:
    """When the track first went outside, and when it was next back inside."""
    out = _first(track, outside)
    if out is None:
        return None, None
    back = _first([p for p in track if p[0] > out[0]], lambda p: not outside(p))
    return out[0], None if back is None else back[0]


def _state_facts(trace: Trace, w: Watch, start: float, out_s: float | None, in_s: float | None,
                 end: float) -> None:
    """system_status, the geofence bits and FENCE_STATUS before going outside, while outside
    (from a second after the crossing to a second before coming back) and after (from a second
    after coming back in); each a list of the values it took in turn."""
    windows = {"before": (start, (out_s if out_s is not None else end) - 1.0)}
    if out_s is not None:
        windows["breached"] = (out_s + 1.0, (in_s if in_s is not None else end) - 1.0)
    if in_s is not None:
        windows["cleared"] = (in_s + 1.0, end)
    for when, (a, b) in windows.items():
        trace.fact(f"{when}.system_status", _runs(t[2] for t in w.beats if a <= t[0] <= b))
        trace.fact(f"{when}.sys_status_geofence", _runs(g for t, g in w.geofence if a <= t <= b))
        fence = [m for t, m in w.fence if a <= t <= b]
        trace.fact(f"{when}.fence_status", _runs(_fence_fields(m) for m in fence))
        trace.fact(f"{when}.breach_count", fence[-1].breach_count if fence else None, COUNT)


def _modes(w: Watch, start: float) -> list[int]:
    return _runs(mode for t, mode, _ in w.beats if t >= start)


def _breach_time_facts(trace: Trace, w: Watch, out_s: float | None, in_s: float | None) -> None:
    """FENCE_STATUS.breach_time: set, and how it stands to the crossing; kept after clearing."""
    breached = [m for t, m in w.fence if m.breach_status]
    first = breached[0].breach_time if breached else None
    trace.fact("breach_time.nonzero", bool(first))
    trace.fact("breach_time.after_crossing_s",
               None if not first or out_s is None else round(w.at_ms(first) - out_s, 1), STAMP)
    if in_s is not None:
        after = [m.breach_time for t, m in w.fence if t >= in_s + 1.0]
        trace.fact("breach_time.after_clearing", None if not after else
                   "same" if after[-1] == first else "zero" if after[-1] == 0 else "changed")


def _at(track, t_s: float):
    return _first(track, lambda p: p[0] >= t_s)


def _first_at(w: Watch, stamps: list[int]) -> float | None:
    return w.at_ms(stamps[0]) if stamps else None


def _distance_at(track, t_s: float | None):
    p = None if t_s is None else _at(track, t_s)
    return None if p is None else round(_distance(p), 1)


def _outside_circle(p) -> bool:
    return _distance(p) >= RADIUS_M


def _out_through_circle(c: Client, sticks: Sticks, w: Watch, pitch: int = FULL_FORWARD) -> tuple[int, float]:
    """Up at 10 m, LOITER, the stick forward; (LOITER's switch [vehicle ms], the push [s])."""
    reach_flying(c, 10.0)  # the throttle at rest: ArduCopter will not arm with it at mid
    since_ms = c.now_ms
    _in_loiter(c, sticks)
    pushed_s = w.now_s()
    sticks.hold(MID, pitch, MID, MID)
    return since_ms, pushed_s


def breach_rtl(c: Client, trace: Trace) -> None:
    sticks, w = Sticks(c), Watch(c)
    with c.listening(sticks), c.listening(w):
        since_ms, pushed_s = _out_through_circle(c, sticks, w)
        c.wait(lambda: c.mode != LOITER, HOLD_S, what="the fence's mode change")
        sticks.hold(MID, MID, MID, MID)
        c.wait(lambda: w.points and _outside_circle(w.points[-1]), 10, what="outside")
        c.wait(lambda: not _outside_circle(w.points[-1]), 90, what="back inside")
        c.idle(AFTER_INSIDE_S)
        end_s = w.now_s()
    track = w.since(pushed_s)
    out_s, in_s = _crossings(track, _outside_circle)
    trace.fact("texts", _texts(c, since_ms))
    trace.fact("modes", _modes(w, pushed_s))
    breach = _text_times(c, since_ms, "breached")
    cleared = _text_times(c, since_ms, "cleared")
    trace.fact("breach_at_m", _distance_at(track, _first_at(w, breach)), BREACH)
    trace.fact("cleared_at_m", _distance_at(track, _first_at(w, cleared)), BREACH)
    trace.fact("farthest_m", round(max(map(_distance, track)), 1), OVERSHOOT)
    trace.fact("outside_s", None if out_s is None or in_s is None else round(in_s - out_s, 1), OUTSIDE)
    _state_facts(trace, w, pushed_s, out_s, in_s, end_s)
    _breach_time_facts(trace, w, out_s, in_s)


def breach_brake(c: Client, trace: Trace) -> None:
    sticks, w = Sticks(c), Watch(c)
    with c.listening(sticks), c.listening(w):
        since_ms, pushed_s = _out_through_circle(c, sticks, w)
        c.wait(lambda: c.mode != LOITER, HOLD_S, what="the fence's mode change")
        sticks.hold(MID, MID, MID, MID)
        c.idle(BRAKE_OUTSIDE_S)
        end_s = w.now_s()
        trace.fact("mode_after", _mode_now(c))
    track = w.since(pushed_s)
    out_s, in_s = _crossings(track, _outside_circle)
    trace.fact("texts", _texts(c, since_ms))
    trace.fact("modes", _modes(w, pushed_s))
    breach = _text_times(c, since_ms, "breached")
    trace.fact("breach_at_m", _distance_at(track, _first_at(w, breach)), BREACH)
    trace.fact("farthest_m", round(max(map(_distance, track)), 1),
               Tol(abs=3.0, why="BRAKE's stop from LOITER's top speed: two brakes"))
    trace.fact("end.distance_m", round(_distance(track[-1]), 1), Tol(abs=3.0, why="where BRAKE stopped it"))
    trace.fact("end.speed_m_s", round(track[-1][4], 1), Tol(abs=0.5, why="BRAKE holds it still"))
    _state_facts(trace, w, pushed_s, out_s, in_s, end_s)
    _breach_time_facts(trace, w, out_s, in_s)


def manual_recovery(c: Client, trace: Trace) -> None:
    sticks, w = Sticks(c), Watch(c)
    with c.listening(sticks), c.listening(w):
        since_ms, pushed_s = _out_through_circle(c, sticks, w)
        c.wait(lambda: c.mode != LOITER, HOLD_S, what="the fence's mode change", exact=True)
        trace.fact("fence_mode", c.mode)
        sticks.hold(MID, RECOVER_PITCH, MID, MID)
        trace.fact("loiter_result", c.set_mode(LOITER))
        recovery_s = w.now_s()
        trace.fact("recovery_start.distance_m", round(_distance(w.points[-1]), 1),
                   Tol(abs=3.0, why="how far past the fence it is as the ACK comes: the breach, RTL's first moment"))
        c.try_wait(lambda: c.mode == LOITER, 3.0)  # the HEARTBEAT saying so (a vehicle may beat only at 1 Hz)
        c.try_wait(lambda: c.mode != LOITER, 25.0)
        retook_s = w.now_s() if c.mode != LOITER else None
        sticks.hold(MID, MID, MID, MID)
        c.idle(5.0)
        end_s = w.now_s()
        trace.fact("mode_after", _mode_now(c))
    track = w.since(pushed_s)
    out_s, _ = _crossings(track, _outside_circle)
    trace.fact("texts", _texts(c, since_ms))
    trace.fact("modes", _modes(w, pushed_s))
    breaches = [w.at_ms(t) for t in _text_times(c, since_ms, "breached")[1:]]  # after the first, RTL's
    trace.fact("retaken_after_s", None if not breaches else round(breaches[0] - recovery_s, 1), RECOVERY)
    trace.fact("retaken_at_m", _distance_at(track, breaches[0] if breaches else None), RECOVERY_M)
    trace.fact("retaken_mode_after_s", None if retook_s is None else round(retook_s - recovery_s, 1), RECOVERY)
    held = [p for p in track if recovery_s <= p[0] <= (retook_s or end_s)]
    p = _at(held, recovery_s + 5.0)
    trace.fact("recovery_5s.speed_m_s", None if p is None else round(p[4], 1),
               Tol(abs=1.5, why="LOITER's speed at 40 % stick, down from the breach's 10 m/s"))
    trace.fact("farthest_m", round(max(map(_distance, track)), 1), RECOVERY_M)
    last = [m for t, m in w.fence]
    trace.fact("end.fence_status.breach_status", last[-1].breach_status if last else None)
    trace.fact("end.fence_status.breach_count", last[-1].breach_count if last else None, COUNT)
    trace.fact("end.fence_status.breach_type", last[-1].breach_type if last else None)
    _breach_time_facts(trace, w, out_s, None)


def report_only(c: Client, trace: Trace) -> None:
    sticks, w = Sticks(c), Watch(c)
    with c.listening(sticks), c.listening(w):
        since_ms, pushed_s = _out_through_circle(c, sticks, w, HALF_FORWARD)
        c.wait(lambda: w.points and _distance(w.points[-1]) >= REPORT_ONLY_TO_M, 40, what=f"{REPORT_ONLY_TO_M:g} m out")
        sticks.hold(MID, MID, MID, MID)
        c.idle(5.0)
        end_s = w.now_s()
        trace.fact("mode_after", _mode_now(c))
    track = w.since(pushed_s)
    out_s, in_s = _crossings(track, _outside_circle)
    trace.fact("texts", _texts(c, since_ms))
    trace.fact("modes", _modes(w, pushed_s))
    trace.fact("breaches_at_m", [_distance_at(track, w.at_ms(t)) for t in _text_times(c, since_ms, "breached")],
               BREACH)
    trace.fact("farthest_m", round(max(map(_distance, track)), 1), Tol(abs=3.0, why="LOITER's stop at half speed"))
    between = [p[0] for p in track if 50.0 <= _distance(p) <= 55.0]
    trace.fact("between.fence_status", _runs(_fence_fields(m) for t, m in w.fence
                                             if between and between[0] <= t <= between[-1]))
    _state_facts(trace, w, pushed_s, out_s, in_s, end_s)
    _breach_time_facts(trace, w, out_s, in_s)


def _above_ceiling(p) -> bool:
    return p[3] >= ALT_MAX_M


def alt_breach(c: Client, trace: Trace) -> None:
    sticks, w = Sticks(c), Watch(c)
    with c.listening(sticks), c.listening(w):
        reach_flying(c, 10.0)  # the throttle at rest: ArduCopter will not arm with it at mid
        since_ms = c.now_ms
        _in_loiter(c, sticks)
        pushed_s = w.now_s()
        sticks.hold(MID, MID, FULL_UP, MID)
        c.wait(lambda: c.mode != LOITER, 20, what="the fence's mode change")
        sticks.hold(MID, MID, MID, MID)
        c.wait(lambda: w.points and _above_ceiling(w.points[-1]), 10, what="above the ceiling")
        # back under by half a metre: RTL's settling may dip under the ceiling by a decimetre first
        c.wait(lambda: w.points[-1][3] < ALT_MAX_M - 0.5, 60, what="back under the ceiling")
        c.idle(AFTER_INSIDE_S)
        end_s = w.now_s()
        trace.fact("mode_after", _mode_now(c))
    track = w.since(pushed_s)
    out_s, in_s = _crossings(track, _above_ceiling)
    # Up to the first clearing only: RTL's settling onto a height 0.1-0.2 m over the ceiling may
    # dip under it once more on Firefly, now and then (so the facts after it would flicker)
    said = _texts(c, since_ms)
    cleared = next((i for i, (_, text) in enumerate(said) if text == "Fence breach cleared"), len(said) - 1)
    trace.fact("texts", said[:cleared + 1])
    trace.fact("modes", _modes(w, pushed_s))
    breach = _text_times(c, since_ms, "breached")
    p = None if not breach else _at(track, w.at_ms(breach[0]))
    trace.fact("breach_at_alt_m", None if p is None else round(p[3], 1), CEILING)
    trace.fact("highest_m", round(max(p[3] for p in track), 1), CEILING)
    trace.fact("end.alt_m", round(track[-1][3], 1), Tol(abs=2.5, why="RTL's height 10 s after: its stop over home, "
                                                                        "RTL_LOIT_TIME, then its descent"))
    trace.fact("end.distance_m", round(_distance(track[-1]), 1), Tol(abs=1.0, why="over home all along"))
    _state_facts(trace, w, pushed_s, out_s, None, end_s if in_s is None else in_s)
    _breach_time_facts(trace, w, out_s, None)


PROBES = {"loiter_circle": loiter_circle, "loiter_circle_stop": loiter_circle_stop, "loiter_slide": loiter_slide,
          "guided_velocity_polygon": guided_velocity_polygon, "altitude_max": altitude_max, "avoid_off": avoid_off,
          "backup": backup, "breach_rtl": breach_rtl, "breach_brake": breach_brake,
          "manual_recovery": manual_recovery, "report_only": report_only, "alt_breach": alt_breach}


def run(target) -> dict[str, Trace]:
    return each_on_a_fresh_vehicle(target, PROBES, PROBES_PARAMS)

"""Precision landing (AC_PrecLand) with SITL's beacon, as ArduCopter lands on it (issue 31).

on_target   PLND_TYPE 4 with a downward rangefinder; the beacon asked for 4 m north and 4 m west
            of home (SITL reads it through float32s: about a metre from there). Takeoff to 10 m in
            GUIDED, LAND: the texts, SYS_STATUS's vision-position bit on the ground, in the air and
            landed, and the landing: where it touches down, how fast it flies over, when it starts
            to descend, its slow final descent, how long it takes.
out_of_view the same with the beacon 30 m away, out of its 10 m view: the failsafe, its hold and a
            landing where the vehicle is.
companion   PLND_TYPE 1: a companion sends LANDING_TARGET (the local frame turned by the heading,
            a position and its distance) for a target 4 m north and 4 m west, with each position
            report from LAND on: the texts, the bit, where it touches down.
bad_frame   the same in MAV_FRAME_LOCAL_NED, a frame ArduCopter does not take: its text, and a
            landing at home.
rtl         SITL's beacon as on_target, the vehicle flown 10 m north first, then RTL (RTL_ALT 12 m,
            within the beacon's view): it lands on the beacon, not at home.
auto        the same beacon, a mission: takeoff to 10 m, land 10 m north of home: the land item
            comes down on the beacon.
lost_strict_1, lost_strict_0, lost_strict_2
            as on_target, the beacon switched off (SIM_PLD_ENABLE 0) once LAND is below 5 m, with
            PLND_STRICT 1 (ArduCopter's default: descend PLND_TIMEOUT, climb back 1.5 m over where
            it last saw the target, come back down, hold 7 s, land where it is), 0 (land where it
            is) and 2 (hold for good: disarmed by force after 15 s of it): the texts, the heights
            (lowest before the climb, highest in it, the hold's) and where it touches down.
lost_no_retries  as lost_strict_1 with PLND_RET_MAX 0: the failsafe where the retry would begin.
lost_found_again as lost_strict_1, the beacon on again as the retry begins: found, landed on.
lost_high   the target lost hovering at 10 m (above PLND_ALT_MAX, 8 m), then LAND: the failsafe at 8 m.
"""
from __future__ import annotations

import math
import statistics

from ..client import Client, mav
from ..facts import Tol, Trace
from .booting import each_on_a_fresh_vehicle
from . import missions
from .missions import upload
from .nav_flight import goto
from .states import GUIDED, reach_armed_on_ground

AREA = "precland"
# The reference's pace: the beacon switched off and on, and a companion's reports, are set in wall
# time, so at 20x a loaded machine moves them by vehicle seconds (a retry over before the beacon is on).
FIREFLY_SPEEDUP = "10"
M_PER_DEG = 111319.5
LAND = 9
VISION = mav.MAV_SYS_STATUS_SENSOR_VISION_POSITION
BOOT = {"PLND_ENABLED": 1, "PLND_TYPE": 4, "SIM_PLD_ENABLE": 1, "SIM_PLD_HEIGHT": 0, "SIM_PLD_ALT_LMT": 15,
        "SIM_PLD_DIST_LMT": 10, "RNGFND1_TYPE": 100, "RNGFND1_MAX": 30}
COMPANION = {"PLND_ENABLED": 1, "PLND_TYPE": 1, "RNGFND1_TYPE": 100, "RNGFND1_MAX": 30}
PROBES_PARAMS = {"on_target": BOOT, "out_of_view": BOOT, "companion": COMPANION, "bad_frame": COMPANION,
                 "rtl": {**BOOT, "RTL_ALT": 1200}, "auto": BOOT,
                 "lost_strict_1": {**BOOT, "PLND_STRICT": 1}, "lost_strict_0": {**BOOT, "PLND_STRICT": 0},
                 "lost_strict_2": {**BOOT, "PLND_STRICT": 2}, "lost_no_retries": {**BOOT, "PLND_RET_MAX": 0},
                 "lost_found_again": BOOT, "lost_high": BOOT}
RTL = 6
TARGET_NE = (4.0, -4.0)
TAKEOFF_M = 10.0
TRACK = Tol(abs=0.6, why="both position controllers' shaping, a 10 Hz track")


def _vision(c: Client) -> str:
    c.fresh("SYS_STATUS")
    s = c.last["SYS_STATUS"]
    return "".join(str(int(bool(mask & VISION))) for mask in (s.onboard_control_sensors_present,
                                                               s.onboard_control_sensors_enabled,
                                                               s.onboard_control_sensors_health))


def _place_beacon(c: Client, north_m: float, east_m: float) -> None:
    """SIM_PLD_LAT/LON by PARAM_SET (a boot file's %g would round them by metres on the reference)."""
    h = c.last["HOME_POSITION"]
    lat = h.latitude * 1e-7 + north_m / M_PER_DEG
    lon = h.longitude * 1e-7 + east_m / (M_PER_DEG * math.cos(math.radians(h.latitude * 1e-7)))
    c.set_param("SIM_PLD_LAT", lat)
    c.set_param("SIM_PLD_LON", lon)


def _ne(c: Client) -> tuple[float, float]:
    h, g = c.last["HOME_POSITION"], c.last["GLOBAL_POSITION_INT"]
    return ((g.lat - h.latitude) * 1e-7 * M_PER_DEG,
            (g.lon - h.longitude) * 1e-7 * M_PER_DEG * math.cos(math.radians(h.latitude * 1e-7)))


def _land(c: Client, trace: Trace, beacon_ne: tuple[float, float] | None, companion=None, first_north_m: float = 0.0,
          mode: int = LAND) -> tuple[int, list]:
    """Ready, take off, hover, LAND until disarmed (with `companion` hearing every message from
    LAND on); (LAND's vehicle time, the track)."""
    c.wait(lambda: "HOME_POSITION" in c.last and c.last["GPS_RAW_INT"].fix_type >= 3, 120, what="a fix")
    c.idle(20.0)  # past the EKF's settling
    if beacon_ne is not None:
        _place_beacon(c, *beacon_ne)
    c.idle(1.0)
    trace.fact("ground.vision", _vision(c))
    since = c.now_ms
    reach_armed_on_ground(c, GUIDED)
    c.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, TAKEOFF_M)
    c.wait(lambda: c.rel_alt_m() > TAKEOFF_M - 0.3, 60, what="the takeoff")
    c.idle(3.0)
    if first_north_m:
        goto(c, first_north_m, 0.0, TAKEOFF_M)
    trace.fact("hover.vision", _vision(c))
    trace.fact("hover.texts", [t for t in c.texts_since(since) if "PrecLand" in t or "Plnd" in t])
    track: list = []
    c.set_mode(mode)
    land_ms = c.now_ms
    def listen(m):
        if m.get_type() == "GLOBAL_POSITION_INT":
            track.append((c.now_ms - land_ms, *_ne(c), m.relative_alt / 1000, m.vx / 100, m.vy / 100, m.vz / 100))
        if companion is not None:
            companion(m)
    with c.listening(listen):
        c.wait(lambda: not c.armed, 120, what="the landing")
    trace.fact("landed.vision", _vision(c))
    texts = [t for t in c.texts_since(land_ms) if "PrecLand" in t or "Plnd" in t]
    if companion is None:
        trace.fact("land.texts", texts)
    else:  # a client's reports bunch in wall time: an "Init Failed" or a "Target Lost" comes and goes
        trace.fact("land.acquired", "PrecLand: Init Complete" in texts)
        trace.fact("land.said", sorted({t for t in texts if "Init" not in t and "Lost" not in t}))
    return land_ms, track


def on_target(c: Client, trace: Trace) -> None:
    _, track = _land(c, trace, (4.0, -4.0))
    n, e = track[-1][1], track[-1][2]
    trace.fact("touchdown.north_m", round(n, 2), Tol(abs=0.1, why="both land on the beacon to centimetres"))
    trace.fact("touchdown.east_m", round(e, 2), Tol(abs=0.1, why="as touchdown.north_m"))
    touchdown = next(t for t, *_, alt, vx, vy, vz in track if alt < 0.05)
    trace.fact("touchdown.after_s", round(touchdown / 1000, 1), Tol(abs=2.0, why="a 26 s landing's descents"))
    trace.fact("over.fastest_m_s", round(max(math.hypot(vx, vy) for *_, vx, vy, vz in track), 1), TRACK)
    descending = next(t for t, *_, vz in track if vz > 0.3 and t > 500)
    trace.fact("over.descends_after_s", round(descending / 1000, 1),
               Tol(abs=0.8, why="ArduCopter's jerk-limited shaping starts the move over 0.5 s later than "
                                "Firefly's position loop, which reaches the 2.5 m ring that much sooner"))
    slow = [vz for t, n_, e_, alt, vx, vy, vz in track if 0.5 < alt < 1.5]
    trace.fact("final.descent_m_s", round(statistics.median(slow), 2) if slow else None,
               Tol(abs=0.06, why="the slowdown's 0.10-0.25 m/s law on each position error"))


def out_of_view(c: Client, trace: Trace) -> None:
    _, track = _land(c, trace, (30.0, 0.0))
    n, e = track[-1][1], track[-1][2]
    trace.fact("touchdown.from_home_m", round(math.hypot(n, e), 1), Tol(abs=0.3, why="it lands where it is"))
    holding = [t for t, n_, e_, alt, vx, vy, vz in track if abs(vz) < 0.05 and 1.0 < alt < TAKEOFF_M - 0.5]
    trace.fact("hold.seconds", round((max(holding) - min(holding)) / 1000, 1) if holding else 0.0,
               Tol(abs=1.0, why="7 s, from when the descent stops"))
    trace.fact("hold.height_m", round(statistics.median(alt for t, n_, e_, alt, *_ in track
                                                        if holding and min(holding) <= t <= max(holding)), 1)
               if holding else None, Tol(abs=0.5, why="where the rangefinder passes PLND_ALT_MAX"))


def _landing_target(c: Client, frame: int):
    """A companion that sees the target at TARGET_NE: LANDING_TARGET with each position report."""
    def send(m):
        if m.get_type() != "GLOBAL_POSITION_INT" or "ATTITUDE" not in c.last:
            return
        n, e = _ne(c)
        rel = (TARGET_NE[0] - n, TARGET_NE[1] - e, m.relative_alt / 1000)
        yaw = c.last["ATTITUDE"].yaw
        x, y = math.cos(yaw) * rel[0] + math.sin(yaw) * rel[1], -math.sin(yaw) * rel[0] + math.cos(yaw) * rel[1]
        distance = math.sqrt(rel[0] ** 2 + rel[1] ** 2 + rel[2] ** 2)
        c.conn.mav.landing_target_send(0, 0, frame, 0, 0, distance, 0, 0, x, y, rel[2], (1, 0, 0, 0),
                                       mav.LANDING_TARGET_TYPE_VISION_FIDUCIAL, 1)
    return send


def companion(c: Client, trace: Trace) -> None:
    _, track = _land(c, trace, None, _landing_target(c, mav.MAV_FRAME_LOCAL_FRD))
    trace.fact("touchdown.north_m", round(track[-1][1], 1), Tol(abs=0.15, why="the companion's 10 Hz reports"))
    trace.fact("touchdown.east_m", round(track[-1][2], 1), Tol(abs=0.15, why="as touchdown.north_m"))


def bad_frame(c: Client, trace: Trace) -> None:
    _, track = _land(c, trace, None, _landing_target(c, mav.MAV_FRAME_LOCAL_NED))
    trace.fact("touchdown.from_home_m", round(math.hypot(track[-1][1], track[-1][2]), 1),
               Tol(abs=0.3, why="it lands where it is"))


def rtl(c: Client, trace: Trace) -> None:
    _, track = _land(c, trace, (4.0, -4.0), first_north_m=10.0, mode=RTL)
    trace.fact("touchdown.north_m", round(track[-1][1], 2), Tol(abs=0.1, why="both land on the beacon"))
    trace.fact("touchdown.east_m", round(track[-1][2], 2), Tol(abs=0.1, why="as touchdown.north_m"))


def auto(c: Client, trace: Trace) -> None:
    c.wait(lambda: "HOME_POSITION" in c.last and c.last["GPS_RAW_INT"].fix_type >= 3, 120, what="a fix")
    c.idle(20.0)
    _place_beacon(c, *TARGET_NE)
    h = c.last["HOME_POSITION"]
    land = (mav.MAV_CMD_NAV_LAND, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, 0, 0, 0, 0,
            h.latitude + round(10.0 / M_PER_DEG * 1e7), h.longitude, 0)
    trace.fact("upload", upload(c, [missions.takeoff(TAKEOFF_M), land]))
    reach_armed_on_ground(c, GUIDED)
    since = c.now_ms
    trace.fact("start", c.command(mav.MAV_CMD_MISSION_START))
    c.wait(lambda: not c.armed, 150, what="the mission's landing")
    trace.fact("texts", [t for t in c.texts_since(since) if "PrecLand" in t])
    n, e = _ne(c)
    trace.fact("touchdown.north_m", round(n, 2), Tol(abs=0.1, why="both land on the beacon"))
    trace.fact("touchdown.east_m", round(e, 2), Tol(abs=0.1, why="as touchdown.north_m"))


LOSE_BELOW_M = 5.0
HEIGHT = Tol(abs=0.5, why="both position controllers' shaping of the climb and the descent, a 10 Hz track")


def _lost(c: Client, trace: Trace, strict: int, lose_below_m: float = LOSE_BELOW_M, back_on_retry: bool = False) -> None:
    """LAND onto the beacon, the beacon off below lose_below_m (and on again as the retry starts
    when back_on_retry): what each PLND_STRICT does. Above the hover, the beacon is off before
    LAND, and the target lost ("PrecLand: Target Lost") when LAND begins."""
    c.wait(lambda: "HOME_POSITION" in c.last and c.last["GPS_RAW_INT"].fix_type >= 3, 120, what="a fix")
    c.idle(20.0)
    _place_beacon(c, *TARGET_NE)
    c.idle(1.0)
    reach_armed_on_ground(c, GUIDED)
    c.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, TAKEOFF_M)
    c.wait(lambda: c.rel_alt_m() > TAKEOFF_M - 0.3, 60, what="the takeoff")
    c.idle(3.0)
    since = c.now_ms
    if lose_below_m > TAKEOFF_M:
        c.set_param("SIM_PLD_ENABLE", 0)
        c.wait(lambda: any("Target Lost" in t for t in c.texts_since(since)), 10, what="the target lost")
    track: list = []
    c.set_mode(LAND)
    land_ms = c.now_ms
    def listen(m):
        if m.get_type() == "GLOBAL_POSITION_INT":
            track.append((c.now_ms - land_ms, *_ne(c), m.relative_alt / 1000, m.vz / 100))
    with c.listening(listen):
        c.wait(lambda: c.rel_alt_m() < lose_below_m, 90, what="the descent onto the beacon")
        c.set_param("SIM_PLD_ENABLE", 0)
        lost_ms = c.now_ms - land_ms
        lost_ne = _ne(c)
        if back_on_retry:
            c.wait(lambda: any("Retrying" in t for t in c.texts_since(land_ms)), 60, what="the retry")
            c.set_param("SIM_PLD_ENABLE", 1)
        if strict == 2:
            c.wait(lambda: any("Failsafe" in t for t in c.texts_since(land_ms)), 90, what="the failsafe")
            c.idle(15.0)
            trace.fact("hold.armed", c.armed)
            trace.fact("hold.height_m", round(c.rel_alt_m(), 1), HEIGHT)
            c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0, 21196)
        c.wait(lambda: not c.armed, 150, what="the landing")
    trace.fact("texts", [t for t in c.texts_since(since) if "PrecLand" in t or "Plnd" in t])
    after = [(t, n, e, alt, vz) for t, n, e, alt, vz in track if t >= lost_ms]
    climb = next((t for t, n, e, alt, vz in after if vz < -0.2), None)
    trace.fact("climb.after_s", None if climb is None else round((climb - lost_ms) / 1000, 1),
               Tol(abs=1.0, why="PLND_TIMEOUT from the last reading, the climb's start on a 10 Hz track"))
    before = [alt for t, n, e, alt, vz in after if climb is None or t <= climb]
    trace.fact("lowest_before_climb_m", round(min(before), 1), HEIGHT)
    trace.fact("highest_after_loss_m", round(max(alt for *_, alt, vz in after), 1), HEIGHT)
    if strict == 1 and not back_on_retry:
        top_t = max(after, key=lambda r: r[3])[0]
        holding = [t for t, n, e, alt, vz in after if t > top_t and abs(vz) < 0.05 and 1.0 < alt < TAKEOFF_M - 0.5]
        trace.fact("hold.seconds", round((max(holding) - min(holding)) / 1000, 1) if holding else 0.0,
                   Tol(abs=1.0, why="7 s, from when the descent stops"))
        trace.fact("hold.height_m", round(statistics.median(alt for t, n, e, alt, vz in after
                                                            if holding and min(holding) <= t <= max(holding)), 1)
                   if holding else None, HEIGHT)
    n, e = track[-1][1], track[-1][2]
    trace.fact("touchdown.from_lost_m", round(math.hypot(n - lost_ne[0], e - lost_ne[1]), 1),
               Tol(abs=0.3, why="where it was when the target went, give or take the retry's return"))
    trace.fact("touchdown.north_m", round(n, 1), Tol(abs=0.3, why="on the beacon, or where it was steered last"))
    trace.fact("touchdown.east_m", round(e, 1), Tol(abs=0.3, why="as touchdown.north_m"))


def lost_strict_1(c: Client, trace: Trace) -> None:
    _lost(c, trace, 1)


def lost_strict_0(c: Client, trace: Trace) -> None:
    _lost(c, trace, 0)


def lost_strict_2(c: Client, trace: Trace) -> None:
    _lost(c, trace, 2)


def lost_no_retries(c: Client, trace: Trace) -> None:
    """PLND_RET_MAX 0: the failsafe where the retry would have begun."""
    _lost(c, trace, 1)


def lost_found_again(c: Client, trace: Trace) -> None:
    """The beacon on again as the retry climbs: found again, it lands on it."""
    _lost(c, trace, 1, back_on_retry=True)


def lost_high(c: Client, trace: Trace) -> None:
    """The target lost hovering at 10 m, above PLND_ALT_MAX (8 m), then LAND: out of range, then
    never seen (ArduCopter forgets a target lost out of range): the failsafe's hold at 8 m."""
    _lost(c, trace, 1, lose_below_m=TAKEOFF_M + 1.0)


PROBES = {"on_target": on_target, "out_of_view": out_of_view, "companion": companion, "bad_frame": bad_frame,
          "rtl": rtl, "auto": auto, "lost_strict_1": lost_strict_1, "lost_strict_0": lost_strict_0,
          "lost_strict_2": lost_strict_2, "lost_no_retries": lost_no_retries, "lost_found_again": lost_found_again,
          "lost_high": lost_high}


def run(target) -> dict[str, Trace]:
    return each_on_a_fresh_vehicle(target, PROBES, PROBES_PARAMS)

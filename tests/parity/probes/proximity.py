"""A 360-degree proximity sensor (AP_Proximity, PRX1_TYPE read at power-on) as ArduCopter reports
and uses it: the DISTANCE_SENSOR messages it sends for its sectors, SYS_STATUS's proximity bits,
simple avoidance with AVOID_ENABLE 2 (the sensor only: the geofence is off, FENCE_ENABLE 0,
unless said), AVOID_MARGIN 2, the pre-arm check and ALT_HOLD's lean away. Each probe on a fresh
vehicle; the sticks held by RC override (throttle and yaw at mid) from just before LOITER or
ALT_HOLD, the vehicle taken off in GUIDED to 10 m facing north (WP_YAW_BEHAVIOR 0).

sitl_sectors        PRX1_TYPE 10 (SITL's lidar: the distance to the inclusion polygon fence in 8
                    sectors of 45 degrees, and up to FENCE_ALT_MAX 50): on the ground before and
                    after uploading a square +-30 m about home, then hovering 10 m north of home
                    facing north and facing 45 degrees (CONDITION_YAW): every DISTANCE_SENSOR for
                    3 s (per id: [id, orientation, min, max, type], the latest current_distance
                    and the rate), SYS_STATUS's proximity bits [present, enabled, healthy]; then
                    the rates with EXTRA3 asked at 2 Hz and with every stream at 4 Hz (which
                    stream carries them); whether OBSTACLE_DISTANCE is ever sent; the texts.
sitl_loiter_stop    the same sensor and square, the fence not enabled (whether the lidar still
                    sees it; if not, FENCE_ENABLE 1 with FENCE_ACTION 0): LOITER, the pitch stick
                    full forward (north) for 20 s: where it stops, the closest forward reading,
                    the fastest speed, where it first slows under 1 m/s.
companion_obstacle  PRX1_TYPE 2 (MAVLink): a companion (system 1, component 196) sends
                    OBSTACLE_DISTANCE at 10 Hz, MAV_FRAME_BODY_FRD, 72 sectors of 5 degrees (20 cm
                    to 3000 cm), a wall 20 m north of home seen straight ahead (+-15 degrees), the
                    rest max_distance + 1 (no obstacle): the bits before and after it starts, the
                    DISTANCE_SENSOR messages the vehicle sends back, and the same LOITER push.
companion_distance_sensor  PRX1_TYPE 2, the companion's DISTANCE_SENSOR facing forward (id 0,
                    20-2000 cm) at 10 Hz, a wall 15 m north of home: the same LOITER push.
companion_obstacle_3d  PRX1_TYPE 2, the companion's OBSTACLE_DISTANCE_3D (body FRD, 0.2-30 m), at 10 Hz a
                    batch of two points of one wall 17 m north of home, with one time stamp: straight
                    ahead, and 30 degrees right: the bits, the DISTANCE_SENSOR messages and the same
                    LOITER push; then a point in MAV_FRAME_LOCAL_NED only (ArduCopter takes body FRD
                    alone): whether the sensor stays healthy on it
companion_guided    PRX1_TYPE 2, companion_obstacle's wall 20 m north: GUIDED velocity targets
                    (SET_POSITION_TARGET_LOCAL_NED) of 3 m/s north at 5 Hz for 20 s: where it
                    stops short of the wall (AVOID_MARGIN 2), its cruise and where it slows.
prearm              PRX1_TYPE 2: ARM in LOITER with no companion yet, then with an obstacle straight
                    ahead at 1 m, 0.5 m and 5 m (the check wants more than 0.6 m): the COMMAND_ACK
                    result, the ARM's own texts and the pre-arm texts that name the sensor.
althold_push        PRX1_TYPE 2, AVOID_DIST_MAX 5, AVOID_ANGLE_MAX 10 degrees: ALT_HOLD with the
                    sticks centred, then a wall appears 3 m ahead of where it hovers (fixed in the
                    world, so the report grows as it is pushed away): its north position 0, 2, 5
                    and 10 s on; then the pitch stick full forward for 5 s: whether it still
                    approaches and passes the wall.
"""
from __future__ import annotations

import math
from contextlib import ExitStack, contextmanager

from pymavlink.dialects.v20 import ardupilotmega as v20

from ..client import Client, mav
from ..facts import Tol, Trace
from ..targets import wait_armable
from .booting import each_on_a_fresh_vehicle
from .avoid import Companion as VelocityTargets
from .avoid import FULL_FORWARD, Recorder, _first, _in_loiter, _mode_now, _slowed_at, _square, _texts
from .missions import upload
from .nav_flight import goto, ne_alt
from .pilot import MID, Sticks
from .states import ALT_HOLD, LOITER, reach_flying

AREA = "proximity"
PROXIMITY = mav.MAV_SYS_STATUS_SENSOR_PROXIMITY
OBSTACLE_AVOIDANCE = mav.MAV_COMP_ID_OBSTACLE_AVOIDANCE  # 196
HOLD_S = 20.0
WINDOW_S = 3.0
SETTLE_MS = 200  # read on past the window so every message stamped inside it has come
SEND_EVERY_MS = 100  # the companion's messages at 10 Hz of vehicle time
SECTORS, INCREMENT_DEG = 72, 5
AHEAD_DEG = 15.0
OBSTACLE_MIN_CM, OBSTACLE_MAX_CM = 20, 3000
SENSOR_MIN_CM, SENSOR_MAX_CM = 20, 2000
NORTH_M = 10.0  # sitl_sectors hovers this far north of home
WALL_OBSTACLE_M, WALL_SENSOR_M, WALL_3D_M = 20.0, 15.0, 17.0  # the companions' walls, north of home
RIGHT_3D_DEG = 30.0  # the 3-D companion's second point of its wall
PUSH_WALL_M = 3.0  # althold_push's wall, ahead of where ALT_HOLD starts
GUIDED_SPEED_M_S = 3.0  # companion_guided's velocity targets, north

COMMON = {"FENCE_ENABLE": 0, "FENCE_ACTION": 0, "AVOID_ENABLE": 2, "AVOID_MARGIN": 2, "WP_YAW_BEHAVIOR": 0}
SITL = {**COMMON, "PRX1_TYPE": 10, "FENCE_ALT_MAX": 50}
MAVLINK = {**COMMON, "PRX1_TYPE": 2}
PROBES_PARAMS = {
    "sitl_sectors": SITL,
    "sitl_loiter_stop": SITL,
    "companion_obstacle": MAVLINK,
    "companion_distance_sensor": MAVLINK,
    "companion_obstacle_3d": MAVLINK,
    "companion_guided": MAVLINK,
    "prearm": MAVLINK,
    "althold_push": {**MAVLINK, "AVOID_DIST_MAX": 5, "AVOID_ANGLE_MAX": 1000},
}

GROUND_CM = Tol(abs=50.0, why="on the ground at home: the estimate's place and the airframe's height within "
                              "half a metre")
HOVER_CM = Tol(abs=150.0, why="hovering where GUIDED arrived (within a metre), a square root of two more along "
                              "the diagonals, where a degree of heading is half a metre too (the reference "
                              "hovered a degree west of north); SITL's lidar bisects to 10 cm")
RATE = Tol(abs=1.5, why="messages counted over 3 s of vehicle time: one either side of the window, a busy link")
STOP = Tol(abs=1.0, why="where proximity avoidance stops it: the wall less AVOID_MARGIN, plus each position "
                        "controller's overshoot of its shaped stop and 10 Hz telemetry at up to 1 m/s")
COMPANION_STOP = Tol(abs=1.5, why=STOP.why + "; the wall's readings come from this client, so where "
                   "they fall in the vehicle's time moves the stop: Firefly's stop with a companion's "
                   "DISTANCE_SENSOR or OBSTACLE_DISTANCE_3D spread 13.1-14.4 m over six runs")
SPEED = Tol(abs=1.0, rel=0.15, why="LOITER's top speed on the way (under LOIT_SPEED, capped by the distance "
                                   "left), as two loiter shapers reach it")
DRIFT = Tol(abs=0.7, why="straight north: drift")
YAW = Tol(abs=3.0, why="a heading held or turned to, within degrees")
PUSHED = Tol(abs=1.0, rel=0.3, why="ALT_HOLD holds no position: how far AVOID_ANGLE_MAX's lean carries each "
                                   "airframe against its drag")


# ----- helpers --------------------------------------------------------------------------------
def _bits(c: Client) -> list[int]:
    """SYS_STATUS's proximity bit sent from now on: [present, enabled, healthy]."""
    c.fresh("SYS_STATUS")
    s = c.last["SYS_STATUS"]
    return [int(bool(getattr(s, f"onboard_control_sensors_{f}") & PROXIMITY)) for f in ("present", "enabled", "health")]


def _sensors(c: Client, sim_s: float = WINDOW_S) -> list:
    """Every DISTANCE_SENSOR the vehicle stamps within the next sim_s of vehicle time. The window
    is cut by each message's own time_boot_ms: on a loaded machine the client reads a backlog
    when it starts listening and a batch past the end, which would count a second too many."""
    got: list = []
    start_ms = c.now_ms
    end_ms = start_ms + sim_s * 1000

    def take(msg) -> None:
        if msg.get_type() == "DISTANCE_SENSOR" and start_ms <= msg.time_boot_ms < end_ms:
            got.append(msg)
    with c.listening(take):
        c.wait(lambda: c.now_ms >= end_ms + SETTLE_MS, sim_s + 5, what="vehicle time")
    return got


def _window(c: Client, trace: Trace, name: str, tol: Tol | None, rates_only: bool = False) -> dict:
    """DISTANCE_SENSOR for WINDOW_S: per id (sorted) [id, orientation, min, max, type], the latest
    current_distance and the rate; {id: latest}."""
    got = _sensors(c)
    latest, counts = {}, {}
    for m in got:
        latest[m.id] = m
        counts[m.id] = counts.get(m.id, 0) + 1
    ids = sorted(latest)
    if not rates_only:
        trace.fact(f"{name}.sensors", [[i, latest[i].orientation, latest[i].min_distance, latest[i].max_distance,
                                         latest[i].type] for i in ids])
        trace.fact(f"{name}.distances_cm", [latest[i].current_distance for i in ids], tol)
    trace.fact(f"{name}.ids", ids)
    trace.fact(f"{name}.rates_hz", [round(counts[i] / WINDOW_S, 1) for i in ids], RATE)
    return latest


def _heading_deg(c: Client) -> float:
    return math.degrees(c.last["ATTITUDE"].yaw) % 360.0


def _north(c: Client) -> float:
    if "HOME_POSITION" in c.last and "GLOBAL_POSITION_INT" in c.last:
        return ne_alt(c)[0]
    return 0.0


def _streams(c: Client) -> None:
    c.request_streams(10)
    c.wait(lambda: "ATTITUDE" in c.last, 60, what="requested streams")


def _wait_home(c: Client) -> None:
    c.wait(lambda: "HOME_POSITION" in c.last and "GPS_RAW_INT" in c.last and c.last["GPS_RAW_INT"].fix_type >= 3,
           120, what="home")


class Companion:
    """A companion computer (system 1, component 196) reporting an obstacle straight ahead every
    SEND_EVERY_MS of vehicle time while on, driven by the vehicle's messages: a wall `wall_north`
    metres north of home (the distance ahead is the wall less the vehicle's north), or `ahead_m`
    fixed; neither: nothing seen. OBSTACLE_DISTANCE, or DISTANCE_SENSOR facing forward."""

    def __init__(self, c: Client, distance_sensor: bool = False, points_3d: bool = False):
        self.c = c
        self.distance_sensor = distance_sensor
        self.points_3d = points_3d
        self.frame_3d = v20.MAV_FRAME_BODY_FRD
        self.on = False
        self.wall_north: float | None = None
        self.ahead_m: float | None = None
        self.sent_ms = -SEND_EVERY_MS

    def distance_m(self) -> float | None:
        if self.ahead_m is not None:
            return self.ahead_m
        if self.wall_north is not None:
            return self.wall_north - _north(self.c)
        return None

    def __call__(self, msg) -> None:
        if self.on and self.c.now_ms - self.sent_ms >= SEND_EVERY_MS:
            self.sent_ms = self.c.now_ms
            self.send()

    def send(self) -> None:
        link = self.c.conn.mav
        old = link.srcSystem, link.srcComponent
        link.srcSystem, link.srcComponent = 1, OBSTACLE_AVOIDANCE
        try:
            d = self.distance_m()
            if self.points_3d:
                self._send_3d(d)
            elif self.distance_sensor:
                cm = SENSOR_MAX_CM + 1 if d is None or d <= 0 else min(max(round(d * 100), SENSOR_MIN_CM),
                                                                        SENSOR_MAX_CM + 1)
                link.distance_sensor_send(self.c.now_ms, SENSOR_MIN_CM, SENSOR_MAX_CM, cm,
                                          mav.MAV_DISTANCE_SENSOR_LASER, 0, mav.MAV_SENSOR_ROTATION_NONE, 0)
            else:
                none = OBSTACLE_MAX_CM + 1  # "no obstacle" (MAVLink's max_distance + 1)
                cm = none if d is None or d <= 0 else min(max(round(d * 100), OBSTACLE_MIN_CM), none)
                distances = [cm if min(j * INCREMENT_DEG, 360 - j * INCREMENT_DEG) <= AHEAD_DEG else none
                             for j in range(SECTORS)]
                link.obstacle_distance_send(self.c.now_ms * 1000, mav.MAV_DISTANCE_SENSOR_LASER, distances,
                                            INCREMENT_DEG, OBSTACLE_MIN_CM, OBSTACLE_MAX_CM, 0.0, 0.0,
                                            mav.MAV_FRAME_BODY_FRD)
        finally:
            link.srcSystem, link.srcComponent = old


    def _send_3d(self, d: float | None) -> None:
        """OBSTACLE_DISTANCE_3D, a MAVLink 2 message: the wall ahead and 30 degrees right, one stamp."""
        if d is None or d <= 0:
            return
        link = v20.MAVLink(self.c.conn, srcSystem=1, srcComponent=OBSTACLE_AVOIDANCE)
        for obstacle_id, (x, y) in enumerate(((d, 0.0), (d, d * math.tan(math.radians(RIGHT_3D_DEG))))):
            link.obstacle_distance_3d_send(self.c.now_ms, mav.MAV_DISTANCE_SENSOR_LASER, self.frame_3d, obstacle_id,
                                           x, y, 0.0, OBSTACLE_MIN_CM / 100.0, OBSTACLE_MAX_CM / 100.0)


def _ready(c: Client, companion: Companion, trace: Trace | None = None) -> None:
    """A vehicle booted without streams: streams asked for, the companion started, ready to arm
    (a MAVLink sensor with no data fails the pre-arm checks). With trace, the proximity bits
    before and after the companion starts."""
    _streams(c)
    if trace is not None:
        c.idle(2.0)
        trace.fact("silent.proximity_bits", _bits(c))
    companion.on = True
    c.idle(1.0)
    if trace is not None:
        trace.fact("fed.proximity_bits", _bits(c))
    wait_armable(c)


@contextmanager
def _up_beside(c: Client, companion: Companion, *listeners, trace: Trace | None = None):
    """The companion speaking, the vehicle ready (with trace, _ready's facts) and up at 10 m in
    GUIDED, with `listeners` hearing the vehicle from before the takeoff."""
    with c.listening(companion):
        _ready(c, companion, trace)
        _wait_home(c)
        with ExitStack() as stack:
            for listener in listeners:
                stack.enter_context(c.listening(listener))
            reach_flying(c, 10.0)
            yield


def _push(c: Client, trace: Trace, rec: Recorder, sticks: Sticks, forward: list | None = None,
          stop: Tol = STOP) -> None:
    """Up at 10 m, LOITER, the pitch stick full forward for HOLD_S, released for 3 s: the stop's
    facts. `forward` collects the vehicle's forward DISTANCE_SENSOR readings [cm] while held."""
    reach_flying(c, 10.0)  # the throttle at rest: ArduCopter will not arm with it at mid
    trace.fact("start.heading_deg", round(_heading_deg(c)) % 360, YAW)
    since_ms = c.now_ms
    _in_loiter(c, sticks)
    pushed_s = rec.now_s()
    sticks.hold(MID, FULL_FORWARD, MID, MID)

    def reading(msg) -> None:
        if forward is not None and msg.get_type() == "DISTANCE_SENSOR" and msg.orientation == 0:
            forward.append(msg.current_distance)
    with c.listening(reading):
        c.idle(HOLD_S)
    released_s = rec.now_s()
    sticks.hold(MID, MID, MID, MID)
    c.idle(3.0)
    trace.fact("texts", _texts(c, since_ms))
    trace.fact("mode_after", _mode_now(c))
    track = rec.since(pushed_s)
    held = [p for p in track if p[0] <= released_s]
    trace.fact("farthest_north_m", round(max(p[1] for p in held), 1), stop)
    trace.fact("released.north_m", round(held[-1][1], 1), stop)
    trace.fact("released.east_m", round(held[-1][2], 1), DRIFT)
    trace.fact("after_release.north_m", round(track[-1][1], 1), stop)
    trace.fact("fastest_m_s", round(max(p[4] for p in held), 1), SPEED)
    trace.fact("slowed_below_1_m_s_at_north_m", _slowed_at(held, lambda p: p[1], 3.0), STOP)


# ----- the probes -----------------------------------------------------------------------------
def sitl_sectors(c: Client, trace: Trace) -> None:
    _streams(c)
    _wait_home(c)
    c.idle(5.0)
    trace.fact("boot.proximity_bits", _bits(c))
    _window(c, trace, "boot", GROUND_CM)
    result, texts = _arm(c)
    trace.fact("boot.arm", result)
    trace.fact("boot.arm_texts", texts)
    trace.fact("upload", upload(c, _square(c), kind=mav.MAV_MISSION_TYPE_FENCE))
    c.idle(1.0)
    trace.fact("uploaded.proximity_bits", _bits(c))
    _window(c, trace, "uploaded", GROUND_CM)
    wait_armable(c)  # the lidar has data only once there is a fence to measure
    reach_flying(c, 10.0)
    goto(c, NORTH_M, 0.0, 10.0)
    c.idle(2.0)
    trace.fact("north.heading_deg", round(_heading_deg(c)) % 360, YAW)
    trace.fact("north.proximity_bits", _bits(c))
    _window(c, trace, "north", HOVER_CM)
    trace.fact("yaw45.result", c.command(mav.MAV_CMD_CONDITION_YAW, 45, 0, 1, 0))
    c.try_wait(lambda: abs(_heading_deg(c) - 45.0) < 1.0, 20)
    c.idle(2.0)
    trace.fact("yaw45.heading_deg", round(_heading_deg(c)), YAW)
    _window(c, trace, "yaw45", HOVER_CM)
    c.conn.mav.request_data_stream_send(1, 1, mav.MAV_DATA_STREAM_EXTRA3, 2, 1)
    c.idle(1.0)
    _window(c, trace, "extra3_2hz", None, rates_only=True)
    c.request_streams(4)
    c.idle(1.0)
    _window(c, trace, "all_4hz", None, rates_only=True)
    c.request_streams(10)
    c.idle(1.0)
    trace.fact("obstacle_distance_sent", c.received.get("OBSTACLE_DISTANCE", 0) > 0)
    trace.fact("texts", _texts(c, 0))


def sitl_loiter_stop(c: Client, trace: Trace) -> None:
    _streams(c)
    _wait_home(c)
    trace.fact("upload", upload(c, _square(c), kind=mav.MAV_MISSION_TYPE_FENCE))
    c.idle(1.0)

    def sees() -> bool:
        return any(m.orientation <= 7 for m in _sensors(c))
    seen = sees()
    trace.fact("sees_fence_not_enabled", seen)
    if not seen:  # SITL's lidar wants the fence enabled: then FENCE_ACTION 0 and AVOID_ENABLE 2 still
        trace.fact("fence_enable", c.set_param("FENCE_ENABLE", 1))
        c.idle(1.0)
        trace.fact("sees_fence_enabled", sees())
    wait_armable(c)
    sticks, rec, forward = Sticks(c), Recorder(c), []
    with c.listening(sticks), c.listening(rec):
        _push(c, trace, rec, sticks, forward)
    trace.fact("closest_forward_cm", min(forward) if forward else None, Tol(abs=100.0, why=STOP.why))


def companion_obstacle(c: Client, trace: Trace) -> None:
    _companion_push(c, trace, Companion(c), WALL_OBSTACLE_M, "20 m less where the hover is, within a metre",
                    ready_trace=True)
    trace.fact("obstacle_distance_sent", c.received.get("OBSTACLE_DISTANCE", 0) > 0)


def companion_distance_sensor(c: Client, trace: Trace) -> None:
    _companion_push(c, trace, Companion(c, distance_sensor=True), WALL_SENSOR_M,
                    "15 m less where the hover is, within a metre")


def companion_obstacle_3d(c: Client, trace: Trace) -> None:
    companion = Companion(c, points_3d=True)
    _companion_push(c, trace, companion, WALL_3D_M, "17 m less where the hover is, within a metre")
    with c.listening(companion):
        companion.frame_3d = v20.MAV_FRAME_LOCAL_NED
        c.idle(2.0)
        trace.fact("local_ned.proximity_bits", _bits(c))


def companion_guided(c: Client, trace: Trace) -> None:
    """GUIDED toward the companion's wall: velocity targets of GUIDED_SPEED_M_S north for HOLD_S."""
    companion = Companion(c)
    companion.wall_north = WALL_OBSTACLE_M
    targets, rec = VelocityTargets(c), Recorder(c)
    with _up_beside(c, companion, targets, rec):
        c.idle(1.0)
        since_ms, pushed_s = c.now_ms, rec.now_s()
        targets.velocity = (GUIDED_SPEED_M_S, 0.0, 0.0)
        c.idle(HOLD_S)
        trace.fact("texts", _texts(c, since_ms))
        trace.fact("mode_after", _mode_now(c))
    held = rec.since(pushed_s)
    trace.fact("farthest_north_m", round(max(p[1] for p in held), 1), COMPANION_STOP)
    trace.fact("end.north_m", round(held[-1][1], 1), COMPANION_STOP)
    trace.fact("end.east_m", round(held[-1][2], 1), DRIFT)
    cruise = [p[4] for p in held if 3.0 < p[1] < 10.0]
    trace.fact("cruise_m_s", round(sorted(cruise)[len(cruise) // 2], 1) if cruise else None,
               Tol(abs=0.3, why="the 3 m/s asked for, as each velocity controller holds it: ArduCopter 2.9-3.0, "
                                "Firefly 3.0-3.1 (two runs each)"))
    trace.fact("slowed_below_1_m_s_at_north_m", _slowed_at(held, lambda p: p[1], 2.0), COMPANION_STOP)


def _companion_push(c: Client, trace: Trace, companion: Companion, wall_m: float, why: str,
                    ready_trace: bool = False) -> None:
    """A companion reporting a wall `wall_m` north of home: the hover's sensors, then the LOITER push."""
    companion.wall_north = wall_m
    sticks, rec = Sticks(c), Recorder(c)
    with _up_beside(c, companion, sticks, rec, trace=trace if ready_trace else None):
        c.idle(1.0)
        trace.fact("hover.proximity_bits", _bits(c))
        _window(c, trace, "hover", Tol(abs=100.0, why=why))
        _push(c, trace, rec, sticks, stop=COMPANION_STOP)


def _proximity_texts(c: Client, since_ms: int, prefix: str) -> list:
    """[severity, text] of the texts since since_ms that start with prefix and name the sensor."""
    return [[sev, text] for stamp, sev, text in c.texts
            if stamp >= since_ms and text.startswith(prefix) and ("PRX" in text or "roximity" in text)]


def _arm(c: Client) -> tuple[int | None, list]:
    """ARM in LOITER: the result, and the "Arm: " texts that name the proximity sensor (the
    failures the ARM reports); disarmed after."""
    c.set_mode(LOITER)
    c.try_wait(lambda: c.mode == LOITER, 3)
    since = c.now_ms
    result = c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    c.idle(1.0)
    texts = _proximity_texts(c, since, "Arm: ")
    if c.armed:
        c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0)
        c.wait(lambda: not c.armed, 10, what="disarmed")
    return result, texts


def prearm(c: Client, trace: Trace) -> None:
    companion = Companion(c)
    with c.listening(companion):
        _streams(c)
        _wait_home(c)
        c.idle(5.0)
        trace.fact("silent.proximity_bits", _bits(c))
        result, texts = _arm(c)
        trace.fact("silent.arm", result)
        trace.fact("silent.arm_texts", texts)
        companion.ahead_m = 5.0
        companion.on = True
        wait_armable(c)  # armable with the obstacle far: what follows is the obstacle's doing alone
        for ahead in (1.0, 0.5, 5.0):
            name = f"at_{ahead:g}m".replace(".", "_")
            since = c.now_ms
            companion.ahead_m = ahead
            c.idle(2.0)  # the 1 Hz pre-arm checks see it (and say so at once when their answer changes)
            trace.fact(f"{name}.proximity_bits", _bits(c))
            result, texts = _arm(c)
            trace.fact(f"{name}.arm", result)
            trace.fact(f"{name}.arm_texts", texts)
            trace.fact(f"{name}.prearm_texts", sorted({tuple(t) for t in _proximity_texts(c, since, "PreArm: ")}))


def althold_push(c: Client, trace: Trace) -> None:
    companion = Companion(c)
    sticks, rec = Sticks(c), Recorder(c)
    with _up_beside(c, companion, sticks, rec):
        sticks.hold(MID, MID, MID, MID)
        c.set_mode(ALT_HOLD)
        c.wait(lambda: c.mode == ALT_HOLD, 5, what="ALT_HOLD")
        c.idle(2.0)
        start_n = rec.points[-1][1]
        companion.wall_north = start_n + PUSH_WALL_M
        wall_s = rec.now_s()
        c.idle(10.5)
        forward_s = rec.now_s()
        sticks.hold(MID, FULL_FORWARD, MID, MID)
        c.idle(5.5)
        sticks.hold(MID, MID, MID, MID)
        c.idle(1.0)
        trace.fact("mode_after", _mode_now(c))
    for s in (0, 2, 5, 10):
        p = _first(rec.points, lambda p: p[0] >= wall_s + s)
        trace.fact(f"centred.north_at_{s}s_m", None if p is None else round(p[1] - start_n, 1), PUSHED)
    centred = [p for p in rec.points if wall_s <= p[0] <= forward_s]
    trace.fact("centred.farthest_back_m", round(min(p[1] for p in centred) - start_n, 1), PUSHED)
    trace.fact("centred.fastest_m_s", round(max(p[4] for p in centred), 1), PUSHED)
    for s in (0, 2, 5):
        p = _first(rec.points, lambda p: p[0] >= forward_s + s)
        trace.fact(f"forward.north_at_{s}s_m", None if p is None else round(p[1] - start_n, 1), PUSHED)
    past = _first([p for p in rec.points if p[0] >= forward_s], lambda p: p[1] >= start_n + PUSH_WALL_M)
    trace.fact("forward.passed_wall_after_s", None if past is None else round(past[0] - forward_s, 1),
               Tol(abs=1.0, why="full forward less the avoidance's lean, from where the push left it"))


PROBES = {"sitl_sectors": sitl_sectors, "sitl_loiter_stop": sitl_loiter_stop, "companion_obstacle": companion_obstacle,
          "companion_distance_sensor": companion_distance_sensor, "companion_obstacle_3d": companion_obstacle_3d,
          "companion_guided": companion_guided, "prearm": prearm, "althold_push": althold_push}


def run(target) -> dict[str, Trace]:
    """Each probe on a fresh vehicle, booted without waiting to be armable: it never is while its
    proximity sensor has no data (no fence for SITL's lidar to measure, no companion yet), so
    each probe makes it ready itself."""
    return each_on_a_fresh_vehicle(target, PROBES, PROBES_PARAMS, streams_hz=None)

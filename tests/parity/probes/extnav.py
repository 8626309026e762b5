"""External navigation: no GPS, a companion's VISION_POSITION_ESTIMATE as the position (issue 31).

Each vehicle boots with GPS1_TYPE 0, VISO_TYPE 1 and EK3_SRC1_POSXY / VELXY / VELZ 6 (height
from the barometer), and each probe starts 25 s after boot. The companion is this client: it answers every SIMSTATE (the simulator's truth, asked
for at 20 Hz) with a pose, the truth as metres north and east of where the vehicle booted, plus an
error the probe chooses; it sends no velocity.

no_origin  before the companion speaks: GPS_RAW_INT, SYS_STATUS's vision and GPS bits, LOITER's
           refusal; once it does: the EKF's texts, its flags, LOCAL_POSITION_NED sent and
           GLOBAL_POSITION_INT all zeros, LOITER's refusal without home, STABILIZE arming
origin     then SET_GPS_GLOBAL_ORIGIN: what comes back (GPS_GLOBAL_ORIGIN, the texts, home), a
           second origin and MAV_CMD_DO_SET_GLOBAL_ORIGIN after it, LOITER arming, and LOITER
           refused once EK3_SRC1_VELZ is set back to the GPS
loiter     the GPS-denied flight: LOITER entered from a GUIDED hover at 10 m (sticks centred by RC override),
           held 20 s (how far the vehicle wanders, where it believes it is), then the roll stick
           full right for 4 s and centred: where it was at the release, its top speed, where it stopped
hold       GUIDED at 10 m with the pose 0.8 m north of the truth: where the vehicle believes it
           is and where it is; then a 5.8 m jump: held off for seconds, then taken (the vehicle
           flies to where the pose says its point is)
jump_with_speed  the same jump from a companion that sends VISION_SPEED_ESTIMATE too: held off
           longer, then the EKF failsafe
silent     GUIDED at 10 m, the companion stops: the vision bit, the EKF failsafe, its texts
other_messages  ODOMETRY in local NED (not taken), in local FRD, then ATT_POS_MOCAP
gps_input  GPS1_TYPE 14 alone: GPS_RAW_INT before, while and after a companion's GPS_INPUT
source_switch  the GPS as source set 1 and the pose (3 m north of the truth) as set 2:
           MAV_CMD_SET_EKF_SOURCE_SET's answers, then in a GUIDED hover set 2 (the estimate
           resets to the pose and the vehicle moves 3 m south), set 1 back, set 3 (no position
           source at all, as its defaults leave it), then the RC function 90 (EKF source set)
           middle and low, as MAV_CMD_DO_AUX_FUNCTION
external_position_estimate  MAV_CMD_EXTERNAL_POSITION_ESTIMATE on a GPS vehicle: COMMAND_LONG,
           a frame with an altitude, an altitude, the GPS in use, on the ground and hovering in
           GUIDED; right behind SIM_GPS1_ENABLE 0; 2 s after it, 20 m north of the truth (the
           estimate jumps, the vehicle stays; the GPS back a second later); then three times 2 s after
           the loss a position north of the truth with the GPS back right behind it: 20 m off and
           1 m accurate (a glitch held off, then the estimate resets to the GPS), 20 m off and 30 m
           accurate (reset at once), 8 m off (fused: the vehicle flies it); lost for good: 10 s
           after (in the EKF failsafe's LAND) 10 m west, 18 s after (the EKF stopped aiding at 15 s),
           and once the GPS is back
external_position_estimate_no_gps  the same command with GPS1_TYPE 0, before and after an origin
external_position_estimate_extnav  on external navigation, with an origin: while the companion
           speaks, 1.5 s after it fell silent (20 m north), then when it speaks again
"""
from __future__ import annotations

import math

from pymavlink.dialects.v20 import ardupilotmega as v20

from ..client import Client, mav
from ..facts import Tol, Trace
from ..targets import wait_armable
from .booting import each_on_a_fresh_vehicle
from .pilot import MID, Sticks

AREA = "extnav"
EXTNAV = {"GPS1_TYPE": 0, "VISO_TYPE": 1, "EK3_SRC1_POSXY": 6, "EK3_SRC1_VELXY": 6, "EK3_SRC1_VELZ": 6}
LOITER, GUIDED, LAND, STABILIZE = 5, 4, 9, 0
M_PER_DEG = 1.0e7 * 0.011131884502145034  # ArduPilot's LOCATION_SCALING_FACTOR, per degree
VISION = mav.MAV_SYS_STATUS_SENSOR_VISION_POSITION
GPS = mav.MAV_SYS_STATUS_SENSOR_GPS
ORIGIN = (-353632610, 1491652300, 584_000)  # the runners' home (targets.HOME), as an origin in e7 / mm
DO_SET_GLOBAL_ORIGIN = 611
# ArduCopter SITL's IMUs agree only this long after boot ("Arm: Accels inconsistent", "Gyros
# inconsistent" before: startup.py); every probe starts after it on both vehicles
SETTLED_MS = 25_000
FAILSAFE_TEXTS = ("EKF variance", "EKF Failsafe: changed to LAND Mode")
TIMING = Tol(abs=1.0, why="a 20 Hz companion answering over the link at speedup 10-20, and 10 Hz streams")
HOLD = Tol(abs=0.3, why="both position controllers settling; the companion's pose lags its SIMSTATE by the link")
LOITER_HOLD_S, LOITER_STICK_S = 20.0, 4.0
RIGHT = 2000  # the roll stick full right
WANDER = Tol(abs=0.3, why="two position controllers holding a pose that lags the truth by the link")
LOITER_PLACE = Tol(abs=2.0, why="two LOITER shapers from rest to the stick's speed and back: Firefly's is "
                                 "AC_Loiter's drag and brake without its jerk shaping, about 1 m ahead at the "
                                 "release and 1-2 m short of ArduCopter's stop after 33 m")
LOITER_SPEED = Tol(abs=1.0, rel=0.15, why="LOITER's speed after the stick's seconds, as two loiter shapers reach it")


def companion_link(c: Client):
    """MAVLink 2 frames (ODOMETRY is a MAVLink 2 message) from a companion's visual odometry."""
    return v20.MAVLink(c.conn, srcSystem=1, srcComponent=mav.MAV_COMP_ID_VISUAL_INERTIAL_ODOMETRY)


class Companion:
    """Answers each SIMSTATE with a pose (a listener of the client: it speaks inside every wait)."""

    def __init__(self, c: Client):
        self.c = c
        self.link = companion_link(c)
        self.first = None
        self.error_ne = (0.0, 0.0)
        self.speaking = False
        self.with_speed = False  # also VISION_SPEED_ESTIMATE (the vehicle's own velocity, as it reports it)
        self.message = "VISION_POSITION_ESTIMATE"  # or ODOMETRY (frame_id below), ATT_POS_MOCAP
        self.odometry_frame = v20.MAV_FRAME_LOCAL_FRD
        self.last_truth = (0.0, 0.0)
        self.track: list | None = None  # (vehicle s, true north, true east) at each SIMSTATE, once a list

    def __call__(self, msg) -> None:
        if msg.get_type() != "SIMSTATE":
            return
        if self.first is None:
            self.first = msg
        self.last_truth = self.truth_ne(msg)
        if self.track is not None:
            self.track.append((self.c.now_ms / 1000.0, *self.last_truth))
        if self.speaking:
            n, e = self.last_truth
            n, e, usec = n + self.error_ne[0], e + self.error_ne[1], self.c.now_ms * 1000
            if self.message == "ODOMETRY":
                self.link.odometry_send(usec, self.odometry_frame, v20.MAV_FRAME_BODY_FRD, n, e, 0.0, [1, 0, 0, 0],
                                        0.0, 0.0, 0.0, 0.0, 0.0, 0.0, [math.nan] * 21, [math.nan] * 21, 0, 0, 100)
                return
            if self.message == "ATT_POS_MOCAP":
                self.link.att_pos_mocap_send(usec, [1, 0, 0, 0], n, e, 0.0)
                return
            self.link.vision_position_estimate_send(usec, n, e, 0.0, 0.0, 0.0, 0.0)
            lpn = self.c.last.get("LOCAL_POSITION_NED")
            if self.with_speed and lpn is not None:
                self.link.vision_speed_estimate_send(self.c.now_ms * 1000, lpn.vx, lpn.vy, lpn.vz)

    def truth_ne(self, s) -> tuple[float, float]:
        f = self.first
        return ((s.lat - f.lat) / 1e7 * M_PER_DEG,
                (s.lng - f.lng) / 1e7 * M_PER_DEG * math.cos(math.radians(f.lat / 1e7)))


def _bits(c: Client, bit: int) -> str:
    c.fresh("SYS_STATUS")
    s = c.last["SYS_STATUS"]
    return "".join(str(int(bool(mask & bit))) for mask in (s.onboard_control_sensors_present,
                                                           s.onboard_control_sensors_enabled,
                                                           s.onboard_control_sensors_health))


def _ekf_texts(texts: list[str]) -> list[str]:
    """The EKF's lines about external navigation, sorted (its two cores say them in either order;
    its start-up lines are ArduCopter's start-up's, which Firefly's default boot skips)."""
    return sorted(t for t in texts if t.startswith("EKF3") and ("external nav" in t or " initial pos " in t
                                                                  or " initial vel " in t))


def _start(c: Client) -> Companion:
    """Streams asked for, SIMSTATE at 20 Hz, the companion listening (silent until told)."""
    c.request_streams(10)
    c.wait(lambda: "ATTITUDE" in c.last, 60, what="requested streams")
    c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_SIMSTATE, 50_000)
    companion = Companion(c)
    c.listeners.append(companion)
    c.wait(lambda: companion.first is not None, 10, what="SIMSTATE")
    c.wait(lambda: c.now_ms >= SETTLED_MS, 60, what="the IMUs settled")
    return companion


def _arm(c: Client, trace: Trace | None = None, name: str = "") -> int | None:
    """ARM, its result and (with a trace) its texts; then two vehicle seconds, so that the next
    ARM is never a retry of this one."""
    t0 = c.now_ms
    result = c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    c.idle(2.0)
    if trace is not None:
        trace.fact(f"{name}_result", result)
        trace.fact(f"{name}_said", sorted(t for t in c.texts_since(t0) if t.startswith("Arm:")))
    return result


def _navigating(c: Client, companion: Companion) -> float:
    """The companion speaks; the vehicle seconds until the EKF says it uses the pose."""
    companion.speaking = True
    return c.wait(lambda: any("is using external nav data" in t for _, _, t in c.texts), 30,
                  what="the EKF using the pose")


def probe_no_origin(c: Client, trace: Trace) -> None:
    companion = _start(c)
    c.fresh("GPS_RAW_INT")
    gps = c.last["GPS_RAW_INT"]
    trace.fact("gps_fix_type", gps.fix_type)
    trace.fact("gps_satellites", gps.satellites_visible)
    trace.fact("gps_bits", _bits(c, GPS))
    trace.fact("vision_bits_silent", _bits(c, VISION))
    trace.fact("local_position_silent", "LOCAL_POSITION_NED" in c.last)
    c.set_mode(LOITER)
    _arm(c, trace, "loiter_silent")
    t0 = c.now_ms
    _navigating(c, companion)
    c.idle(3.0)
    trace.fact("ekf_said", _ekf_texts(c.texts_since(t0)))
    trace.fact("vision_bits", _bits(c, VISION))
    c.fresh("EKF_STATUS_REPORT")
    trace.fact("ekf_flags", c.last["EKF_STATUS_REPORT"].flags)
    c.fresh("LOCAL_POSITION_NED")
    c.fresh("GLOBAL_POSITION_INT")
    g = c.last["GLOBAL_POSITION_INT"]
    trace.fact("global_position", [g.lat, g.lon, g.alt, g.relative_alt])
    trace.fact("home_sent", "HOME_POSITION" in c.last)
    _arm(c, trace, "loiter")
    c.set_mode(STABILIZE)
    trace.fact("stabilize_arm", _arm(c))
    c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0)


def probe_origin(c: Client, trace: Trace) -> None:
    companion = _start(c)
    _navigating(c, companion)
    c.idle(3.0)
    t0 = c.now_ms
    c.conn.mav.set_gps_global_origin_send(1, *ORIGIN)
    c.wait(lambda: "GPS_GLOBAL_ORIGIN" in c.last and "HOME_POSITION" in c.last, 5, what="the origin and home")
    c.idle(1.0)
    trace.fact("said", c.texts_since(t0))
    o = c.last["GPS_GLOBAL_ORIGIN"]
    trace.fact("origin", [o.latitude, o.longitude, o.altitude])
    h = c.last["HOME_POSITION"]
    trace.fact("home_from_origin_m", [round((h.latitude - o.latitude) / 1e7 * M_PER_DEG, 1),
                                      round((h.longitude - o.longitude) / 1e7 * M_PER_DEG, 1)], Tol(abs=0.2))
    trace.fact("home_alt_above_origin_m", (h.altitude - o.altitude) / 1000.0, Tol(abs=0.2, why="the barometer's"))
    c.fresh("GLOBAL_POSITION_INT")
    trace.fact("located", c.last["GLOBAL_POSITION_INT"].lat != 0)
    t1 = c.now_ms
    c.conn.mav.set_gps_global_origin_send(1, ORIGIN[0] + 9000, ORIGIN[1], ORIGIN[2] + 10_000)  # 100 m north
    c.idle(2.0)
    trace.fact("second_said", c.texts_since(t1))
    trace.fact("command_after", c.command_int(DO_SET_GLOBAL_ORIGIN, mav.MAV_FRAME_GLOBAL_INT, x=ORIGIN[0] + 9000,
                                              y=ORIGIN[1], z=594.0))
    seen = c.received.get("GPS_GLOBAL_ORIGIN", 0)
    c.command(mav.MAV_CMD_GET_HOME_POSITION)
    c.wait(lambda: c.received.get("GPS_GLOBAL_ORIGIN", 0) > seen, 3, what="GPS_GLOBAL_ORIGIN asked for")
    o = c.last["GPS_GLOBAL_ORIGIN"]
    trace.fact("origin_after", [o.latitude, o.longitude, o.altitude])
    c.set_mode(LOITER)
    trace.fact("loiter_arm", _arm(c))
    c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0)
    c.idle(1.0)
    c.set_param("EK3_SRC1_VELZ", 3)  # the vertical velocity left on the GPS there is not
    _arm(c, trace, "velz_on_gps")
    c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0)


def _hover(c: Client, companion: Companion) -> None:
    """Navigating with an origin, GUIDED at 10 m, settled."""
    _navigating(c, companion)
    c.idle(3.0)
    c.conn.mav.set_gps_global_origin_send(1, *ORIGIN)
    c.wait(lambda: "HOME_POSITION" in c.last, 5, what="home")
    c.idle(3.0)
    c.set_mode(GUIDED)
    _arm(c)
    c.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 10)
    c.wait(lambda: c.rel_alt_m() > 9.5, 30, what="10 m")
    c.idle(5.0)


def probe_hold(c: Client, trace: Trace) -> None:
    companion = _start(c)
    _hover(c, companion)
    companion.error_ne = (0.8, 0.0)
    c.idle(10.0)
    c.fresh("LOCAL_POSITION_NED")
    lpn = c.last["LOCAL_POSITION_NED"]
    trace.fact("believed_ne", [lpn.x, lpn.y], Tol(abs=0.3, why=HOLD.why))
    trace.fact("true_ne", list(companion.last_truth), Tol(abs=0.3, why=HOLD.why))
    t0 = c.now_ms
    companion.error_ne = (5.8, 0.0)
    took = c.wait(lambda: c.last["LOCAL_POSITION_NED"].x > 2.5, 20, what="the jump taken")
    trace.fact("held_off_s", took, Tol(abs=0.6, why=TIMING.why))
    c.wait(lambda: c.now_ms >= t0 + 15_000, 20, what="15 s after the jump")
    trace.fact("true_n_15s", companion.last_truth[0], Tol(abs=0.5, why=HOLD.why))
    c.fresh_heartbeat()
    trace.fact("mode_15s", c.mode)
    trace.fact("said", [t for t in c.texts_since(t0) if t in FAILSAFE_TEXTS])


def probe_loiter(c: Client, trace: Trace) -> None:
    """LOITER with no GPS, on the pose alone (issue 31's GPS-denied flight): entered from the
    GUIDED hover with the sticks centred by RC override; held 20 s; the roll stick full right for
    LOITER_STICK_S, then centred again for 5 s."""
    companion = _start(c)
    _hover(c, companion)
    sticks = Sticks(c)
    with c.listening(sticks):
        sticks.hold(MID, MID, MID, MID)
        trace.fact("result", c.set_mode(LOITER))
        c.wait(lambda: c.mode == LOITER, 5, what="LOITER")
        entered = companion.last_truth
        companion.track = []
        c.idle(LOITER_HOLD_S)
        trace.fact("hold.wander_m", round(max(math.dist(entered, p[1:]) for p in companion.track), 2), WANDER)
        trace.fact("hold.believed_less_true", [round(x, 1) for x in _believed_less_true(c, companion)], HOLD)
        start_s, companion.track = c.now_ms / 1000.0, []
        sticks.hold(RIGHT, MID, MID, MID)
        c.idle(LOITER_STICK_S)
        released_s = c.now_ms / 1000.0
        sticks.hold(MID, MID, MID, MID)
        c.idle(5.0)
        track = companion.track
        speeds = [math.dist(a[1:], b[1:]) / (b[0] - a[0])  # over half a second: SIMSTATE's 1e-7 degrees
                  for a, b in zip(track, track[10:]) if b[0] > a[0]]
        held = [p for p in track if p[0] <= released_s]
        trace.fact("stick.east_at_release_m", round(held[-1][2] - entered[1], 1), LOITER_PLACE)
        trace.fact("stick.north_at_release_m", round(held[-1][1] - entered[0], 1), LOITER_PLACE)
        trace.fact("stick.fastest_m_s", round(max(speeds), 1), LOITER_SPEED)
        trace.fact("stick.stopped_east_m", round(track[-1][2] - entered[1], 1), LOITER_PLACE)
        trace.fact("stick.took_s", round(released_s - start_s, 1))
        c.fresh_heartbeat()
        trace.fact("mode_after", c.mode)
        trace.fact("said", [t for t in c.texts_since(int(start_s * 1000)) if t.startswith("EKF")])


def probe_jump_with_speed(c: Client, trace: Trace) -> None:
    companion = _start(c)
    companion.with_speed = True
    _hover(c, companion)
    t0 = c.now_ms
    companion.error_ne = (5.0, 0.0)
    c.idle(5.0)
    c.fresh("LOCAL_POSITION_NED")
    trace.fact("believed_n_5s", c.last["LOCAL_POSITION_NED"].x, Tol(abs=0.4, why=HOLD.why))
    landed = c.try_wait(lambda: c.mode == LAND, 20)
    trace.fact("failsafe_after_s", (c.now_ms - t0) / 1000.0 if landed else None, Tol(abs=1.5, why=TIMING.why))
    c.idle(2.0)
    trace.fact("said", [t for t in c.texts_since(t0) if t in FAILSAFE_TEXTS])


def probe_silent(c: Client, trace: Trace) -> None:
    companion = _start(c)
    _hover(c, companion)
    t0 = c.now_ms
    companion.speaking = False
    unhealthy = c.wait(lambda: _bits(c, VISION)[2] == "0", 5, what="the vision bit's health off")
    trace.fact("unhealthy_after_s", unhealthy, Tol(abs=0.5, why=TIMING.why))
    took = c.wait(lambda: c.mode == LAND, 20, what="the EKF failsafe") + unhealthy
    trace.fact("failsafe_after_s", took, Tol(abs=1.0, why=TIMING.why))
    c.idle(2.0)
    trace.fact("said", [t for t in c.texts_since(t0) if t in FAILSAFE_TEXTS])


def probe_other_messages(c: Client, trace: Trace) -> None:
    """ODOMETRY in a frame ArduCopter does not take, then in local FRD (a pose and a velocity),
    then ATT_POS_MOCAP: the vision bit and the EKF's texts for each."""
    companion = _start(c)
    companion.message, companion.odometry_frame = "ODOMETRY", v20.MAV_FRAME_LOCAL_NED
    companion.speaking = True
    c.idle(3.0)
    trace.fact("odometry_ned_vision_bits", _bits(c, VISION))
    trace.fact("odometry_ned_said", _ekf_texts([t for _, _, t in c.texts]))
    companion.odometry_frame = v20.MAV_FRAME_LOCAL_FRD
    t0 = c.now_ms
    c.idle(3.0)
    trace.fact("odometry_vision_bits", _bits(c, VISION))
    trace.fact("odometry_said", _ekf_texts(c.texts_since(t0)))
    c.fresh("EKF_STATUS_REPORT")
    trace.fact("odometry_ekf_flags", c.last["EKF_STATUS_REPORT"].flags)
    companion.message = "ATT_POS_MOCAP"
    c.idle(3.0)
    trace.fact("mocap_vision_bits", _bits(c, VISION))
    c.fresh("EKF_STATUS_REPORT")
    trace.fact("mocap_ekf_flags", c.last["EKF_STATUS_REPORT"].flags)


def probe_gps_input(c: Client, trace: Trace) -> None:
    """GPS1_TYPE 14: the receiver before, while and after a companion sends GPS_INPUT (the
    boot place, 12 satellites, at the SIMSTATE rate)."""
    _start(c)
    c.fresh("GPS_RAW_INT")
    g = c.last["GPS_RAW_INT"]
    trace.fact("before", [g.fix_type, g.satellites_visible])
    trace.fact("before_gps_bits", _bits(c, GPS))

    def gps_input(msg) -> None:
        if msg.get_type() == "SIMSTATE" and sending[0]:
            link.gps_input_send(c.now_ms * 1000, 0, 0, 0, 0, 3, msg.lat, msg.lng, 584.0, 0.8, 1.0, 0.0, 0.0,
                                      0.0, 0.2, 0.3, 0.5, 12)
    sending = [True]
    link = companion_link(c)
    t0 = c.now_ms
    c.listeners.append(gps_input)
    c.idle(3.0)
    c.fresh("GPS_RAW_INT")
    g = c.last["GPS_RAW_INT"]
    trace.fact("sending", [g.fix_type, g.satellites_visible])
    trace.fact("sending_near_m", round(math.hypot((g.lat - ORIGIN[0]) / 1e7 * M_PER_DEG,
                                                   (g.lon - ORIGIN[1]) / 1e7 * M_PER_DEG * 0.815), 0) <= 1)
    trace.fact("said", [t for t in c.texts_since(t0) if t.startswith("GPS")])
    c.fresh("GLOBAL_POSITION_INT")
    trace.fact("located", c.last["GLOBAL_POSITION_INT"].lat != 0)
    sending[0] = False
    took = c.wait(lambda: c.last["GPS_RAW_INT"].fix_type < 3, 15, what="the fix lost")
    trace.fact("no_fix_after_s", took, Tol(abs=1.0, why=TIMING.why))
    g = c.last["GPS_RAW_INT"]
    trace.fact("stopped", [g.fix_type, g.satellites_visible])


def _ne(c: Client) -> list:
    c.fresh("LOCAL_POSITION_NED")
    lpn = c.last["LOCAL_POSITION_NED"]
    return [round(lpn.x, 2), round(lpn.y, 2)]


def probe_source_switch(c: Client, trace: Trace) -> None:
    companion = _start(c)
    companion.error_ne = (3.0, 0.0)
    companion.speaking = True
    wait_armable(c)
    for wanted in (0, 4):
        trace.fact(f"set_{wanted}", c.command(mav.MAV_CMD_SET_EKF_SOURCE_SET, wanted))
    c.set_mode(GUIDED)
    trace.fact("arm", _arm(c))
    c.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 10)
    c.wait(lambda: c.rel_alt_m() > 9.5, 30, what="10 m")
    c.idle(5.0)
    trace.fact("gps.believed_ne", _ne(c), HOLD)
    trace.fact("gps.true_ne", [round(x, 2) for x in companion.last_truth], HOLD)
    c.fresh("EKF_STATUS_REPORT")
    trace.fact("gps.ekf_flags", c.last["EKF_STATUS_REPORT"].flags)
    steps = (("set_2", mav.MAV_CMD_SET_EKF_SOURCE_SET, 2), ("set_1", mav.MAV_CMD_SET_EKF_SOURCE_SET, 1),
             ("set_3", mav.MAV_CMD_SET_EKF_SOURCE_SET, 3), ("aux_middle", mav.MAV_CMD_DO_AUX_FUNCTION, 90, 1),
             ("aux_low", mav.MAV_CMD_DO_AUX_FUNCTION, 90, 0))
    near = Tol(abs=0.5, why=HOLD.why)
    for name, *command in steps:
        t0 = c.now_ms
        trace.fact(name, c.command(*command))
        c.idle(1.0)
        trace.fact(f"{name}.believed_ne_1s", _ne(c), near)
        c.idle(9.0)
        trace.fact(f"{name}.believed_ne", _ne(c), near)
        trace.fact(f"{name}.true_ne", [round(x, 2) for x in companion.last_truth], near)
        c.fresh("EKF_STATUS_REPORT")
        trace.fact(f"{name}.ekf_flags", c.last["EKF_STATUS_REPORT"].flags)
        c.fresh_heartbeat()
        trace.fact(f"{name}.mode", c.mode)
        # (the EKF failsafe's LAND touches down near the end: when it disarms is not this probe's)
        trace.fact(f"{name}.said", [t for t in c.texts_since(t0)
                                    if not t.startswith(("PreArm", "SIM Hit ground", "Disarming motors"))])


EXTERNAL_POSITION_ESTIMATE = 43003
GPS_GLITCHING = 32768  # EKF_STATUS_REPORT's EKF_GPS_GLITCH flag
LANES = ("EKF3 lane switch", "EKF primary changed")  # ArduCopter's EKF lanes, which Firefly does not model


def _told_send(c: Client, companion: Companion, n: float, e: float, frame: int = mav.MAV_FRAME_GLOBAL_INT,
               z: float = math.nan, long: bool = False, accuracy_m: float = 1.0) -> None:
    """MAV_CMD_EXTERNAL_POSITION_ESTIMATE sent, not waited for: n, e metres from where the vehicle
    booted, param 1 the sender's clock (the vehicle's here: no two sends alike)."""
    f = companion.first
    lat = f.lat + round(n / M_PER_DEG * 1e7)
    lon = f.lng + round(e / (M_PER_DEG * math.cos(math.radians(f.lat / 1e7))) * 1e7)
    c.acks.clear()
    if long:
        c.conn.mav.command_long_send(1, 1, EXTERNAL_POSITION_ESTIMATE, 0, c.now_ms / 1000.0, 0.0, accuracy_m, 0.0,
                                     lat / 1e7, lon / 1e7, z)
    else:
        c.conn.mav.command_int_send(1, 1, frame, EXTERNAL_POSITION_ESTIMATE, 0, 0, c.now_ms / 1000.0, 0.0,
                                    accuracy_m, 0.0, lat, lon, z)


def _told(c: Client, companion: Companion, n: float, e: float, **how) -> int | None:
    """MAV_CMD_EXTERNAL_POSITION_ESTIMATE (_told_send) and its answer."""
    _told_send(c, companion, n, e, **how)
    return c._ack_result(EXTERNAL_POSITION_ESTIMATE, 5.0)


def _told_off_truth(c: Client, companion: Companion, dn: float, de: float, accuracy_m: float = 1.0) -> int | None:
    n, e = companion.last_truth
    return _told(c, companion, n + dn, e + de, accuracy_m=accuracy_m)


def _believed_less_true(c: Client, companion: Companion) -> list:
    """Where LOCAL_POSITION_NED says the vehicle is, less where it is (north, east)."""
    believed = _ne(c)
    return [round(believed[0] - companion.last_truth[0], 1), round(believed[1] - companion.last_truth[1], 1)]


def _until(c: Client, t_ms: float) -> None:
    c.wait(lambda: c.now_ms >= t_ms, (t_ms - c.now_ms) / 1000.0 + 5, what="vehicle time")


def _gps_send(c: Client, on: bool) -> None:
    c.conn.mav.param_set_send(1, 1, b"SIM_GPS1_ENABLE", 1.0 if on else 0.0, mav.MAV_PARAM_TYPE_REAL32)


def _gps_lost(c: Client) -> int:
    """The GPS switched off; the vehicle time of its first report without a fix. A command sent
    later reaches the vehicle later still, by what the link lags (seconds of a vehicle run at 20x
    on a loaded machine): each step below leaves that much room."""
    _gps_send(c, False)
    c.wait(lambda: c.last["GPS_RAW_INT"].fix_type < 3, 5, what="the fix lost", exact=True)
    return c.now_ms


NEAR = Tol(abs=0.5, why=HOLD.why)
DRIFT = Tol(abs=1.0, why="ArduCopter's dead reckoning drifts the vehicle (0.4 m in 4 s); Firefly's holds the truth")


def _told_then_gps_back(c: Client, companion: Companion, trace: Trace, name: str, north_m: float,
                        accuracy_m: float) -> None:
    """In a hover: the GPS lost; 2 s later told north_m north of the truth, the GPS back right
    behind it: where the vehicle believes it is, and where it went."""
    lost = _gps_lost(c)
    _until(c, lost + 2000)
    told_at = companion.last_truth
    t0 = c.now_ms
    _told_send(c, companion, told_at[0] + north_m, told_at[1], accuracy_m=accuracy_m)
    _gps_send(c, True)
    trace.fact(name, c._ack_result(EXTERNAL_POSITION_ESTIMATE, 5.0))
    _until(c, lost + 6000)  # a glitch is held off until 10 s after the loss
    trace.fact(f"{name}.6s.believed_less_true_ne", _believed_less_true(c, companion), NEAR)
    c.fresh("EKF_STATUS_REPORT")
    trace.fact(f"{name}.6s.gps_glitching", bool(c.last["EKF_STATUS_REPORT"].flags & GPS_GLITCHING))
    _until(c, lost + 13_000)
    trace.fact(f"{name}.13s.believed_less_true_ne", _believed_less_true(c, companion), NEAR)
    trace.fact(f"{name}.13s.true_moved_m", round(math.dist(told_at, companion.last_truth), 1), DRIFT)
    c.fresh_heartbeat()
    trace.fact(f"{name}.13s.mode", c.mode)
    trace.fact(f"{name}.said", [t for t in c.texts_since(t0) if not t.startswith(LANES)])
    c.idle(10.0)  # ArduCopter's glitch clears 10 s after the reset


def probe_external_position_estimate(c: Client, trace: Trace) -> None:
    companion = _start(c)
    wait_armable(c)
    trace.fact("long", _told(c, companion, 20, 0, long=True))
    trace.fact("frame_relative_alt", _told(c, companion, 20, 0, frame=mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT))
    trace.fact("altitude_given", _told(c, companion, 20, 0, z=584.0))
    trace.fact("gps_in_use", _told(c, companion, 20, 0))
    c.set_mode(GUIDED)
    trace.fact("arm", _arm(c))
    c.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 10)
    c.wait(lambda: c.rel_alt_m() > 9.5, 30, what="10 m")
    c.idle(5.0)
    trace.fact("hover_gps_in_use", _told(c, companion, 20, 0))
    _gps_send(c, False)
    trace.fact("lost_0s", _told(c, companion, 20, 0))  # right behind the loss
    c.set_param("SIM_GPS1_ENABLE", 1)
    c.idle(5.0)
    t0 = c.now_ms
    lost = _gps_lost(c)
    _until(c, lost + 2000)
    trace.fact("lost_2s", _told_off_truth(c, companion, 20, 0))
    c.idle(1.0)
    trace.fact("lost_2s.believed_less_true_ne", _believed_less_true(c, companion), NEAR)
    trace.fact("lost_2s.said", [t for t in c.texts_since(t0) if not t.startswith(LANES)])
    c.set_param("SIM_GPS1_ENABLE", 1)
    c.idle(20.0)  # a glitch until 10 s after the loss, then a reset; ArduCopter's glitch clears 10 s after it
    _told_then_gps_back(c, companion, trace, "told_20m", 20, 1.0)  # a glitch, then a reset
    _told_then_gps_back(c, companion, trace, "told_20m_30m_accurate", 20, 30.0)  # reset at once
    _told_then_gps_back(c, companion, trace, "told_8m", 8, 1.0)  # fused: the vehicle flies it
    lost = _gps_lost(c)
    c.wait(lambda: c.mode == LAND, 15, what="the EKF failsafe")
    _until(c, lost + 10_000)
    trace.fact("lost_10s", _told_off_truth(c, companion, 0, -10))
    c.idle(1.0)
    trace.fact("lost_10s.believed_less_true_ne", _believed_less_true(c, companion), NEAR)
    _until(c, lost + 18_000)
    trace.fact("lost_18s", _told_off_truth(c, companion, 0, 0))  # the EKF stopped aiding at 15 s
    c.set_param("SIM_GPS1_ENABLE", 1)
    c.idle(1.5)
    trace.fact("gps_again.believed_less_true_ne", _believed_less_true(c, companion), NEAR)
    trace.fact("gps_again", _told_off_truth(c, companion, 20, 0))


def probe_external_position_estimate_no_gps(c: Client, trace: Trace) -> None:
    companion = _start(c)
    t0 = c.now_ms
    trace.fact("no_origin", _told(c, companion, 20, 0))
    c.idle(1.0)
    trace.fact("no_origin.said", [t for t in c.texts_since(t0) if not t.startswith("PreArm")])
    c.conn.mav.set_gps_global_origin_send(1, *ORIGIN)
    c.wait(lambda: any(t.endswith("origin set") for t in c.texts_since(t0)), 5, what="the origin")
    c.idle(2.0)
    trace.fact("origin_sent", "GPS_GLOBAL_ORIGIN" in c.last)
    trace.fact("home_sent", "HOME_POSITION" in c.last)
    t1 = c.now_ms
    trace.fact("origin", _told(c, companion, 20, 0))
    c.idle(1.0)
    trace.fact("origin.said", [t for t in c.texts_since(t1) if not t.startswith("PreArm")])


def probe_external_position_estimate_extnav(c: Client, trace: Trace) -> None:
    companion = _start(c)
    _navigating(c, companion)
    c.idle(3.0)
    c.conn.mav.set_gps_global_origin_send(1, *ORIGIN)
    c.wait(lambda: "HOME_POSITION" in c.last, 5, what="home")
    c.idle(2.0)
    trace.fact("speaking", _told_off_truth(c, companion, 20, 0))
    companion.speaking = False
    c.idle(1.5)
    t0 = c.now_ms
    trace.fact("silent_1.5s", _told_off_truth(c, companion, 20, 0))
    c.idle(0.5)
    trace.fact("silent.believed_less_true_ne", _believed_less_true(c, companion), NEAR)
    companion.speaking = True
    c.idle(2.0)
    trace.fact("speaking_again_2s.believed_less_true_ne", _believed_less_true(c, companion), NEAR)
    c.idle(8.0)
    trace.fact("speaking_again_10s.believed_less_true_ne", _believed_less_true(c, companion), NEAR)
    trace.fact("said", [t for t in c.texts_since(t0) if not t.startswith("PreArm")])


PROBES = {"no_origin": probe_no_origin, "origin": probe_origin, "hold": probe_hold, "loiter": probe_loiter,
          "jump_with_speed": probe_jump_with_speed, "silent": probe_silent, "other_messages": probe_other_messages,
          "gps_input": probe_gps_input, "source_switch": probe_source_switch,
          "external_position_estimate": probe_external_position_estimate,
          "external_position_estimate_no_gps": probe_external_position_estimate_no_gps,
          "external_position_estimate_extnav": probe_external_position_estimate_extnav}
# the GPS as set 1 (EK3_SRC1_* defaults), the pose as set 2, set 3 left at its defaults (none)
SOURCE_SETS = {"VISO_TYPE": 1, "EK3_SRC2_POSXY": 6, "EK3_SRC2_VELXY": 6, "EK3_SRC2_VELZ": 6, "EK3_SRC2_POSZ": 1,
               "EK3_SRC2_YAW": 1}
PARAMS = {name: EXTNAV for name in PROBES} | {"gps_input": {"GPS1_TYPE": 14}, "source_switch": SOURCE_SETS,
                                              "external_position_estimate": None,
                                              "external_position_estimate_no_gps": {"GPS1_TYPE": 0}}


def run(target) -> dict[str, Trace]:
    """Each probe on a fresh vehicle booted with external navigation, without waiting to be
    armable: it is not, without a pose and an origin."""
    return each_on_a_fresh_vehicle(target, PROBES, PARAMS, streams_hz=None)

"""GUIDED's interface as user programs drive it, measured: what a client would notice of each.

* offboard_landed: MAVSDK Offboard velocity setpoints (its type mask) streamed to a vehicle armed
  on the ground in GUIDED: ArduCopter stays on the ground and disarms after DISARM_DELAY.
* offboard_flying: MAVSDK Offboard's position NED, velocity NED, velocity body with a yaw rate,
  and an attitude (SET_ATTITUDE_TARGET, thrust 0.5 = hold the height) from a hover.
* velocity_step_stop: 5 m/s north streamed for 6 s, then nothing: GUID_TIMEOUT stops it.
* dronekit: a DroneKit-style script: simple_goto (MISSION_ITEM, current = 2), DO_CHANGE_SPEED,
  a second simple_goto, velocity setpoints at DroneKit's 1 Hz; the distance flown; the guided
  waypoint's answers when refused.
* pause_continue: DO_PAUSE_CONTINUE during a GUIDED goto, and in LOITER.
* auto_pause: DO_PAUSE_CONTINUE on an AUTO waypoint leg, and at the mission's end.
* condition_yaw: CONDITION_YAW at a rate, relative counter-clockwise, and the long way round.
* climb_speed: DO_CHANGE_SPEED's climb and descent speeds on a GUIDED height change.
* nogps: GUIDED_NOGPS from the ground: a climb by SET_ATTITUDE_TARGET's thrust (as a climb
  rate), a hold, an attitude step, the level when the stream stops, and bad attitude targets.
Numbers carry tolerances for two airframes and controllers doing the same thing.
"""
from __future__ import annotations

import math

from ..client import Client, ProbeTimeout, mav
from ..facts import Tol, Trace
from .flight import ne
from .missions import upload
from .states import AUTO, GUIDED, LOITER, on_ground_disarmed, reach_armed_on_ground, reach_flying
from .texts import said

AREA = "guided"
GUIDED_NOGPS = 20
EARTH_M_PER_DEG = 111_195.0
# MAVSDK Offboard's type masks (offboard_impl.cpp): what each of its setpoints leaves out
MAVSDK_VELOCITY_NED = 0x7 | 0x1C0 | 0x800  # position, acceleration, yaw rate ignored
MAVSDK_VELOCITY_BODY = 0x7 | 0x1C0 | 0x400  # position, acceleration, yaw ignored
MAVSDK_POSITION_NED = 0x38 | 0x1C0 | 0x800
DRONEKIT_VELOCITY = 0b0000_1111_1100_0111  # send_ned_velocity's mask: velocity only
ATTITUDE_ONLY = 0x7  # SET_ATTITUDE_TARGET: body rates ignored
LEG_M = 150.0  # a pause's leg: long enough that a late pause still leaves most of it

RATE = Tol(abs=0.3, rel=0.15, why="two airframes and controller tunings: speeds within 15 %")
TIME = Tol(abs=1.5, rel=0.2, why="two airframes and controller tunings: times within 20 %")
DIST = Tol(abs=2.0, rel=0.15, why="distances flown by two airframes and controllers within 15 %")
HOLD = Tol(abs=0.7, why="a hold: within 0.7 m on both")
ANGLE = Tol(abs=2.0, why="an attitude reached within 2 degrees")
HEADING = Tol(abs=8.0, why="a heading or turn within 8 degrees (turn rates and yaw tuning differ)")
LANDED_DISARM = Tol(abs=1.5, why="DISARM_DELAY counted from the land detector's verdict, a moment apart")


# ----- what the client reads -----------------------------------------------------------------
def speed(client: Client) -> float:
    p = client.last["GLOBAL_POSITION_INT"]
    return math.hypot(p.vx, p.vy) / 100.0


def heading_deg(client: Client) -> float:
    return math.degrees(client.last["ATTITUDE"].yaw) % 360.0


def pitch_deg(client: Client) -> float:
    return math.degrees(client.last["ATTITUDE"].pitch)


def angle_between(a: float, b: float) -> float:
    return (b - a + 180.0) % 360.0 - 180.0


class Track:
    """Every position and attitude sample with its vehicle time, as the messages come: timings
    read from it are the vehicle's own, also when a busy client reads its socket late (at 20x a
    client that stalls for 0.2 s of wall time would otherwise read a phase 4 s too long)."""

    def __init__(self, client: Client):
        self.client = client
        self.samples: list[tuple] = []  # (t_ms, n, e, alt, speed, heading, pitch, armed)

    def __call__(self, msg) -> None:
        c = self.client
        if msg.get_type() == "GLOBAL_POSITION_INT" and "ATTITUDE" in c.last:
            n, e = ne(c)
            self.samples.append((c.now_ms, n, e, c.rel_alt_m(), speed(c), heading_deg(c), pitch_deg(c), c.armed))

    def first(self, condition, after_ms: int = 0) -> int:
        """Vehicle time [ms] of the first sample (at or after after_ms) for which condition(sample)."""
        return next(s[0] for s in self.samples if s[0] >= after_ms and condition(s))

    def at(self, t_ms: float) -> tuple:
        """The last sample at or before t_ms."""
        best = self.samples[0]
        for s in self.samples:
            if s[0] > t_ms:
                break
            best = s
        return best


def timed(client: Client, track: Track, condition, sim_s: float, what: str) -> float:
    """Wait until condition(sample) holds; the vehicle seconds from now to the sample that first
    showed it."""
    start = client.now_ms
    client.wait(lambda: bool(track.samples) and condition(track.samples[-1]), sim_s, what=what)
    return (track.first(condition, start) - start) / 1000.0


# ----- what the client sends -----------------------------------------------------------------
def stream(client: Client, send, sim_s: float, hz: float = 10.0, until=None) -> int:
    """Call send() every 1/hz of vehicle time for sim_s (or until until()); the vehicle time of
    the last send [ms]."""
    start = last = client.now_ms
    while client.now_ms - start < sim_s * 1000 and not (until and until()):
        send()
        last = client.now_ms
        due = client.now_ms + 1000.0 / hz
        client.wait(lambda: client.now_ms >= due or bool(until and until()), 5, what="vehicle time")
    return last


def local_target(client: Client, mask: int, frame=mav.MAV_FRAME_LOCAL_NED, pos=(0, 0, 0), vel=(0, 0, 0),
                 yaw=0.0, yaw_rate=0.0) -> None:
    client.conn.mav.set_position_target_local_ned_send(client.now_ms, 1, 1, frame, mask, *pos, *vel, 0, 0, 0,
                                                       yaw, yaw_rate)


def attitude_target(client: Client, pitch_deg_: float = 0.0, thrust: float = 0.5, mask: int = ATTITUDE_ONLY,
                    q=None) -> None:
    if q is None:
        half = math.radians(pitch_deg_) / 2.0
        yaw = client.last["ATTITUDE"].yaw / 2.0
        q = [math.cos(half) * math.cos(yaw), -math.sin(half) * math.sin(yaw),
             math.sin(half) * math.cos(yaw), math.cos(half) * math.sin(yaw)]
    client.conn.mav.set_attitude_target_send(client.now_ms, 1, 1, mask, q, 0, 0, 0, thrust)


def guided_waypoint(client: Client, north_m: float, east_m: float, alt_m: float, current: int = 2,
                    command: int = mav.MAV_CMD_NAV_WAYPOINT, frame: int = mav.MAV_FRAME_GLOBAL_RELATIVE_ALT,
                    as_int: bool = False) -> int | None:
    """DroneKit's simple_goto (MISSION_ITEM), or MAVProxy's guided (as_int); the MISSION_ACK's type."""
    h = client.last["HOME_POSITION"]
    lat = h.latitude * 1e-7 + north_m / EARTH_M_PER_DEG
    lon = h.longitude * 1e-7 + east_m / (EARTH_M_PER_DEG * math.cos(math.radians(h.latitude * 1e-7)))
    seen = client.received.get("MISSION_ACK", 0)
    if as_int:
        client.conn.mav.mission_item_int_send(1, 1, 0, frame, command, current, 1, 0, 0, 0, 0,
                                              int(lat * 1e7), int(lon * 1e7), alt_m)
    else:
        client.conn.mav.mission_item_send(1, 1, 0, frame, command, current, 1, 0, 0, 0, 0, lat, lon, alt_m)
    if not client.try_wait(lambda: client.received.get("MISSION_ACK", 0) > seen, 3):
        return None
    return client.last["MISSION_ACK"].type


def stop_here(client: Client) -> None:
    """Hold where it is, at 10 m, at its heading: a position target at the present point (the
    heading given, so that coming back from an overshoot does not turn it), until still."""
    p = client.last["GLOBAL_POSITION_INT"]
    client.conn.mav.set_position_target_global_int_send(
        0, 1, 1, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, 0x9F8, p.lat, p.lon, 10.0, 0, 0, 0, 0, 0, 0,
        client.last["ATTITUDE"].yaw, 0)
    client.wait(lambda: speed(client) < 0.2 and abs(client.rel_alt_m() - 10.0) < 0.5, 30, what="a hold")


# ----- probes ----------------------------------------------------------------------------------
def hovering(client: Client) -> Trace:
    """A probe's start: hovering still in GUIDED at 10 m."""
    reach_flying(client)
    stop_here(client)
    return Trace()


def peak(track: Track, t0: float, t1: float, value) -> float:
    """The largest value(sample) between two vehicle times [ms]: a figure a client that stalls
    for a moment (its stream then pausing, up to GUID_TIMEOUT) does not change."""
    return max(value(s) for s in track.samples if t0 <= s[0] <= t1)


def peak_rate(track: Track, t0: float, t1: float, index: int, window_ms: float = 1000.0,
              wrap: bool = False) -> float:
    """The fastest change of sample[index] over any window_ms between t0 and t1, per second."""
    samples = [s for s in track.samples if t0 <= s[0] <= t1]
    best = 0.0
    for i, a in enumerate(samples):
        b = next((s for s in samples[i:] if s[0] - a[0] >= window_ms), None)
        if b is None:
            break
        change = angle_between(a[index], b[index]) if wrap else b[index] - a[index]
        best = max(best, abs(change) / ((b[0] - a[0]) / 1000.0))
    return best


def path_m(track: Track, t0: float, t1: float) -> float:
    """Horizontal path length flown between two vehicle times [ms]."""
    pts = [(s[1], s[2]) for s in track.samples if t0 <= s[0] <= t1]
    return sum(math.dist(a, b) for a, b in zip(pts, pts[1:]))


def offboard_landed(client: Client, track: Track) -> Trace:
    t = Trace()
    reach_armed_on_ground(client, GUIDED)
    start, start_ne = client.now_ms, ne(client)
    stream(client, lambda: local_target(client, MAVSDK_VELOCITY_NED, vel=(3.0, 0.0, -1.0)), 14.0, hz=20,
           until=lambda: not client.armed)
    client.fresh("GLOBAL_POSITION_INT")  # a sample that knows of the disarm
    t.fact("left_ground", max(s[3] for s in track.samples if s[0] >= start) > 0.5)
    t.fact("moved_m", math.dist(start_ne, ne(client)), HOLD)
    t.fact("disarmed", not client.armed)
    if not client.armed:
        t.fact("disarmed_after_s", (track.first(lambda s: not s[7], start + 1) - start) / 1000.0, LANDED_DISARM)
    return t


def offboard_flying(client: Client, track: Track) -> Trace:
    t = hovering(client)
    here = client.last["LOCAL_POSITION_NED"]
    n0, e0 = ne(client)
    target = (here.x + 15.0, here.y, -10.0)  # 15 m north, 10 m up from the EKF origin (home's ground)
    start = client.now_ms
    arrived = lambda s: math.hypot(s[1] - n0 - 15.0, s[2] - e0) < 1.0  # noqa: E731
    stream(client, lambda: local_target(client, MAVSDK_POSITION_NED, pos=target), 40,
           until=lambda: arrived(track.samples[-1]))
    t.fact("position_ned_15m_s", (track.first(arrived, start) - start) / 1000.0, TIME)
    stop_here(client)
    start = client.now_ms
    stream(client, lambda: local_target(client, MAVSDK_VELOCITY_NED, vel=(0.0, 2.0, 0.0), yaw=math.pi / 2), 4.0)
    t.fact("velocity_ned_east_speed", peak(track, start, client.now_ms, lambda s: s[4]), RATE)
    t.fact("velocity_ned_heading_deg", round(heading_deg(client)), HEADING)
    stop_here(client)
    start = client.now_ms
    stream(client, lambda: local_target(client, MAVSDK_VELOCITY_BODY, frame=mav.MAV_FRAME_BODY_NED,
                                        vel=(2.0, 0.0, 0.0), yaw_rate=math.radians(30)), 4.0)
    t.fact("velocity_body_turn_deg_s", peak_rate(track, start, client.now_ms, 5, 2000.0, wrap=True),
           Tol(abs=3.0, why="30 deg/s asked: both turn at it"))
    t.fact("velocity_body_speed", peak(track, start, client.now_ms, lambda s: s[4]), RATE)
    stop_here(client)
    start, alt0 = client.now_ms, client.rel_alt_m()
    stream(client, lambda: attitude_target(client, -10.0, 0.5), 2.0)
    t.fact("attitude_pitch_deg", track.at(start + 1800)[6], ANGLE)
    t.fact("attitude_speed_after_1_8s", track.at(start + 1800)[4], RATE)
    t.fact("attitude_climbed_m", client.rel_alt_m() - alt0, HOLD)
    client.idle(5.0)  # GUID_TIMEOUT (3 s): level again
    t.fact("attitude_level_after_timeout", abs(pitch_deg(client)) < 2.0)
    t.fact("mode_after", client.mode)
    return t


def velocity_step_stop(client: Client, track: Track) -> Trace:
    t = hovering(client)
    start = client.now_ms
    last_sent = stream(client, lambda: local_target(client, MAVSDK_VELOCITY_NED, vel=(5.0, 0.0, 0.0)), 6.0)
    end = client.now_ms
    t.fact("speed_in_stream", peak(track, start, end, lambda s: s[4]), RATE)
    client.wait(lambda: speed(client) < 0.3, 20, what="the stop")
    slows = track.first(lambda s: s[4] < 4.5, last_sent)
    t.fact("slows_after_s", (slows - last_sent) / 1000.0,
           Tol(abs=1.0, why="GUID_TIMEOUT (3 s) after the last setpoint, which a busy client sends late"))
    stopped = track.first(lambda s: s[4] < 0.3, slows)
    t.fact("stopped_after_slowing_s", (stopped - slows) / 1000.0, TIME)
    t.fact("slowing_distance_m", path_m(track, slows, stopped), DIST)
    return t


def dronekit(client: Client, track: Track) -> Trace:
    t = hovering(client)
    n0, e0 = ne(client)
    begin = client.now_ms
    t.fact("goto_ack", guided_waypoint(client, n0 + 40.0, e0, 10.0))
    t.fact("goto_40m_s", timed(client, track, lambda s: math.hypot(s[1] - n0 - 40.0, s[2] - e0) < 1.0, 60,
                               "the first goto"), TIME)
    t.fact("groundspeed_result", client.command(mav.MAV_CMD_DO_CHANGE_SPEED, 1, 3.0, -1))
    t.fact("goto2_ack", guided_waypoint(client, n0 + 40.0, e0 + 30.0, 10.0))
    client.wait(lambda: ne(client)[1] - e0 > 15.0, 60, what="half the second goto")
    t.fact("goto2_cruise_speed", track.at(track.first(lambda s: s[2] - e0 > 15.0, begin))[4], RATE)
    client.wait(lambda: math.hypot(ne(client)[0] - n0 - 40.0, ne(client)[1] - e0 - 30.0) < 1.0, 60,
                what="the second goto")
    stream(client, lambda: local_target(client, DRONEKIT_VELOCITY, vel=(-2.0, 0.0, 0.0)), 5.0, hz=1.0)
    client.wait(lambda: speed(client) < 0.3, 20, what="the stop after the velocity")
    t.fact("distance_flown_m", path_m(track, begin, client.now_ms), DIST)
    t.fact("change_alt_ack", guided_waypoint(client, 0, 0, 12.0, current=3))
    t.fact("land_item_ack", guided_waypoint(client, 0, 0, 10.0, command=mav.MAV_CMD_NAV_LAND))
    t.fact("local_frame_ack", guided_waypoint(client, 0, 0, 10.0, frame=mav.MAV_FRAME_LOCAL_NED, as_int=True))
    t.fact("bad_latitude_ack", guided_waypoint(client, 1e8, 0, 10.0))
    client.set_mode(LOITER)
    client.wait(lambda: client.mode == LOITER, 5, what="LOITER")
    t.fact("goto_in_loiter_ack", guided_waypoint(client, 0, 0, 10.0, as_int=True))
    return t


def paused_stop(client: Client, track: Track, t: Trace) -> None:
    """DO_PAUSE_CONTINUE 0 while flying a leg at speed: the ACK, the stop, the hold after it."""
    t.fact("pause_result", client.command(mav.MAV_CMD_DO_PAUSE_CONTINUE, 0))
    paused = client.now_ms  # the ACK's place among the stamped messages: when the vehicle took it
    client.wait(lambda: speed(client) < 0.3, 20, what="the pause")
    stopped = track.first(lambda s: s[4] < 0.3, paused)
    # The speed it had when paused depends on when the client saw 7 m/s and on the speedup: the
    # stop is compared from the speed it peaks at (a vehicle speeding up goes on a moment, as its
    # acceleration turns round within the jerk limit).
    v0 = track.at(paused)[4]
    peak = max((s for s in track.samples if paused <= s[0] <= stopped), key=lambda s: s[4])
    t.fact("speed_gained_after_pause", peak[4] - v0, Tol(abs=0.8, why="the acceleration's turn-round"))
    t.fact("stop_from_peak_s_per_m_s", (stopped - peak[0]) / 1000.0 / peak[4], Tol(rel=0.2, why=TIME.why))
    t.fact("stop_from_peak_m_per_m2_s2", path_m(track, peak[0], stopped) / peak[4] ** 2,
           Tol(abs=0.03, rel=0.15, why="the stop's shape within the acceleration and jerk limits"))
    stopped_at = ne(client)
    client.idle(3.0)
    t.fact("held_m", math.dist(stopped_at, ne(client)), HOLD)


def resumed(client: Client, track: Track, t: Trace, north_m: float, within_m: float) -> None:
    """DO_PAUSE_CONTINUE 1: the ACK, how fast it is going again 4 s later (where it stopped, so
    the rest of the leg, depends on when the client paused), and that it gets there."""
    t.fact("continue_result", client.command(mav.MAV_CMD_DO_PAUSE_CONTINUE, 1))
    went_on = client.now_ms
    client.wait(lambda: abs(ne(client)[0] - north_m) < within_m, 60, what="the leg's end")
    t.fact("speed_4s_after_continue", track.at(went_on + 4000)[4], RATE)


def pause_continue(client: Client, track: Track) -> Trace:
    t = hovering(client)
    n0, e0 = ne(client)
    guided_waypoint(client, n0 + LEG_M, e0, 10.0, as_int=True)
    client.wait(lambda: speed(client) > 7.0, 20, what="7 m/s")
    paused_stop(client, track, t)
    resumed(client, track, t, n0 + LEG_M, 1.0)
    t.fact("bad_param_result", client.command(mav.MAV_CMD_DO_PAUSE_CONTINUE, 2))
    client.set_mode(LOITER)
    client.wait(lambda: client.mode == LOITER, 5, what="LOITER")
    mark = client.now_ms
    t.fact("pause_in_loiter_result", client.command(mav.MAV_CMD_DO_PAUSE_CONTINUE, 0))
    t.fact("resume_in_loiter_result", client.command(mav.MAV_CMD_DO_PAUSE_CONTINUE, 1))
    client.idle(0.5)
    t.fact("said_in_loiter", said(client.texts_since(mark)))
    return t


def auto_pause(client: Client, track: Track) -> Trace:
    """DO_PAUSE_CONTINUE in AUTO: on a waypoint leg, and once the mission's last point is reached."""
    t = hovering(client)
    n0, e0 = ne(client)
    h = client.last["HOME_POSITION"]
    lat = h.latitude + int((n0 + LEG_M) / EARTH_M_PER_DEG * 1e7)
    lon = h.longitude + int(e0 / (EARTH_M_PER_DEG * math.cos(math.radians(h.latitude * 1e-7))) * 1e7)
    t.fact("upload", upload(client, [(mav.MAV_CMD_NAV_WAYPOINT, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT,
                                      0, 0, 0, 0, lat, lon, 10.0)]))
    t.fact("auto_result", client.set_mode(AUTO))
    client.wait(lambda: speed(client) > 7.0, 30, what="7 m/s")
    paused_stop(client, track, t)
    resumed(client, track, t, n0 + LEG_M, 1.5)
    client.idle(3.0)
    mark = client.now_ms
    t.fact("pause_at_the_end_result", client.command(mav.MAV_CMD_DO_PAUSE_CONTINUE, 0))
    client.idle(0.5)
    t.fact("said_at_the_end", said(client.texts_since(mark)))
    t.fact("mode_after", client.mode)
    return t


def condition_yaw(client: Client, track: Track) -> Trace:
    t = hovering(client)
    target = (heading_deg(client) + 90.0) % 360.0
    t.fact("absolute_result", client.command(mav.MAV_CMD_CONDITION_YAW, target, 20.0, 1, 0))
    t.fact("absolute_20deg_s_took_s", timed(client, track, lambda s: abs(angle_between(s[5], target)) < 3.0, 30,
                                            "the heading"), TIME)
    client.idle(1.0)
    yaw1 = heading_deg(client)
    t.fact("relative_ccw_result", client.command(mav.MAV_CMD_CONDITION_YAW, 45.0, 0, -1, 1))
    client.idle(4.0)
    t.fact("relative_ccw_turned_deg", angle_between(yaw1, heading_deg(client)), HEADING)
    yaw2 = heading_deg(client)
    target = (yaw2 - 40.0) % 360.0  # 40 degrees counter-clockwise, asked for clockwise: 320 round
    start = client.now_ms
    t.fact("long_way_result", client.command(mav.MAV_CMD_CONDITION_YAW, target, 60.0, 1, 0))
    client.idle(10.0)
    headings = [s[5] for s in track.samples if s[0] >= start]
    t.fact("long_way_turned_deg", sum(angle_between(a, b) for a, b in zip(headings, headings[1:])), HEADING)
    return t


def climb_speed(client: Client, track: Track) -> Trace:
    t = hovering(client)
    p = client.last["GLOBAL_POSITION_INT"]

    def to(alt):
        client.conn.mav.set_position_target_global_int_send(
            0, 1, 1, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, 0xDF8, p.lat, p.lon, alt, 0, 0, 0, 0, 0, 0, 0, 0)

    def rate_between(a_m: float, b_m: float, after: int) -> float:
        up = b_m > a_m
        t_a = track.first(lambda s: (s[3] > a_m) if up else (s[3] < a_m), after)
        t_b = track.first(lambda s: (s[3] > b_m) if up else (s[3] < b_m), t_a)
        return abs(b_m - a_m) / ((t_b - t_a) / 1000.0)
    to(22.0)
    client.idle(0.5)
    start = client.now_ms
    t.fact("climb_result", client.command(mav.MAV_CMD_DO_CHANGE_SPEED, 2, 1.0, -1))
    client.wait(lambda: client.rel_alt_m() > 21.5, 30, what="22 m")
    t.fact("climb_m_s", rate_between(14.0, 18.0, start), RATE)
    to(10.0)
    client.idle(0.5)
    start = client.now_ms
    t.fact("descent_result", client.command(mav.MAV_CMD_DO_CHANGE_SPEED, 3, 0.5, -1))
    client.wait(lambda: client.rel_alt_m() < 16.5, 30, what="16.5 m")
    t.fact("descent_m_s", rate_between(19.0, 17.0, start), RATE)
    return t


def nogps(client: Client, track: Track) -> Trace:
    t = Trace()
    on_ground_disarmed(client)
    t.fact("mode_result", client.set_mode(GUIDED_NOGPS))
    client.wait(lambda: client.mode == GUIDED_NOGPS, 5, what="GUIDED_NOGPS")
    t.fact("arm_result", client.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1))
    client.idle(1.0)
    t.fact("on_ground_without_targets", client.rel_alt_m() < 0.3)
    start = client.now_ms
    stream(client, lambda: attitude_target(client, 0.0, 0.7), 6.0)
    t.fact("climb_on_thrust_0_7_m_s", peak_rate(track, start + 1000, client.now_ms, 3, 2000.0), RATE)
    start = client.now_ms
    stream(client, lambda: attitude_target(client, 0.0, 0.5), 3.0)  # the climb stops, then holds
    t.fact("held_on_thrust_0_5_m", track.at(start + 2900)[3] - track.at(start + 1200)[3], HOLD)
    start = client.now_ms
    stream(client, lambda: attitude_target(client, -10.0, 0.5), 3.0)
    t.fact("pitch_step_deg", track.at(start + 2500)[6], ANGLE)
    t.fact("pitch_step_speed_after_2_5s", track.at(start + 2500)[4], RATE)
    client.idle(5.0)
    t.fact("level_after_timeout", abs(pitch_deg(client)) < 2.0)
    alt0 = client.rel_alt_m()
    for bad in ([0.0, 0.0, 0.0, 0.0], [math.nan, 0.0, 0.0, 0.0], [2.0, 0.0, 0.0, 0.0]):
        stream(client, lambda: attitude_target(client, thrust=0.5, q=bad), 1.0)
    t.fact("bad_quaternions_alt_change_m", client.rel_alt_m() - alt0, HOLD)
    t.fact("bad_quaternions_pitch_level", abs(pitch_deg(client)) < 2.0)
    mark, alt0 = client.now_ms, client.rel_alt_m()
    stream(client, lambda: attitude_target(client, thrust=math.nan), 1.0)  # the middle: hold the height
    client.idle(0.5)
    t.fact("nan_thrust_said", said(client.texts_since(mark)))
    t.fact("nan_thrust_alt_change_m", client.rel_alt_m() - alt0, HOLD)
    t.fact("thrust_option_set", client.set_param("GUID_OPTIONS", 8))  # the thrust field is a thrust
    start = client.now_ms
    stream(client, lambda: attitude_target(client, 0.0, 0.45), 2.0)
    t.fact("thrust_0_45_climb_m_s", peak_rate(track, start, client.now_ms, 3, 1000.0),
           Tol(abs=0.3, rel=0.25, why="0.45 is above both hovers (Firefly's MOT_THST_HOVER 0.35, "
                                      "ArduCopter SITL's about 0.37): a climb of the same kind"))
    client.set_param("GUID_OPTIONS", 0)
    stream(client, lambda: attitude_target(client, 0.0, 0.5), 2.0)
    t.fact("mode_after", client.mode)
    t.fact("armed_after", client.armed)
    return t


PROBES = {"offboard_landed": offboard_landed, "offboard_flying": offboard_flying,
          "velocity_step_stop": velocity_step_stop, "dronekit": dronekit, "pause_continue": pause_continue,
          "auto_pause": auto_pause,
          "condition_yaw": condition_yaw, "climb_speed": climb_speed, "nogps": nogps}


def run(target, names: list[str] | None = None) -> dict[str, Trace]:
    traces: dict[str, Trace] = {}
    client = target.boot()
    try:
        client.conn.mav.command_long_send(1, 1, mav.MAV_CMD_REQUEST_MESSAGE, 0, 242, 0, 0, 0, 0, 0, 0)
        client.wait(lambda: "HOME_POSITION" in client.last, 10, what="HOME_POSITION")
        track = Track(client)
        with client.listening(track):
            for name, probe in PROBES.items():
                if names is None or name in names:
                    try:
                        traces[name] = probe(client, track)
                    except (ProbeTimeout, StopIteration, ArithmeticError, ValueError) as exc:  # not observed
                        print(f"guided probe {name} stopped: {exc!r}")
                        traces[name] = Trace()
    finally:
        client.close()
        target.close()
    return traces

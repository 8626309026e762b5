"""Refusals: what a vehicle answers to input it should refuse, or survive, in a state where it
cannot act on it: every mode and flying command before home is set and with no GPS at all,
hostile numbers (NaN, inf, 1e30, int32 extremes, unknown frames) in commands and setpoints on a
ready vehicle, and bad mission, fence and rally items.

Facts per command: the COMMAND_ACK result (None: no answer), the mode and arming state after (a
fresh HEARTBEAT), whether home is set after (HOME_POSITION answers a REQUEST_MESSAGE), what the
vehicle said; in flight, the state 2 s after and whether it stayed within 50 m of where it was
and how far it moved in 4 s; per upload, the MISSION_ACK type, the item it came after, and what a download
returns after it.

A vehicle may die on some of this (that is what the area is for): the client then notices that
vehicle time stood still (Client.stall_s), the probe's remaining facts read SILENT, and the next
probe boots a new vehicle, so one crash costs one probe's facts, not the area.
"""
from __future__ import annotations

import math
import re

from ..client import Client, ProbeTimeout, VehicleSilent, mav
from ..facts import Tol, Trace
from .missions import HOME_ITEM, download_commands, send_item
from .states import (GUIDED, HOVER_ALT_M, LOITER, STABILIZE, mode_name, on_ground_disarmed, reach_disarmed_in,
                     reach_flying)
from .texts import said as said_all

# Said by ArduCopter's fence when it indexes a new list, on its own 1 Hz schedule: in the window
# of an upload's answer or not by timing alone; what refuses the fence ("... validation failed")
# comes with the upload.
FENCE_INDEXED = re.compile(r"^Fence Indexed OK$")


def said(texts: list[str]) -> list[str]:
    return [t for t in said_all(texts) if not FENCE_INDEXED.search(t)]

AREA = "refusals"
HOME_LAT, HOME_LON = -35.363261, 149.165230
HOME_LAT_E7, HOME_LON_E7 = round(HOME_LAT * 1e7), round(HOME_LON * 1e7)
EARTH_M_PER_DEG = 111_195.0
NORTH_20M_LAT_E7 = round((HOME_LAT + 20 / EARTH_M_PER_DEG) * 1e7)
NAN, INF = float("nan"), float("inf")
INT32_MAX, INT32_MIN = 2**31 - 1, -2**31
REL = mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT

STALL_S = 5.0           # wall seconds of vehicle time standing still: the vehicle died or went mute
SILENT = "<no answer: vehicle silent>"
TIMED_OUT = "<timed out>"
UNREACHED = "<start state not reached>"
SAID_WITHIN_S = 0.2     # the replies to a command come with its ACK; a fresh HEARTBEAT follows anyway
HOME_REPLY_S = 0.5      # a HOME_POSITION asked for comes within a tick of Firefly at 20x (0.2 s)
# Before home: from the GPS fix (10.2 s) until home at 19.9 s, when nothing that decides these
# answers changes on either vehicle; no command starts after WINDOW_CLOSE_S, so that the longest
# observation (~2 s) ends before home comes. An ARM's refusal changes within the window: ArduCopter
# says "Arm: Accels inconsistent" until about 14 s, then "Arm: Gyros inconsistent", so it is sent
# from ARM_OPEN_S only.
WINDOW_OPEN_S, ARM_OPEN_S, WINDOW_CLOSE_S = 10.6, 15.0, 17.5
WINDOW_BOOTS = 4        # the window is 0.35 s of wall time at Firefly's 20x: a busy machine can miss it
SET_MODE_ACK_S = 1.0    # ArduCopter does not ACK the SET_MODE message: how long to wait for one
NO_GPS_FROM_S = 25.0    # with no GPS: past every start-up stage (the gyros agree at 22.5 s)
HOME_ALT_TOL = Tol(abs=0.5, why="home's altitude is the height estimate where it was set: centimetres "
                                "apart between ArduCopter runs and from Firefly's")


# ----- a vehicle that may die ------------------------------------------------------------------
class Vehicle:
    """The target's present vehicle, booted (again) when a probe needs one and it has none."""

    def __init__(self, target, arrive=None, **boot):
        self.target, self.arrive, self.boot_args = target, arrive, boot
        self.c: Client | None = None
        self.home_alt0: float | None = None  # home's altitude as first reported (hostile-value probes)

    def client(self) -> Client:
        if self.c is None:
            self.c = self.target.boot(**self.boot_args)
            self.c.stall_s = STALL_S
            if self.arrive is not None:
                self.arrive(self)
        return self.c

    def lost(self) -> None:
        """This vehicle is no use any more (dead, or its state out of reach): the next boots anew."""
        if self.c is not None:
            self.c.close()
        self.c = None


class Facts(dict):
    """One probe's facts as they are observed, written to the trace in a fixed order at the end,
    each fact not observed (the vehicle died first) as `missing`."""

    def write(self, trace: Trace, name: str, keys: list[str], missing: str, tols: dict | None = None) -> None:
        for key in keys:
            trace.fact(f"{name}.{key}", self.get(key, missing), (tols or {}).get(key))


def attempt(vehicle: Vehicle, trace: Trace, name: str, keys: list[str], reach, act, tols=None,
            boots: int = 2) -> None:
    """reach(client) a known state (on a new vehicle when that fails, up to `boots` times), then
    act(client, facts)."""
    facts = Facts()
    for _ in range(boots):
        try:
            c = vehicle.client()
            reach(c)
            break
        except ProbeTimeout as exc:
            failure = exc
            vehicle.lost()
    else:
        facts.write(trace, name, keys, f"{UNREACHED[:-1]}: {failure}>", tols)
        return
    missing = SILENT
    try:
        act(c, facts)
    except VehicleSilent:
        vehicle.lost()
    except ProbeTimeout:
        missing = TIMED_OUT
        vehicle.lost()
    facts.write(trace, name, keys, missing, tols)


def within(c: Client, condition, sim_s: float) -> bool:
    """Whether condition() holds within sim_s of vehicle time; a dead vehicle raises."""
    try:
        c.wait(condition, sim_s)
        return True
    except VehicleSilent:
        raise
    except ProbeTimeout:
        return False


def home_is_set(c: Client) -> bool:
    """Ask for HOME_POSITION: a vehicle without home sends none."""
    seen = c.received.get("HOME_POSITION", 0)
    c.conn.mav.command_long_send(1, 1, mav.MAV_CMD_REQUEST_MESSAGE, 0, mav.MAVLINK_MSG_ID_HOME_POSITION,
                                 0, 0, 0, 0, 0, 0)
    return within(c, lambda: c.received.get("HOME_POSITION", 0) > seen, HOME_REPLY_S)


def get_home(c: Client) -> tuple[int | None, float | None]:
    """GET_HOME_POSITION's result and the altitude (m) of the HOME_POSITION it brought, if any."""
    seen = c.received.get("HOME_POSITION", 0)
    result = c.command(mav.MAV_CMD_GET_HOME_POSITION)
    if not within(c, lambda: c.received.get("HOME_POSITION", 0) > seen, 1.0):
        return result, None
    return result, round(c.last["HOME_POSITION"].altitude / 1000.0, 1)


# ----- what is sent ----------------------------------------------------------------------------
def long(command: int, *params):
    return lambda c: c.command(command, *params)


def cint(command: int, frame: int, p1=0.0, p2=0.0, p3=0.0, p4=0.0, x=0, y=0, z=0.0):
    return lambda c: c.command_int(command, frame, p1, p2, p3, p4, x, y, z)


def set_mode_message(mode: int):
    """The SET_MODE message (not the command). ArduCopter 4.7 sends no COMMAND_ACK for it (the
    result is then None); an ACK for it would carry command 11, the message's id."""
    def send(c: Client) -> int | None:
        c.acks.clear()
        c.conn.mav.set_mode_send(1, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, mode)
        return c._ack_result(mav.MAVLINK_MSG_ID_SET_MODE, SET_MODE_ACK_S)
    return send


def set_mode(mode: int):
    return long(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, mode)


MODES_TRIED = (0, 2, 3, 4, 5, 6, 9, 16, 17)
# ARM and TAKEOFF first: an earlier command's side effects (a latched internal error) must not
# decide them.
UNREADY_COMMANDS = {
    "arm": long(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1),
    "takeoff": long(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 10),
    **{f"mode_{mode_name(m)}": set_mode(m) for m in MODES_TRIED},
    "land": long(mav.MAV_CMD_NAV_LAND),
    "rtl": long(mav.MAV_CMD_NAV_RETURN_TO_LAUNCH),
    "reposition": cint(mav.MAV_CMD_DO_REPOSITION, REL, -1, 1, 0, NAN, NORTH_20M_LAT_E7, HOME_LON_E7, 10.0),
    "mission_start": long(mav.MAV_CMD_MISSION_START, 0, 0),
    "get_home_position": long(mav.MAV_CMD_GET_HOME_POSITION),
    "set_home_here": long(mav.MAV_CMD_DO_SET_HOME, 1),
    "condition_yaw": long(mav.MAV_CMD_CONDITION_YAW, 90, 30, 1, 0),
    "change_speed": long(mav.MAV_CMD_DO_CHANGE_SPEED, 1, 3, -1),
    "set_mode_message_land": set_mode_message(9),
}
UNREADY_KEYS = ["result", "mode_after", "armed_after", "home_set_after", "said", "back_to_stabilize"]


def observe_unready(send):
    """Send, then the state after (observe_ground's facts, and whether home is set); a mode
    change is followed by DO_SET_MODE back to STABILIZE."""
    observe = observe_ground(send)

    def act(c: Client, facts: Facts) -> None:
        observe(c, facts)
        facts["home_set_after"] = home_is_set(c)
        facts["back_to_stabilize"] = c.set_mode(STABILIZE) if c.mode != STABILIZE else "-"
        if facts["back_to_stabilize"] is None:
            c.fresh_heartbeat()  # a dead vehicle raises here; a live one that did not answer is a fact
    return act


def disarmed_stabilize(c: Client) -> None:
    if c.armed:
        c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0)
        c.wait(lambda: not c.armed, 5, what="disarmed")
    if c.mode != STABILIZE:
        c.set_mode(STABILIZE)
        c.wait(lambda: c.mode == STABILIZE, 5, what="STABILIZE")


class WindowClosed(ProbeTimeout):
    """Home is set, or nearly, in this boot: the next command needs another."""


def arrive_booting(v: Vehicle) -> None:
    c = v.c
    c.request_streams(10)  # ArduCopter streams nothing until asked
    c.wait(lambda: "ATTITUDE" in c.last, 30, what="streams")


def reach_before_home(open_s: float):
    def reach(c: Client) -> None:
        c.wait(lambda: c.now_ms >= open_s * 1000 and "GPS_RAW_INT" in c.last
               and c.last["GPS_RAW_INT"].fix_type >= 3, 60, what="the GPS fix, before home")
        if c.now_ms > WINDOW_CLOSE_S * 1000 or c.received.get("HOME_POSITION", 0):
            raise WindowClosed("home is (nearly) set: another boot")
        disarmed_stabilize(c)
    return reach


def reach_no_gps(c: Client) -> None:
    c.wait(lambda: c.now_ms >= NO_GPS_FROM_S * 1000, 60, what="past start-up")
    if c.received.get("HOME_POSITION", 0):
        raise WindowClosed("an earlier command set home: another boot")
    disarmed_stabilize(c)


def before_home(target) -> dict[str, Trace]:
    """Each command in the window between the GPS fix and home (about 7 s of vehicle time per
    boot: a boot answers a few commands, the next boot the next few)."""
    trace = Trace()
    vehicle = Vehicle(target, arrive_booting, streams_hz=None, realistic_startup=True)
    for name, send in UNREADY_COMMANDS.items():
        reach = reach_before_home(ARM_OPEN_S if name == "arm" else WINDOW_OPEN_S)
        attempt(vehicle, trace, name, UNREADY_KEYS, reach, observe_unready(send), boots=WINDOW_BOOTS)
    # the proof that every answer came before home (the last command's included)
    trace.fact("window.home_unset_after_every_command",
               all(trace.values[f"{name}.home_set_after"] is False for name in UNREADY_COMMANDS))
    vehicle.lost()
    return {"before_home": trace}


def no_gps(target) -> dict[str, Trace]:
    """The same commands on a vehicle whose GPS never had a fix (SIM_GPS1_ENABLE 0 from power-on)."""
    trace = Trace()
    vehicle = Vehicle(target, arrive_booting, streams_hz=None, realistic_startup=True,
                      params={"SIM_GPS1_ENABLE": 0})
    facts = Facts()
    try:
        c = vehicle.client()
        reach_no_gps(c)
        gps = c.last.get("GPS_RAW_INT")
        facts["gps_fix_type"] = gps.fix_type if gps is not None else None
        facts["home_set"] = home_is_set(c)
    except ProbeTimeout:
        vehicle.lost()
    facts.write(trace, "at_start", ["gps_fix_type", "home_set"], SILENT)
    for name, send in UNREADY_COMMANDS.items():
        attempt(vehicle, trace, name, UNREADY_KEYS, reach_no_gps, observe_unready(send))
    vehicle.lost()
    return {"no_gps": trace}


# ----- hostile values on a ready vehicle --------------------------------------------------------
def arrive_ready(v: Vehicle) -> None:
    _, v.home_alt0 = get_home(v.c)


def reach_ground_guided(v: Vehicle):
    def reach(c: Client) -> None:
        reach_disarmed_in(c, GUIDED)
        c.wait(lambda: c.mode == GUIDED, 5, what="GUIDED")
        _, alt = get_home(c)
        if alt is None or v.home_alt0 is None or abs(alt - v.home_alt0) > 1.0:
            c.command(mav.MAV_CMD_DO_SET_HOME, 1)  # home back where the vehicle stands
    return reach


SET_HOMES = {
    "set_home_long_alt_3e6": long(mav.MAV_CMD_DO_SET_HOME, 0, 0, 0, 0, HOME_LAT, HOME_LON, 3_000_000),
    "set_home_long_alt_nan": long(mav.MAV_CMD_DO_SET_HOME, 0, 0, 0, 0, HOME_LAT, HOME_LON, NAN),
    "set_home_int_frame0_z_1e30": cint(mav.MAV_CMD_DO_SET_HOME, mav.MAV_FRAME_GLOBAL, 0, 0, 0, 0,
                                       HOME_LAT_E7, HOME_LON_E7, 1e30),
    "set_home_int_frame255": cint(mav.MAV_CMD_DO_SET_HOME, 255, 0, 0, 0, 0, HOME_LAT_E7, HOME_LON_E7, 600.0),
}
SET_HOME_KEYS = ["result", "said", "get_home.result", "home_alt_m"]


def observe_set_home(send):
    def act(c: Client, facts: Facts) -> None:
        t0 = c.now_ms
        facts["result"] = send(c)
        c.idle(SAID_WITHIN_S)
        facts["said"] = said(c.texts_since(t0))
        facts["get_home.result"], facts["home_alt_m"] = get_home(c)
    return act


GROUND_COMMANDS = {
    "condition_yaw_nan": long(mav.MAV_CMD_CONDITION_YAW, NAN, 30, 1, 0),
    "condition_yaw_inf": long(mav.MAV_CMD_CONDITION_YAW, INF, 30, 1, 0),
    "condition_yaw_1e30": long(mav.MAV_CMD_CONDITION_YAW, 1e30, 30, 1, 0),
    "condition_yaw_rate_nan": long(mav.MAV_CMD_CONDITION_YAW, 90, NAN, 1, 0),
    "change_speed_nan": long(mav.MAV_CMD_DO_CHANGE_SPEED, 1, NAN, -1),
    "change_speed_inf": long(mav.MAV_CMD_DO_CHANGE_SPEED, 1, INF, -1),
    "change_speed_1e30": long(mav.MAV_CMD_DO_CHANGE_SPEED, 1, 1e30, -1),
    "change_speed_minus1": long(mav.MAV_CMD_DO_CHANGE_SPEED, 1, -1, -1),
}
GROUND_KEYS = ["result", "mode_after", "armed_after", "said"]


def observe_ground(send):
    """Send, then the result, mode, arming and what the vehicle said."""
    def act(c: Client, facts: Facts) -> None:
        t0 = c.now_ms
        facts["result"] = send(c)
        c.idle(SAID_WITHIN_S)
        c.fresh_heartbeat()
        facts["mode_after"], facts["armed_after"] = mode_name(c.mode), c.armed
        facts["said"] = said(c.texts_since(t0))
    return act


def position(c: Client) -> tuple[float, float, float]:
    """North, east, up (m) from home, from GLOBAL_POSITION_INT."""
    m = c.last["GLOBAL_POSITION_INT"]
    north = (m.lat - HOME_LAT_E7) * 1e-7 * EARTH_M_PER_DEG
    east = (m.lon - HOME_LON_E7) * 1e-7 * EARTH_M_PER_DEG * math.cos(math.radians(HOME_LAT))
    return north, east, m.relative_alt / 1000.0


def reach_hover(c: Client) -> None:
    """Flying in GUIDED at HOVER_ALT_M over home (flown back there if a probe moved it), GUIDED
    entered afresh (through LOITER), so no target or speed of an earlier probe is left."""
    reach_flying(c)
    c.set_mode(LOITER)
    c.wait(lambda: c.mode == LOITER, 5, what="LOITER")
    c.set_mode(GUIDED)
    c.wait(lambda: c.mode == GUIDED, 5, what="GUIDED")

    def there() -> bool:
        n, e, up = position(c)
        return math.hypot(n, e) < 1.0 and abs(up - HOVER_ALT_M) < 0.7
    if not there():
        c.conn.mav.set_position_target_global_int_send(0, 1, 1, REL, POS_ONLY, HOME_LAT_E7, HOME_LON_E7,
                                                       HOVER_ALT_M, 0, 0, 0, 0, 0, 0, 0, 0)
        c.wait(there, 90, what="back over home")
        c.idle(1.0)


POS_ONLY = 0b110111111000  # SET_POSITION_TARGET type_mask: position only (no velocity, accel, yaw)
VEL_ONLY = 0b110111000111


def local_target(x=0.0, y=0.0, z=-HOVER_ALT_M, mask=POS_ONLY, vx=0.0):
    return lambda c: c.conn.mav.set_position_target_local_ned_send(
        0, 1, 1, mav.MAV_FRAME_LOCAL_NED, mask, x, y, z, vx, 0, 0, 0, 0, 0, 0, 0)


def global_target(alt: float):
    return lambda c: c.conn.mav.set_position_target_global_int_send(
        0, 1, 1, REL, POS_ONLY, HOME_LAT_E7, HOME_LON_E7, alt, 0, 0, 0, 0, 0, 0, 0, 0)


def reposition(x=NORTH_20M_LAT_E7, y=HOME_LON_E7, z=HOVER_ALT_M, frame=REL):
    return cint(mav.MAV_CMD_DO_REPOSITION, frame, -1, 1, 0, NAN, x, y, z)


FLYING = {  # name -> (send, whether it is a command with an ACK); x=1e30 last (see below)
    "local_x_1e9": (local_target(x=1e9), False),
    "local_z_minus_1e9": (local_target(z=-1e9), False),
    "local_velocity_1e9": (local_target(mask=VEL_ONLY, z=0.0, vx=1e9), False),
    "global_alt_1e30": (global_target(1e30), False),
    "reposition_lat_int32_max": (reposition(x=INT32_MAX), True),
    "reposition_lat_int32_min": (reposition(x=INT32_MIN), True),
    "reposition_lon_int32_max": (reposition(y=INT32_MAX), True),
    "reposition_lon_int32_min": (reposition(y=INT32_MIN), True),
    "reposition_alt_nan": (reposition(z=NAN), True),
    "reposition_alt_inf": (reposition(z=INF), True),
    "reposition_alt_1e30": (reposition(z=1e30), True),
    "reposition_frame255": (reposition(frame=255), True),
    **{f"flying_{name}": (send, True) for name, send in GROUND_COMMANDS.items()},
    # ArduCopter meets a NaN in its position controller ("Internal Errors 0x400", constraining_nan):
    # it drifts off slowly, cannot be flown back, and an internal error refuses every arm after.
    # Last, so no probe depends on the vehicle it leaves.
    "local_x_1e30": (local_target(x=1e30), False),
}
FLYING_KEYS = ["result", "mode_2s", "armed_2s", "within_50m_2s", "moved_m_4s", "climbed_m_4s", "said"]
MOVED_TOL = Tol(abs=3.0, rel=0.5, why="how far a vehicle gets in 4 s toward a far target is its acceleration "
                                      "and jerk shaping, not alike in detail; a refused setpoint moves it by "
                                      "hover noise only (under 0.3 m); ArduCopter's slow drift after x=1e30 "
                                      "(a NaN in its position controller) went 1.5 to 3.8 m in 4 s in repeated runs")
RESTORE_SPEED = (mav.MAV_CMD_DO_CHANGE_SPEED, 1, 10, -1)  # WPNAV_SPEED's 10 m/s on both, after a change


def observe_flying(send, acked: bool, restore_speed: bool):
    def act(c: Client, facts: Facts) -> None:
        t0, where = c.now_ms, position(c)
        result = send(c)
        facts["result"] = result if acked else "-"
        c.wait(lambda: c.now_ms >= t0 + 2000, 10, what="2 s")
        c.fresh_heartbeat()
        facts["mode_2s"], facts["armed_2s"] = mode_name(c.mode), c.armed
        facts["within_50m_2s"] = math.dist(where, position(c)) <= 50.0
        c.wait(lambda: c.now_ms >= t0 + 4000, 10, what="4 s")
        facts["moved_m_4s"] = round(math.dist(where, position(c)), 1) + 0.0  # never -0.0
        facts["climbed_m_4s"] = round(position(c)[2] - where[2], 1) + 0.0
        facts["said"] = said(c.texts_since(t0))
        if restore_speed:
            c.command(*RESTORE_SPEED)
    return act


def hostile_on_ground(vehicle: Vehicle) -> dict[str, Trace]:
    trace = Trace()
    reach = reach_ground_guided(vehicle)
    for name, send in SET_HOMES.items():
        attempt(vehicle, trace, name, SET_HOME_KEYS, reach, observe_set_home(send), {"home_alt_m": HOME_ALT_TOL})
    for name, send in GROUND_COMMANDS.items():
        attempt(vehicle, trace, name, GROUND_KEYS, reach, observe_ground(send))
    return {"hostile_on_ground": trace}


def hostile_flying(vehicle: Vehicle) -> dict[str, Trace]:
    trace = Trace()
    for name, (send, acked) in FLYING.items():
        attempt(vehicle, trace, name, FLYING_KEYS, reach_hover,
                observe_flying(send, acked, restore_speed="change_speed" in name),
                {"moved_m_4s": MOVED_TOL, "climbed_m_4s": MOVED_TOL})
    return {"hostile_flying": trace}


# ----- bad mission, fence and rally items -------------------------------------------------------
MISSION, FENCE, RALLY = mav.MAV_MISSION_TYPE_MISSION, mav.MAV_MISSION_TYPE_FENCE, mav.MAV_MISSION_TYPE_RALLY
G = mav.MAV_FRAME_GLOBAL_INT
TAKEOFF = (mav.MAV_CMD_NAV_TAKEOFF, REL, 0, 0, 0, 0, 0, 0, 10)


def jump(target, repeat):
    return (mav.MAV_CMD_DO_JUMP, REL, target, repeat, 0, 0, 0, 0, 0)


def vertex(count, n_m, e_m, command=mav.MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION):
    lat = HOME_LAT_E7 + round(n_m / EARTH_M_PER_DEG * 1e7)
    lon = HOME_LON_E7 + round(e_m / (EARTH_M_PER_DEG * math.cos(math.radians(HOME_LAT))) * 1e7)
    return (command, G, count, 0, 0, 0, lat, lon, 0)


def circle(radius):
    return (mav.MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION, G, radius, 0, 0, 0, HOME_LAT_E7, HOME_LON_E7, 0)


UPLOADS = {  # name -> (list type, items)
    "mission_command_0": (MISSION, [HOME_ITEM, TAKEOFF, (0, REL, 0, 0, 0, 0, 0, 0, 0)]),
    "mission_command_65535": (MISSION, [HOME_ITEM, TAKEOFF, (65535, REL, 0, 0, 0, 0, 0, 0, 0)]),
    "mission_jump_nan_nan": (MISSION, [HOME_ITEM, TAKEOFF, jump(NAN, NAN)]),
    "mission_jump_to_65535": (MISSION, [HOME_ITEM, TAKEOFF, jump(65535, 1)]),
    "mission_jump_to_minus1": (MISSION, [HOME_ITEM, TAKEOFF, jump(-1, 1)]),
    "mission_jump_to_1e30": (MISSION, [HOME_ITEM, TAKEOFF, jump(1e30, 1)]),
    "fence_circle_radius_nan": (FENCE, [circle(NAN)]),
    "fence_circle_radius_minus50": (FENCE, [circle(-50)]),
    "fence_circle_radius_0": (FENCE, [circle(0)]),
    "fence_circle_radius_inf": (FENCE, [circle(INF)]),
    "fence_polygon_count_nan_on_vertex_2": (FENCE, [vertex(3, 50, -50), vertex(NAN, 50, 50), vertex(3, -50, 0)]),
    "fence_polygon_of_1_vertex": (FENCE, [vertex(1, 50, 0)]),
    "rally_alt_nan": (RALLY, [(mav.MAV_CMD_NAV_RALLY_POINT, REL, 0, 0, 0, 0, HOME_LAT_E7, HOME_LON_E7, NAN)]),
}
UPLOAD_KEYS = ["clear", "ack", "ack_after_item", "said", "download"]


def clear_list(c: Client, kind: int) -> int | None:
    acks: list = []

    def answer(msg):
        if msg.get_type() == "MISSION_ACK" and msg.mission_type == kind:
            acks.append(msg.type)
    with c.listening(answer):
        c.conn.mav.mission_clear_all_send(1, 1, kind)
        within(c, lambda: bool(acks), 5)
    return acks[0] if acks else None


def upload_items(c: Client, kind: int, items: list) -> tuple[int | None, int | None]:
    """The MISSION_ACK type of an upload of `items`, and the item whose sending it answered."""
    requested, acks = [], []

    def answer(msg):
        msg_kind = msg.get_type()
        if msg_kind in ("MISSION_REQUEST", "MISSION_REQUEST_INT") and msg.mission_type == kind and not acks:
            requested.append(msg.seq)
            if msg.seq < len(items):
                send_item(c, msg.seq, items[msg.seq], kind)
        elif msg_kind == "MISSION_ACK" and msg.mission_type == kind:
            acks.append(msg.type)
    with c.listening(answer):
        c.conn.mav.mission_count_send(1, 1, len(items), kind)
        within(c, lambda: bool(acks), 10)
    return (acks[0] if acks else None), (requested[-1] if acks and requested else None)


def observe_upload(kind: int, items: list):
    def act(c: Client, facts: Facts) -> None:
        facts["clear"] = clear_list(c, kind)
        t0 = c.now_ms
        facts["ack"], facts["ack_after_item"] = upload_items(c, kind, items)
        c.idle(SAID_WITHIN_S)
        facts["said"] = said(c.texts_since(t0))
        facts["download"] = download_commands(c, kind=kind)
        if facts["download"] is None:
            c.fresh_heartbeat()  # a stalled download from a dead vehicle is its silence
    return act


# Missions with a jump ArduCopter takes at upload, flown: what AUTO does on reaching the jump.
FLOWN = ("mission_jump_to_65535", "mission_jump_to_minus1", "mission_jump_to_1e30")
FLOWN_KEYS = ["ack", "start", "reached", "said", "mode_end", "armed_end", "flying_end"]
FLOWN_FOR_S = 8.0  # after reaching the takeoff altitude: the jump is the next item, taken at once


def observe_flown(items: list):
    def act(c: Client, facts: Facts) -> None:
        clear_list(c, MISSION)
        facts["ack"], _ = upload_items(c, MISSION, items)
        c.set_mode(GUIDED)
        c.wait(lambda: c.mode == GUIDED, 5, what="GUIDED")
        c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
        c.wait(lambda: c.armed, 10, what="armed")
        t0, reached = c.now_ms, []
        with c.listening(lambda m: reached.append(m.seq) if m.get_type() == "MISSION_ITEM_REACHED" else None):
            facts["start"] = c.command(mav.MAV_CMD_MISSION_START, 0, 0)
            within(c, lambda: c.rel_alt_m() > HOVER_ALT_M - 0.7, 30)
            c.idle(FLOWN_FOR_S)
            c.fresh_heartbeat()
        facts["reached"] = reached
        # the arm's own "Arming motors" may come just before or after the HEARTBEAT that shows it
        facts["said"] = [t for t in said(c.texts_since(t0)) if t != "Arming motors"]
        facts["mode_end"], facts["armed_end"] = mode_name(c.mode), c.armed
        facts["flying_end"] = c.rel_alt_m() > 2.0
    return act


def bad_jumps_flown(vehicle: Vehicle) -> dict[str, Trace]:
    trace = Trace()
    for name in FLOWN:
        attempt(vehicle, trace, name, FLOWN_KEYS, on_ground_disarmed, observe_flown(UPLOADS[name][1]))
    return {"bad_jumps_flown": trace}


def bad_items(vehicle: Vehicle) -> dict[str, Trace]:
    trace = Trace()
    for name, (kind, items) in UPLOADS.items():
        attempt(vehicle, trace, name, UPLOAD_KEYS, on_ground_disarmed, observe_upload(kind, items))
    return {"bad_items": trace}


def run(target) -> dict[str, Trace]:
    traces = {}
    try:
        traces.update(before_home(target))
        traces.update(no_gps(target))
        ready = Vehicle(target, arrive_ready)  # ready to arm: one vehicle for the rest, booted again if it dies
        traces.update(hostile_on_ground(ready))
        traces.update(bad_items(ready))
        traces.update(bad_jumps_flown(ready))
        traces.update(hostile_flying(ready))
    finally:
        target.close()
    return traces

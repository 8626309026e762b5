"""ArduCopter's whole command surface (issue 26): every in-scope MAV_CMD its GCS handles, sent as a
ground station sends it, with the parameters a ground station fills in, in three situations
(disarmed in GUIDED on the ground, armed on the ground in GUIDED, flying in GUIDED at 10 m).

One trace per command, named as in surface/arducopter.json; its facts are "<state>.<fact>", or
"<state>.<variant>.<fact>" for a command sent more than one way (arm and disarm, several message
ids). Per send: the first COMMAND_ACK's result and how many ACKs for it came within 2 s, the mode
and arming from a fresh HEARTBEAT after them, what the vehicle said, the message types it sent
back within 1 s that it was not sending anyway, and where the command has an effect a client can
see, that effect (the nose turning, a servo output, the home moving, the fence bit...).

The link is MAVLink 1 (the harness's client speaks it and ArduCopter follows a ground station's
protocol), so SERVO_OUTPUT_RAW carries servos 1-8 only and RELAY_STATUS (id 12918) cannot be
sent at all: the servo commands use servo 8, and a relay's effect is not observable here.
"""
from __future__ import annotations

import json
import math
import socket
import time
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from ..client import Client, ProbeTimeout, mav
from ..facts import Tol, Trace
from .states import GUIDED, HOVER_ALT_M, LOITER, mode_name, on_ground_disarmed
from .texts import said

AREA = "surface_commands"
KIND = "commands"
SURFACE_DIR = Path(__file__).parents[1] / "surface"

HOME_LAT, HOME_LON, HOME_ALT_M = -35.363261, 149.165230, 584.0
NAN = float("nan")
ACK_WINDOW_S = 2.0      # ACKs for the command counted this long after sending it
REPLY_WINDOW_MS = 1000  # message types that came back this soon after sending...
STREAMED_WINDOW_S = 5.0  # ...and are not among those streamed anyway: seen this long on reaching a state
REBOOT_WAIT_S = 60.0  # wall seconds for a rebooted vehicle to speak again: ArduCopter SITL takes a few
# Not replies: COMMAND_ACK, STATUSTEXT and HEARTBEAT are facts of their own; ArduCopter starts a
# TIMESYNC exchange every few seconds, broadcasts a PARAM_VALUE whenever it saves a parameter of
# its own accord (statistics, learned offsets), and streams POSITION_TARGET_GLOBAL_INT only while
# its mode has a target, which comes and goes within a state: any of them can fall in any window.
NOT_REPLIES = {"COMMAND_ACK", "STATUSTEXT", "HEARTBEAT", "TIMESYNC", "PARAM_VALUE", "POSITION_TARGET_GLOBAL_INT"}
# The first HOME_POSITION of a new 1 Hz stream falls inside the reply window or just after it, by
# phase: for this command home_positions_in_3s says what came back.
NO_REPLY_SET = {"MAV_CMD_SET_MESSAGE_INTERVAL"}
GEOFENCE_BIT = mav.MAV_SYS_STATUS_GEOFENCE
RECEIVE_BUFFER_BYTES = 8 << 20
# Armed on the ground, both vehicles disarm after DISARM_DELAY (10 s). A loaded machine can stall
# this client a quarter of a wall second, 5 s of a vehicle at 20x, and let that run out in the
# middle of a command: with the auto-disarm off, "armed on the ground" lasts as long as needed.
NO_AUTO_DISARM = ("DISARM_DELAY", 0)
SERVO = 8  # an output with no function on a quad (1-4 are motors) that MAVLink 1's SERVO_OUTPUT_RAW carries

FRAME_REL = mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT
FRAME_AMSL = mav.MAV_FRAME_GLOBAL_INT


@dataclass(frozen=True)
class Send:
    """How a ground station sends one command. `p` is param1..param7 (for COMMAND_INT, p1..p4 and
    x, y, z). A location command (`at` set) goes as COMMAND_INT, as MAVSDK and QGroundControl send
    them (ArduCopter takes DO_REPOSITION only that way): `at` = (metres ahead, metres to the
    right, altitude in `frame`) from where the vehicle is, so the command means the same from
    wherever the previous one left it."""
    p: tuple = ()
    at: tuple | None = None
    frame: int = FRAME_REL
    why: str = ""  # why zeros are the normal parameters, or why a choice matters
    heading_in: int | None = None  # the index of a parameter that is the vehicle's heading (deg)


def _send(*p, why=""):
    return Send(tuple(p), why=why)


def _at(ahead, right, alt, *p, frame=FRAME_REL, why=""):
    return Send(tuple(p), (ahead, right, alt), frame, why)


ZEROS = "zeros are how a ground station sends it"
REPOSITION_M = 20.0
# command name -> {variant: Send}; one variant is named "" (facts "<state>.<fact>").
TABLE: dict[str, dict[str, Send]] = {
    # -- arming, modes, flight ------------------------------------------------------------------
    "MAV_CMD_COMPONENT_ARM_DISARM": {"arm": _send(1), "disarm": _send(0)},
    "MAV_CMD_DO_SET_MODE": {"": _send(mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, LOITER,
                                      why="LOITER: a mode other than the state's GUIDED, so the change shows")},
    "MAV_CMD_NAV_TAKEOFF": {"": _send(0, 0, 0, 0, 0, 0, HOVER_ALT_M, why="param7: 10 m above home, as QGC's takeoff")},
    "MAV_CMD_NAV_VTOL_TAKEOFF": {"": _send(0, 0, 0, 0, 0, 0, HOVER_ALT_M, why="as NAV_TAKEOFF")},
    "MAV_CMD_NAV_LAND": {"": _send(why=ZEROS + ": land here (no location = where the vehicle is)")},
    "MAV_CMD_NAV_VTOL_LAND": {"": _send(why=ZEROS + ": land here")},
    "MAV_CMD_NAV_RETURN_TO_LAUNCH": {"": _send(why=ZEROS + ": RTL has no parameters")},
    "MAV_CMD_NAV_LOITER_UNLIM": {"": _send(why=ZEROS + ": 'loiter here' (ArduCopter ignores the location)")},
    "MAV_CMD_DO_CHANGE_SPEED": {"": _send(1, 3, -1, why="groundspeed 3 m/s, throttle unchanged")},
    "MAV_CMD_DO_REPOSITION": {"": _at(REPOSITION_M, 0, HOVER_ALT_M, -1, mav.MAV_DO_REPOSITION_FLAGS_CHANGE_MODE, 0, NAN,
                                      why="20 m ahead at 10 m, default speed, switch to GUIDED, yaw unchanged")},
    "MAV_CMD_CONDITION_YAW": {"": _send(90, 30, 1, 1, why="90 deg clockwise relative to the heading, 30 deg/s")},
    "MAV_CMD_DO_PAUSE_CONTINUE": {"": _send(0, why="0 = pause (QGC's pause button); zero is the normal value")},
    "MAV_CMD_MISSION_START": {"": _send(0, 0, why=ZEROS + ": first and last item 0 = the whole mission")},
    "MAV_CMD_DO_SET_MISSION_CURRENT": {"": _send(1, 0, why="item 1, the first after home; no reset")},
    "MAV_CMD_DO_JUMP_TAG": {"": _send(1, why="tag 1")},
    "MAV_CMD_DO_LAND_START": {"": _send(why=ZEROS + ": no location = the landing sequence nearest the vehicle")},
    "MAV_CMD_DO_RETURN_PATH_START": {"": _send(why=ZEROS + ": no location = from where the vehicle is")},
    "MAV_CMD_DO_FOLLOW": {"": _send(2, why="follow system id 2")},
    "MAV_CMD_DO_FLIGHTTERMINATION": {"": _send(1, why="1 = terminate, the only thing the command is sent for")},
    "MAV_CMD_DO_PARACHUTE": {"": _send(mav.PARACHUTE_RELEASE, why="release: a ground station's parachute button")},
    "MAV_CMD_DO_MOTOR_TEST": {"": _send(1, mav.MOTOR_TEST_THROTTLE_PERCENT, 5, 2, 0, 0,
                                        why="motor 1 at 5 % for 2 s, one motor (count 0), default order")},
    "MAV_CMD_DO_FENCE_ENABLE": {"": _send(1, why="1 = enable")},
    "MAV_CMD_DO_AUX_FUNCTION": {"": _send(9, 2, why="aux function 9 (camera trigger), switch high")},
    "MAV_CMD_DO_SET_SAFETY_SWITCH_STATE": {"": _send(mav.SAFETY_SWITCH_STATE_DANGEROUS,
                                                     why="safety off, the state a vehicle flies in (SAFE=0 would block outputs)")},
    # -- locations: ROI and home ---------------------------------------------------------------
    "MAV_CMD_DO_SET_ROI_LOCATION": {"": _at(0, 50, 0, why="50 m to the right of the nose on the ground: the nose should turn +90 deg")},
    "MAV_CMD_DO_SET_ROI": {"": _at(0, 50, 0, mav.MAV_ROI_LOCATION, why="as DO_SET_ROI_LOCATION, mode MAV_ROI_LOCATION")},
    "MAV_CMD_DO_SET_ROI_NONE": {"": _send(why=ZEROS + ": it has no parameters")},
    "MAV_CMD_DO_SET_ROI_SYSID": {"": _send(2, why="point at system id 2")},
    "MAV_CMD_DO_SET_HOME": {"": _at(20, 0, HOME_ALT_M, 0, frame=FRAME_AMSL,
                                    why="param1 0 = this location: 20 m ahead at the field's AMSL altitude, as QGC's 'set home here'")},
    "MAV_CMD_GET_HOME_POSITION": {"": _send(why=ZEROS + ": it has no parameters")},
    "MAV_CMD_DO_SET_GLOBAL_ORIGIN": {"": _at(0, 0, HOME_ALT_M, frame=FRAME_AMSL, why="the vehicle's own position")},
    "MAV_CMD_EXTERNAL_POSITION_ESTIMATE": {"": _at(0, 0, HOME_ALT_M, 0, 0, 1, NAN, frame=FRAME_AMSL,
                                                   why="the vehicle's own position, 1 m accuracy, now")},
    "MAV_CMD_EXTERNAL_WIND_ESTIMATE": {"": _send(3, 1, 90, 10, why="3 m/s (+-1) from 90 deg (+-10)")},
    # -- messages ---------------------------------------------------------------------------------
    "MAV_CMD_REQUEST_MESSAGE": {"AUTOPILOT_VERSION": _send(148), "HOME_POSITION": _send(242),
                                "EXTENDED_SYS_STATE": _send(245)},
    "MAV_CMD_SET_MESSAGE_INTERVAL": {"": _send(242, 1_000_000, why="HOME_POSITION (not streamed) at 1 Hz")},
    "MAV_CMD_GET_MESSAGE_INTERVAL": {"": _send(30, why="ATTITUDE's interval")},
    "MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES": {"": _send(1, why="1 = request (0 is refused)")},
    "MAV_CMD_DO_SEND_BANNER": {"": _send(why=ZEROS + ": it has no parameters")},
    "MAV_CMD_CONTROL_HIGH_LATENCY": {"": _send(0, why="0 = high-latency off: 1 would turn the normal link's streams off")},
    # -- outputs: servos, relays, payloads ---------------------------------------------------------
    "MAV_CMD_DO_SET_SERVO": {"": _send(SERVO, 1500, why="servo 8 (unassigned on a quad, in MAVLink 1's SERVO_OUTPUT_RAW) to 1500 us")},
    "MAV_CMD_DO_REPEAT_SERVO": {"": _send(SERVO, 1900, 2, 0.5, why="servo 8 to 1900 us and back to trim, twice, 0.5 s each")},
    "MAV_CMD_DO_SET_RELAY": {"": _send(0, 1, why="relay 0 on")},
    "MAV_CMD_DO_REPEAT_RELAY": {"": _send(0, 2, 0.5, why="relay 0 toggled twice, 0.5 s each")},
    "MAV_CMD_DO_GRIPPER": {"": _send(1, mav.GRIPPER_ACTION_RELEASE, why="gripper 1, release")},
    "MAV_CMD_DO_WINCH": {"": _send(1, mav.WINCH_RELATIVE_LENGTH_CONTROL, 1, 0.5, why="winch 1, let out 1 m at 0.5 m/s")},
    "MAV_CMD_DO_SPRAYER": {"": _send(1, why="1 = on")},
    "MAV_CMD_AIRFRAME_CONFIGURATION": {"": _send(-1, 0, why="all landing gear, deploy")},
    "MAV_CMD_DO_ADSB_OUT_IDENT": {"": _send(why=ZEROS + ": it has no parameters")},
    # -- camera and mount ---------------------------------------------------------------------------
    "MAV_CMD_DO_DIGICAM_CONTROL": {"": _send(0, 0, 0, 0, 1, why="param5 1 = shoot")},
    "MAV_CMD_DO_DIGICAM_CONFIGURE": {"": _send(0, 125, 0, 100, why="shutter 1/125 s, ISO 100, the rest unchanged")},
    "MAV_CMD_DO_SET_CAM_TRIGG_DIST": {"": _send(10, 0, 1, why="every 10 m, one picture now")},
    "MAV_CMD_SET_CAMERA_ZOOM": {"": _send(mav.ZOOM_TYPE_RANGE, 50, why="zoom to 50 % of the range")},
    "MAV_CMD_SET_CAMERA_FOCUS": {"": _send(mav.FOCUS_TYPE_AUTO, why="autofocus")},
    "MAV_CMD_SET_CAMERA_SOURCE": {"": _send(0, 1, 0, why="all cameras, primary source RGB")},
    "MAV_CMD_IMAGE_START_CAPTURE": {"": _send(0, 0, 1, 0, why="all cameras, one image")},
    "MAV_CMD_IMAGE_STOP_CAPTURE": {"": _send(why=ZEROS + ": camera 0 = all")},
    "MAV_CMD_VIDEO_START_CAPTURE": {"": _send(0, 0, why=ZEROS + ": stream 0 = all, no status messages")},
    "MAV_CMD_VIDEO_STOP_CAPTURE": {"": _send(0, why=ZEROS + ": stream 0 = all")},
    "MAV_CMD_CAMERA_TRACK_POINT": {"": _send(0.5, 0.5, 0.05, why="the image's centre, radius 5 %")},
    "MAV_CMD_CAMERA_TRACK_RECTANGLE": {"": _send(0.4, 0.4, 0.6, 0.6, why="a box round the centre")},
    "MAV_CMD_CAMERA_STOP_TRACKING": {"": _send(why=ZEROS + ": it has no parameters")},
    "MAV_CMD_DO_MOUNT_CONFIGURE": {"": _send(mav.MAV_MOUNT_MODE_MAVLINK_TARGETING, why="mode: MAVLink targeting")},
    "MAV_CMD_DO_MOUNT_CONTROL": {"": _send(-30, 0, 0, 0, 0, 0, mav.MAV_MOUNT_MODE_MAVLINK_TARGETING,
                                           why="pitch -30 deg, roll and yaw 0, mode MAVLink targeting")},
    "MAV_CMD_DO_GIMBAL_MANAGER_PITCHYAW": {"": _send(-30, 0, NAN, NAN, 0, 0, 0,
                                                     why="pitch -30, yaw 0, no rates (NaN, as MAVSDK), gimbal 0")},
    "MAV_CMD_DO_GIMBAL_MANAGER_CONFIGURE": {"": _send(255, 190, -1, -1, 0, 0, 0,
                                                      why="this ground station (255/190) takes primary control")},
    # -- calibration, storage, system ---------------------------------------------------------------
    "MAV_CMD_PREFLIGHT_CALIBRATION": {"": _send(0, 0, 1, why="param3 1 = barometer only")},
    "MAV_CMD_PREFLIGHT_STORAGE": {"": _send(2, why="2 = reset parameters to defaults (0/1 are refused by ArduPilot)")},
    "MAV_CMD_RUN_PREARM_CHECKS": {"": _send(why=ZEROS + ": it has no parameters")},
    "MAV_CMD_BATTERY_RESET": {"": _send(1, 10, why="battery 1 (mask bit 0) to 10 %: far below what a few minutes' flying leaves, so the reset shows")},
    "MAV_CMD_SET_EKF_SOURCE_SET": {"": _send(1, why="source set 1 (the primary)")},
    "MAV_CMD_FIXED_MAG_CAL_YAW": {"": Send((0, 0, 0, 0), heading_in=0,
                                           why="the vehicle's true heading (as a user reads it off the airframe), all compasses, here")},
    "MAV_CMD_DO_START_MAG_CAL": {"": _send(0, 0, 1, 0, 0, why="all compasses, autosave, no delay, no reboot")},
    "MAV_CMD_DO_ACCEPT_MAG_CAL": {"": _send(why=ZEROS + ": mask 0 = all compasses")},
    "MAV_CMD_DO_CANCEL_MAG_CAL": {"": _send(why=ZEROS + ": mask 0 = all compasses")},
    "MAV_CMD_ACCELCAL_VEHICLE_POS": {"": _send(mav.ACCELCAL_VEHICLE_POS_LEVEL, why="'vehicle is level', a calibration's first step")},
    "MAV_CMD_SCRIPTING": {"": _send(mav.SCRIPTING_CMD_STOP_AND_RESTART, why="restart scripts")},
    "MAV_CMD_STORAGE_FORMAT": {"": _send(1, 1, why="storage 1, format (1 = confirm)")},
    "MAV_CMD_START_RX_PAIR": {"": _send(0, 0, why=ZEROS + ": Spektrum, DSM2: the first of each enum")},
    "MAV_CMD_PREFLIGHT_REBOOT_SHUTDOWN": {"": _send(1, why="1 = reboot the autopilot")},
}
REBOOT = "MAV_CMD_PREFLIGHT_REBOOT_SHUTDOWN"


# ----- the surface ----------------------------------------------------------------------------------
def in_scope() -> list[dict]:
    """ArduCopter's in-scope commands: in arducopter.json and not in scope.toml's [[out]]."""
    doc = json.loads((SURFACE_DIR / "arducopter.json").read_text())
    scope = tomllib.loads((SURFACE_DIR / "scope.toml").read_text())
    out = {name for block in scope.get("out", []) if block["kind"] == KIND for name in block["names"]}
    return [e for e in doc[KIND] if e["name"] not in out]


# ----- watching what comes back ---------------------------------------------------------------------
class Seen:
    """Every message type the vehicle sends, stamped with vehicle time: to tell a reply from a
    message that is streamed anyway."""

    def __init__(self, client: Client):
        self.client = client
        self.stamps: list[tuple[int, str]] = []
        self.beats: list[tuple[int, int, bool]] = []  # (vehicle time, mode, armed) of each HEARTBEAT
        self.streamed: set[str] = set()
        self.servos: list[tuple[int, int, int, int]] = []  # (vehicle time, servo1, servo2, servo 8)
        client.listeners.append(self._take)

    def _take(self, msg) -> None:
        kind = msg.get_type()
        self.stamps.append((self.client.now_ms, kind))
        if len(self.stamps) > 20000:
            del self.stamps[:10000]
        if kind == "SERVO_OUTPUT_RAW":
            self.servos.append((self.client.now_ms, msg.servo1_raw, msg.servo2_raw, getattr(msg, f"servo{SERVO}_raw")))
            del self.servos[:-400]
        if kind == "HEARTBEAT":
            self.beats.append((self.client.now_ms, self.client.mode, self.client.armed))
            del self.beats[:-20]

    def state_after(self, t_ms: int) -> tuple | None:
        """(mode, armed) of the first HEARTBEAT sent from `t_ms` on, if one came."""
        return next(((mode, armed) for t, mode, armed in self.beats if t >= t_ms), None)

    def learn_streamed(self) -> None:
        """The types the vehicle sends unasked in this state: a few quiet seconds' worth. (Not
        the seconds before each command: an arm just before it can send HOME_POSITION there.)"""
        self.client.idle(1.0)  # let the state's own messages (an arm's HOME_POSITION) pass
        t0 = self.client.now_ms
        self.client.idle(STREAMED_WINDOW_S)
        self.streamed = {k for t, k in self.stamps if t >= t0}

    def replies(self, t0: int) -> list[str]:
        after = {k for t, k in self.stamps if t0 <= t <= t0 + REPLY_WINDOW_MS}
        return sorted(after - self.streamed - NOT_REPLIES)

    def came(self, kind: str, t0: int, t1: int) -> bool:
        return any(k == kind and t0 <= t <= t1 for t, k in self.stamps)


# ----- geometry ---------------------------------------------------------------------------------
def heading_deg(client: Client) -> float:
    return math.degrees(client.last["ATTITUDE"].yaw) % 360


def turned_deg(before: float, after: float) -> float:
    return (after - before + 180) % 360 - 180


def offset(lat: float, lon: float, north_m: float, east_m: float) -> tuple[float, float]:
    return (lat + north_m / 111_195.0, lon + east_m / (111_195.0 * math.cos(math.radians(lat))))


def distance_m(lat1, lon1, lat2, lon2) -> float:
    dn = (lat2 - lat1) * 111_195.0
    de = (lon2 - lon1) * 111_195.0 * math.cos(math.radians(lat1))
    return math.hypot(dn, de)


def position(client: Client) -> tuple[float, float]:
    g = client.last["GLOBAL_POSITION_INT"]
    return g.lat / 1e7, g.lon / 1e7


def ground_speed(client: Client) -> float:
    g = client.last["GLOBAL_POSITION_INT"]
    return math.hypot(g.vx, g.vy) / 100.0


def target_of(client: Client, at) -> tuple[int, int, float]:
    """`at` (ahead, right, alt) from the vehicle's position and heading -> COMMAND_INT x, y, z."""
    ahead, right, alt = at
    h = math.radians(heading_deg(client))
    north, east = ahead * math.cos(h) - right * math.sin(h), ahead * math.sin(h) + right * math.cos(h)
    lat, lon = offset(*position(client), north, east)
    return int(round(lat * 1e7)), int(round(lon * 1e7)), float(alt)


# ----- the states -----------------------------------------------------------------------------------
SETTLE_S = 0.5  # after reaching a state, for its own texts ("Arming motors") to come in before a command


def arm_in_guided(client: Client) -> None:
    """Armed on the ground in GUIDED (it stays armed: see NO_AUTO_DISARM)."""
    if client.armed and client.mode == GUIDED and client.rel_alt_m() < 0.5:
        return
    on_ground_disarmed(client)
    client.set_mode(GUIDED)
    client.wait(lambda: client.mode == GUIDED, 5, what="GUIDED")
    for _ in range(5):  # a calibration just run can hold arming off a moment
        client.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
        if client.try_wait(lambda: client.armed, 2):
            client.idle(SETTLE_S)
            return
        client.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0)  # a half-armed vehicle (see NotArmable)
        client.idle(1.0)
    raise NotArmable(f"not armable in GUIDED on the ground: {[t for _, _, t in client.texts[-5:]]}")


class NotArmable(ProbeTimeout):
    """A vehicle a command left unable to arm until it reboots: ArduCopter after a motor test
    run while armed (its motors disarmed, itself still counting as armed, so that neither an
    arm nor a disarm changes anything) or a fixed-yaw compass calibration."""


def disarmed_in_guided(client: Client) -> None:
    if client.armed or client.mode != GUIDED:
        on_ground_disarmed(client)
        if client.mode != GUIDED:
            client.set_mode(GUIDED)
            client.try_wait(lambda: client.mode == GUIDED, 2)
        client.idle(SETTLE_S)


def flying_in_guided(client: Client) -> None:
    """Hovering in GUIDED at about 10 m, still: after a command that moved, lowered or turned it,
    a reposition to where it is at 10 m settles it; after one that landed or stopped it, a new
    takeoff (once a vehicle that fell has come to rest on the ground)."""
    if not (client.armed and client.rel_alt_m() > 2.0):
        if not client.armed:
            client.try_wait(lambda: client.rel_alt_m() < 0.5, 30)
        arm_in_guided(client)
        client.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, HOVER_ALT_M)
        client.wait(lambda: client.rel_alt_m() > HOVER_ALT_M - 0.5, 60, what="takeoff altitude")
    elif client.mode != GUIDED:
        client.set_mode(GUIDED)
        client.wait(lambda: client.mode == GUIDED, 5, what="GUIDED")
    if abs(client.rel_alt_m() - HOVER_ALT_M) > 1.0 or ground_speed(client) > 0.5:
        lat, lon = position(client)
        client.command_int(mav.MAV_CMD_DO_REPOSITION, FRAME_REL, -1, 0, 0, NAN,
                           int(round(lat * 1e7)), int(round(lon * 1e7)), HOVER_ALT_M)
        client.try_wait(lambda: abs(client.rel_alt_m() - HOVER_ALT_M) < 0.7 and ground_speed(client) < 0.3, 30)


# Flying and armed first: the calibrations a disarmed vehicle accepts leave it unable to arm
# until it reboots ("Compass calibrated requires reboot").
STATES = {"flying": flying_in_guided, "armed": arm_in_guided, "disarmed": disarmed_in_guided}
# Sent last in each state, in this order, for the same reason.
SPOILERS = ["MAV_CMD_PREFLIGHT_CALIBRATION", "MAV_CMD_ACCELCAL_VEHICLE_POS", "MAV_CMD_DO_START_MAG_CAL",
            "MAV_CMD_DO_ACCEPT_MAG_CAL", "MAV_CMD_DO_CANCEL_MAG_CAL", "MAV_CMD_PREFLIGHT_STORAGE",
            "MAV_CMD_FIXED_MAG_CAL_YAW"]
# Accepted, these leave a vehicle that cannot arm until it reboots (ArduCopter takes a fixed-yaw
# compass calibration even in flight): a fresh vehicle for the next state.
NEEDS_REBOOT_AFTER = {"MAV_CMD_FIXED_MAG_CAL_YAW"}


# ----- effects: what a client sees a command do --------------------------------------------------------
@dataclass
class Effects:
    """Per command, the effect to read after its ACK (state -> reader); `cleanup` undoes what
    would outlast the command and spoil the next one (not a fact)."""
    read: dict = field(default_factory=dict)
    cleanup: object = None


def _turn(client: Client, fact, ctx) -> None:
    ctx.watch(client, 6.0)  # 90 deg at ArduCopter's default yaw rate takes about 2 s; more to settle
    fact("turned_deg", turned_deg(ctx.before, heading_deg(client)),
         Tol(abs=15, why="yaw settles within a few degrees; the two vehicles' yaw tuning differs"))


def _servo_after(client: Client, fact, ctx) -> None:
    client.fresh("SERVO_OUTPUT_RAW")
    fact("servo8_us", getattr(client.last["SERVO_OUTPUT_RAW"], f"servo{SERVO}_raw"))


def _servo_toggles(client: Client, fact, ctx) -> None:
    ctx.watch(client, 1.0)  # two 0.5 s toggles end within the ACK window: read them from the send on
    fact("servo8_values_us", sorted({s8 for t, _, _, s8 in ctx.seen.servos if ctx.t0 <= t <= ctx.end and s8}))


def _motor_spin(client: Client, fact, ctx) -> None:
    ctx.watch(client, 1.0)  # the 2 s test, from the send on
    outputs = [(s1, s2) for t, s1, s2, _ in ctx.seen.servos if ctx.t0 <= t <= ctx.end]
    fact("motor1_max_us", max((s1 for s1, _ in outputs), default=0),
         Tol(abs=40, why="5 % of the PWM range; spin-min scaling differs a little"))
    fact("motor2_spun", max((s2 for _, s2 in outputs), default=0) > 1100)


def _test_ends(client: Client, fact, ctx) -> None:
    ctx.watch(client, 1.5)  # no fact: the 2 s test ends (and says so) inside its own command's window


def _climb(client: Client, fact, ctx) -> None:
    ctx.watch(client, 4.0)
    fact("climbing", client.rel_alt_m() > ctx.before + 1.0)


def _speed_to_goto(client: Client, fact, ctx) -> None:
    lat, lon = position(client)
    h = math.radians(heading_deg(client))
    goal = offset(lat, lon, 100 * math.cos(h), 100 * math.sin(h))
    client.command_int(mav.MAV_CMD_DO_REPOSITION, FRAME_REL, -1, 0, 0, NAN,
                       int(round(goal[0] * 1e7)), int(round(goal[1] * 1e7)), HOVER_ALT_M)
    ctx.watch(client, 8.0)
    fact("speed_to_goto_ms", ground_speed(client), Tol(abs=1.0, why="cruise speed of a goto, after the acceleration"))


def _moves_toward(client: Client, fact, ctx) -> None:
    """Gone 5 m of the 20 toward the goal (from where it was sent): an overshot wait only adds."""
    ctx.watch(client, 5.0)
    fact("moving_toward", distance_m(*position(client), *ctx.before) < REPOSITION_M - 5.0)


def _home(client: Client, fact, ctx) -> None:
    seen = client.received.get("HOME_POSITION", 0)
    client.command(mav.MAV_CMD_REQUEST_MESSAGE, 242)
    if not client.try_wait(lambda: client.received.get("HOME_POSITION", 0) > seen, 2):
        fact("home_off_target_m", None)
        return
    h = client.last["HOME_POSITION"]
    fact("home_off_target_m", distance_m(h.latitude / 1e7, h.longitude / 1e7, *ctx.before),
         Tol(abs=1.5, why="the location as stored: centimetres; 20 m if ignored"))


def _fence(client: Client, fact, ctx) -> None:
    client.fresh("SYS_STATUS")
    fact("fence_enabled", bool(client.last["SYS_STATUS"].onboard_control_sensors_enabled & GEOFENCE_BIT))


def _battery(client: Client, fact, ctx) -> None:
    client.fresh("SYS_STATUS")
    fact("battery_remaining_pct", client.last["SYS_STATUS"].battery_remaining,
         Tol(abs=2, why="percent; a second's draw"))


def _home_rate(client: Client, fact, ctx) -> None:
    start, end = ctx.watch(client, 3.0)
    fact("home_positions_in_3s", sum(1 for t, k in ctx.seen.stamps if k == "HOME_POSITION" and start <= t < end),
         Tol(abs=1, why="1 Hz over 3 s: 2 to 4 by phase"))


def _interval(client: Client, fact, ctx) -> None:
    m = client.last.get("MESSAGE_INTERVAL")
    fact("interval_us", m.interval_us if m is not None and ctx.seen.came("MESSAGE_INTERVAL", ctx.t0, client.now_ms)
         else None)


def _camera_feedback(client: Client, fact, ctx) -> None:
    fact("camera_feedback", ctx.seen.came("CAMERA_FEEDBACK", ctx.t0, client.now_ms))


def _restore_home(client: Client) -> None:
    client.command_int(mav.MAV_CMD_DO_SET_HOME, FRAME_AMSL, 0, 0, 0, 0,
                       int(HOME_LAT * 1e7), int(HOME_LON * 1e7), HOME_ALT_M)


FLY = ("flying",)
ALL = ("disarmed", "armed", "flying")
EFFECTS = {
    "MAV_CMD_DO_SET_ROI_LOCATION": Effects({s: _turn for s in FLY},
                                           lambda c: c.command(mav.MAV_CMD_DO_SET_ROI_NONE)),
    "MAV_CMD_DO_SET_ROI": Effects({s: _turn for s in FLY}, lambda c: c.command(mav.MAV_CMD_DO_SET_ROI_NONE)),
    "MAV_CMD_CONDITION_YAW": Effects({s: _turn for s in FLY}),
    "MAV_CMD_DO_SET_SERVO": Effects({s: _servo_after for s in ALL}),
    "MAV_CMD_DO_REPEAT_SERVO": Effects({s: _servo_toggles for s in ALL}),
    "MAV_CMD_DO_MOTOR_TEST": Effects({"disarmed": _motor_spin, "armed": _test_ends}),
    # a paused GUIDED holds its heading against a later ROI: continue
    "MAV_CMD_DO_PAUSE_CONTINUE": Effects({}, lambda c: c.command(mav.MAV_CMD_DO_PAUSE_CONTINUE, 1)),
    "MAV_CMD_NAV_TAKEOFF": Effects({"armed": _climb}),
    "MAV_CMD_NAV_VTOL_TAKEOFF": Effects({"armed": _climb}),
    "MAV_CMD_DO_CHANGE_SPEED": Effects({s: _speed_to_goto for s in FLY},
                                       lambda c: c.command(mav.MAV_CMD_DO_CHANGE_SPEED, 1, -1, -1)),
    "MAV_CMD_DO_REPOSITION": Effects({s: _moves_toward for s in FLY}),
    "MAV_CMD_DO_SET_HOME": Effects({s: _home for s in ALL}, _restore_home),
    "MAV_CMD_DO_FENCE_ENABLE": Effects({s: _fence for s in ALL},
                                       lambda c: c.command(mav.MAV_CMD_DO_FENCE_ENABLE, 0)),
    "MAV_CMD_BATTERY_RESET": Effects({s: _battery for s in ALL}),
    # back to the default rate (0), not off (-1): Firefly streams HOME_POSITION by default
    "MAV_CMD_SET_MESSAGE_INTERVAL": Effects({s: _home_rate for s in ALL},
                                            lambda c: c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, 242, 0)),
    "MAV_CMD_GET_MESSAGE_INTERVAL": Effects({s: _interval for s in ALL}),
    "MAV_CMD_DO_DIGICAM_CONTROL": Effects({s: _camera_feedback for s in ALL}),
    "MAV_CMD_DO_START_MAG_CAL": Effects({}, lambda c: c.command(mav.MAV_CMD_DO_CANCEL_MAG_CAL)),
}
# The requests answered by one message: did it come back (for REQUEST_MESSAGE, the variant's).
ANSWERED_BY = {"MAV_CMD_GET_HOME_POSITION": "HOME_POSITION",
               "MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES": "AUTOPILOT_VERSION"}
HEADING_BEFORE = {"MAV_CMD_DO_SET_ROI_LOCATION", "MAV_CMD_DO_SET_ROI", "MAV_CMD_CONDITION_YAW"}
ALTITUDE_BEFORE = {"MAV_CMD_NAV_TAKEOFF", "MAV_CMD_NAV_VTOL_TAKEOFF"}


@dataclass
class Context:
    """What an effect is read against: the value before sending, when it was sent, what came;
    and when its watch was meant to end (a stalled client can overshoot a wait: what it reads
    from the messages it is bounded by this)."""
    before: object
    t0: int
    seen: Seen
    end: int = 0

    def watch(self, client: Client, sim_s: float) -> tuple[int, int]:
        """Let `sim_s` of vehicle time pass; the (start, end) it meant to watch."""
        start = client.now_ms
        self.end = start + int(sim_s * 1000)
        client.idle(sim_s)
        return start, self.end


def widen_receive_buffer(client: Client) -> None:
    """A deep socket buffer: on a loaded machine this client can be starved of the CPU for a
    while, and a vehicle streaming at 20x fills the default buffer in under a second; the
    datagrams after that (an ACK, a reply) would be lost and a command would look unanswered."""
    sock = getattr(client.conn, "port", None)
    if sock is None:
        return
    for option in (getattr(socket, "SO_RCVBUFFORCE", None), socket.SO_RCVBUF):
        if option is None:
            continue
        try:
            sock.setsockopt(socket.SOL_SOCKET, option, RECEIVE_BUFFER_BYTES)
            return
        except OSError:  # SO_RCVBUFFORCE needs CAP_NET_ADMIN; SO_RCVBUF is capped by rmem_max
            continue


# ----- sending and observing ------------------------------------------------------------------------
class Prober:
    def __init__(self, target):
        self.target = target
        self.client: Client | None = None
        self.seen: Seen | None = None

    def boot(self) -> Client:
        self.client = self.target.boot()
        widen_receive_buffer(self.client)
        self.client.set_param(*NO_AUTO_DISARM)
        self.client.stall_s = 20.0  # a vehicle that stops (a reboot) must not hang the probe
        self.seen = Seen(self.client)
        return self.client

    def reboot_fresh(self) -> None:
        """A fresh vehicle in the middle of a state: it streams what the last one did."""
        streamed = self.seen.streamed
        self.boot()
        self.seen.streamed = streamed

    def send(self, entry: dict, how: Send, target_xyz=None) -> None:
        c = self.client
        p = list(how.p) + [0.0] * 7
        if how.heading_in is not None:
            p[how.heading_in] = round(heading_deg(c))
        as_int = how.at is not None or "long" not in entry.get("paths", ["long"])
        c.acks.clear()
        if as_int:
            x, y, z = target_xyz if target_xyz is not None else (int(p[4]), int(p[5]), p[6])
            c.conn.mav.command_int_send(1, 1, how.frame, entry["id"], 0, 0, p[0], p[1], p[2], p[3], x, y, z)
        else:
            c.conn.mav.command_long_send(1, 1, entry["id"], 0, *p[:7])

    def take_acks(self, command: int, into: list) -> bool:
        into.extend(a for a in self.client.acks if a.command == command)
        self.client.acks.clear()
        return bool(into)

    def observe(self, entry: dict, state: str, variant: str, how: Send, trace: Trace) -> int | None:
        c, name = self.client, entry["name"]
        prefix = f"{state}.{variant}." if variant else f"{state}."

        def fact(key, value, tol=None):
            trace.fact(prefix + key, value, tol)
        xyz = target_of(c, how.at) if how.at is not None else None
        before = (heading_deg(c) if name in HEADING_BEFORE else c.rel_alt_m() if name in ALTITUDE_BEFORE
                  else (xyz[0] / 1e7, xyz[1] / 1e7) if xyz is not None else None)
        t0 = c.now_ms
        self.send(entry, how, xyz)
        acks: list = []
        c.try_wait(lambda: self.take_acks(entry["id"], acks), 5.0)
        end = t0 + ACK_WINDOW_S * 1000
        if c.now_ms < end:
            c.idle((end - c.now_ms) / 1000.0)
        self.take_acks(entry["id"], acks)
        fact("result", acks[0].result if acks else None)
        fact("acks", len(acks))
        if name in ANSWERED_BY:
            fact(f"{ANSWERED_BY[name].lower()}_came", self.seen.came(ANSWERED_BY[name], t0, t0 + REPLY_WINDOW_MS))
        if name == "MAV_CMD_REQUEST_MESSAGE":
            fact("came", self.seen.came(variant, t0, t0 + REPLY_WINDOW_MS))
        effects = EFFECTS.get(name, Effects())
        reader = effects.read.get(state)
        ctx = Context(before, t0, self.seen, t0 + int(ACK_WINDOW_S * 1000))
        if reader is not None:
            reader(c, fact, ctx)
        # the first HEARTBEAT a second after sending (at 1 Hz one falls in the ACK window), or
        # after the effect's watch
        beat_from = t0 + 1000 if reader is None else ctx.end
        state_after = self.seen.state_after(beat_from)
        if state_after is None:
            c.wait(lambda: self.seen.state_after(beat_from) is not None, 5, what="a HEARTBEAT")
            state_after = self.seen.state_after(beat_from)
        mode, armed = state_after
        fact("mode_after", mode_name(mode))
        fact("armed_after", armed)
        # what it said from the send to the end of the ACK window or of the effect's watch (both
        # waited for in full, and a stalled client's overshoot left out)
        fact("said", said([text for stamp, _, text in c.texts if t0 <= stamp <= ctx.end]))
        if name not in NO_REPLY_SET:
            fact("replies", self.seen.replies(t0))
        if effects.cleanup is not None:
            effects.cleanup(c)
            c.idle(1.0)  # what the undone state sent (FENCE_STATUS, HOME_POSITION) dies away
        return acks[0].result if acks else None

    def reboot(self, entry: dict, state: str, how: Send, trace: Trace) -> bool:
        """PREFLIGHT_REBOOT_SHUTDOWN: the ACK, then (in wall time: a rebooted vehicle's clock
        starts again) whether it rebooted (its boot clock went back) and its HEARTBEATs came back.
        True when the vehicle is not the one that was (the caller boots a fresh one)."""
        c = self.client
        newest = c.now_ms
        went_back, beats_after = [], []

        def watch(msg):
            nonlocal newest
            stamp = getattr(msg, "time_boot_ms", None)
            if stamp is not None and msg.get_type() != "TIMESYNC":
                if stamp + 2000 < newest:
                    went_back.append(stamp)
                elif not went_back:
                    newest = max(newest, stamp)
            if msg.get_type() == "HEARTBEAT" and went_back:
                beats_after.append(msg)
        t0 = c.now_ms
        c.listeners.append(watch)
        try:
            self.send(entry, how)
            acks: list = []
            refused = False
            wall0 = last_ask = time.monotonic()
            # In wall time: a restarted vehicle's clock starts again, below the client's; and it
            # streams nothing until asked, so ask often (or its clock passes the old one unseen).
            while time.monotonic() - wall0 < REBOOT_WAIT_S and not (went_back and len(beats_after) >= 2):
                c.pump(0.05)
                self.take_acks(entry["id"], acks)
                accepted = acks and acks[0].result in (mav.MAV_RESULT_ACCEPTED, mav.MAV_RESULT_IN_PROGRESS)
                if acks and not accepted and not went_back and c.now_ms - t0 >= ACK_WINDOW_S * 1000:
                    refused = True
                    break
                if accepted and time.monotonic() - last_ask > 0.5:
                    c.request_streams()
                    last_ask = time.monotonic()
            trace.fact(f"{state}.result", acks[0].result if acks else None)
            trace.fact(f"{state}.acks", len(acks))
            if not refused:
                trace.fact(f"{state}.rebooted", bool(went_back))
                trace.fact(f"{state}.heartbeats_resume", len(beats_after) >= 2)
                return True
            c.fresh_heartbeat()
            trace.fact(f"{state}.mode_after", mode_name(c.mode))
            trace.fact(f"{state}.armed_after", c.armed)
            trace.fact(f"{state}.said", said(c.texts_since(t0)))
            return False
        finally:
            c.listeners.remove(watch)


def run(target, entries: list[dict] | None = None) -> dict[str, Trace]:
    entries = in_scope() if entries is None else entries
    traces = {e["name"]: Trace() for e in entries}
    prober = Prober(target)
    try:
        prober.boot()
        ordered = sorted((e for e in entries if e["name"] != REBOOT),
                         key=lambda e: SPOILERS.index(e["name"]) if e["name"] in SPOILERS else -1)
        spoiled = False
        for state, reach in STATES.items():
            if spoiled:  # a fresh vehicle, not one that cannot arm until it reboots
                prober.reboot_fresh()
                spoiled = False
            reach(prober.client)
            prober.seen.learn_streamed()
            for entry in ordered:
                for variant, how in TABLE.get(entry["name"], {"": Send()}).items():
                    try:
                        reach(prober.client)
                    except NotArmable:
                        prober.reboot_fresh()
                        reach(prober.client)
                    result = prober.observe(entry, state, variant, how, traces[entry["name"]])
                    spoiled |= entry["name"] in NEEDS_REBOOT_AFTER and result == mav.MAV_RESULT_ACCEPTED
        if any(e["name"] == REBOOT for e in entries):
            # last, from a fresh boot; refused while armed, so disarmed (the one that reboots) last
            entry = next(e for e in entries if e["name"] == REBOOT)
            prober.boot()
            for state in ("armed", "flying", "disarmed"):
                STATES[state](prober.client)
                if prober.reboot(entry, state, TABLE[REBOOT][""], traces[REBOOT]) and state != "disarmed":
                    prober.boot()
    finally:
        target.close()
    return traces

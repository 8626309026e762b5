"""Every message ArduCopter handles (surface/arducopter.json "messages", less scope.toml's [[out]]),
sent as a real client sends it, and what changes on the wire.

Each message is sent in one state: disarmed on the ground in GUIDED for most (parameters, logs,
signing and the mission protocol answer there, and an armed copter on the ground disarms itself
within seconds); flying in GUIDED for the setpoint messages (ArduCopter's GUIDED ignores them on the
ground); flying in LOITER for the stick inputs (RC_CHANNELS_OVERRIDE, MANUAL_CONTROL,
RADIO_RC_CHANNELS: a joystick flies a pilot-controlled mode, GUIDED ignores sticks).

Facts per message, named "<state>.<fact>":
* replies: the message types the vehicle sent within 1 s of it that it was not sending in the
  second before, less the types it streams (seen while calibrating the state, which catches those
  streamed below 1 Hz too) and less what it says unprompted (STATUSTEXT, recorded as texts; its
  own TIMESYNC requests; parameters it saves by itself);
* said, mode_after, armed_after;
* for a message that steers: how far the vehicle moved and turned (coarse tolerances);
* for a message that feeds a sensor: the SYS_STATUS sensor bits it changed (ArduCopter's default
  parameters: no rangefinder, no visual odometry, no ADSB receiver are configured);
* a few more where the message's point is a later effect (signing, stream rates).

A message with no observable effect is recorded as such (no replies, nothing said, no change):
Firefly must then do nothing too.
"""
from __future__ import annotations

import json
import math
import re
import struct
import time
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from pymavlink import mavutil

from ..client import Client, ProbeTimeout, mav
from ..facts import Tol, Trace
from .states import GUIDED, LOITER, mode_name, reach_disarmed_in, reach_flying
from .texts import said

AREA = "surface_messages"
KIND = "messages"
SURFACE = Path(__file__).resolve().parent.parent / "surface"
HOME_LAT, HOME_LON, HOME_ALT_M = -35.363261, 149.165230, 584.0
WINDOW_S = 1.0        # vehicle seconds a reply is waited for
SETTLE_MAX_S = 60.0   # a parameter list or a transfer's retries end well within this
MOVE = Tol(abs=3.0, why="each vehicle's own acceleration, braking and wind; coarse by design")
CLIMB = Tol(abs=1.5, why="altitude held by each vehicle's own controller")
TURN = Tol(abs=15.0, why="each vehicle's own yaw rate limits")
TILT = Tol(abs=4.0, why="attitude controller's own response at the moment sampled")
RATE = Tol(abs=1.5, why="messages counted over 2 s at 10x: a scheduler tick either side")
SIGNING_KEY = bytes(range(1, 33))


# ----- the surface ------------------------------------------------------------------------------
def in_scope() -> list[str]:
    """ArduCopter's messages less the ones scope.toml puts out of scope, in arducopter.json order."""
    doc = json.loads((SURFACE / "arducopter.json").read_text())
    out = {name for block in tomllib.loads((SURFACE / "scope.toml").read_text()).get("out", [])
           if block.get("kind") == KIND for name in block["names"]}
    return [e["name"] for e in doc[KIND] if e["name"] not in out]


# ----- sending ------------------------------------------------------------------------------------
def encode(client: Client, name: str, /, **given):
    """The message `name` with the fields given and zeros (empty strings) elsewhere."""
    cls = getattr(mavutil.mavlink, f"MAVLink_{name.lower()}_message")
    lengths = dict(zip(cls.ordered_fieldnames, cls.array_lengths))  # in wire order, not the XML's
    fields = {}
    for field, kind in zip(cls.fieldnames, cls.fieldtypes):
        length = lengths[field]
        if field in given:
            fields[field] = given[field]
        elif kind == "char":
            fields[field] = b""
        else:
            fields[field] = [0] * length if length else 0
    return getattr(client.conn.mav, f"{name.lower()}_encode")(**fields)


def tx(client: Client, name: str, /, source: tuple[int, int] | None = None, **given) -> None:
    """Send `name`; from another system/component (`source`) where a real sender is not a GCS."""
    msg = encode(client, name, **given)
    link = client.conn.mav
    saved = link.srcSystem, link.srcComponent
    if source:
        link.srcSystem, link.srcComponent = source
    try:
        link.send(msg)
    finally:
        link.srcSystem, link.srcComponent = saved


def tx_radio_rc_channels(client: Client, channels: list[int]) -> None:
    """RADIO_RC_CHANNELS (420, development dialect; pymavlink's has not got it): packed by hand
    as a MAVLink 2 frame, CRC extra 20 as ArduPilot's generated headers say."""
    payload = struct.pack("<IHBBB32h", 0, 0, 1, 1, len(channels), *(channels + [0] * (32 - len(channels))))
    payload = payload.rstrip(b"\0") or b"\0"  # MAVLink 2 trims trailing zeros
    link = client.conn.mav
    link.seq = (link.seq + 1) % 256
    header = struct.pack("<BBBBBBBHB", 0xFD, len(payload), 0, 0, link.seq, link.srcSystem,
                         link.srcComponent, 420 & 0xFFFF, 420 >> 16)
    crc = mavutil.x25crc(header[1:] + payload)
    crc.accumulate(bytes([20]))
    client.conn.write(header + payload + struct.pack("<H", crc.crc))


def q_from_euler(roll: float, pitch: float, yaw: float) -> list[float]:
    cr, sr, cp, sp = math.cos(roll / 2), math.sin(roll / 2), math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return [cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy,
            cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy]


def e7(deg: float) -> int:
    return int(round(deg * 1e7))


def north_of(lat: float, metres: float) -> float:
    return lat + metres / 111_195.0


def east_of(lat: float, lon: float, metres: float) -> float:
    return lon + metres / (111_195.0 * math.cos(math.radians(lat)))


def here(client: Client) -> tuple[float, float, float]:
    g = client.last["GLOBAL_POSITION_INT"]
    return g.lat / 1e7, g.lon / 1e7, g.relative_alt / 1000.0


def local(client: Client) -> tuple[float, float, float]:
    p = client.last["LOCAL_POSITION_NED"]
    return p.x, p.y, p.z


def ftp_payload(opcode: int, path: bytes = b"", seq: int = 0) -> list[int]:
    header = struct.pack("<HBBBBBxI", seq, 0, opcode, len(path), 0, 0, 0)
    return list((header + path).ljust(251, b"\0"))


# ----- how each message is sent -----------------------------------------------------------------
@dataclass(frozen=True)
class Way:
    """How a real client sends one message, in which state, and what else to look at.
    `send(client)` sends it once; with `repeat_hz` the client streams it for `for_s` vehicle
    seconds as real senders do (a sensor, a joystick, a companion computer); `chained`: the
    next step of a protocol exchange begun by the message before it, sent without waiting for
    the link to fall quiet (the vehicle would give up on the exchange)."""
    state: str
    send: Callable[[Client], None]
    use: str
    repeat_hz: float = 0.0
    for_s: float = WINDOW_S
    effect: str = ""            # "", "sensor", "move", "tilt", "stream_rate", "signing"
    chained: bool = False
    center: Callable[[Client], None] | None = None  # sticks centred, before and after (LOITER)


GROUND, FLYING_GUIDED, FLYING_LOITER = "ground", "guided", "loiter"


def _local_target(client: Client) -> None:
    n, e, d = local(client)
    tx(client, "SET_POSITION_TARGET_LOCAL_NED", time_boot_ms=client.now_ms, target_system=1, target_component=1,
       coordinate_frame=mav.MAV_FRAME_LOCAL_NED, type_mask=0b0000_1111_1111_1000, x=n + 10.0, y=e, z=d)


def _global_target(client: Client) -> None:
    lat, lon, alt = here(client)
    tx(client, "SET_POSITION_TARGET_GLOBAL_INT", time_boot_ms=client.now_ms, target_system=1, target_component=1,
       coordinate_frame=mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, type_mask=0b0000_1111_1111_1000,
       lat_int=e7(lat), lon_int=e7(east_of(lat, lon, 10.0)), alt=alt + 5.0)


def _attitude_target(client: Client) -> None:
    yaw = client.last["ATTITUDE"].yaw if "ATTITUDE" in client.last else 0.0
    tx(client, "SET_ATTITUDE_TARGET", time_boot_ms=client.now_ms, target_system=1, target_component=1,
       type_mask=0b0000_0111,  # body rates ignored: attitude and thrust only
       q=q_from_euler(0.0, math.radians(-10.0), yaw), thrust=0.5)  # 0.5: hold the climb rate at zero


def _override(pitch_pwm: int):
    def send(client: Client) -> None:
        tx(client, "RC_CHANNELS_OVERRIDE", target_system=1, target_component=1,
           chan1_raw=1500, chan2_raw=pitch_pwm, chan3_raw=1500, chan4_raw=1500,
           chan5_raw=65535, chan6_raw=65535, chan7_raw=65535, chan8_raw=65535)
    return send


def _manual(x: int):
    def send(client: Client) -> None:
        tx(client, "MANUAL_CONTROL", target=1, x=x, y=0, z=500, r=0, buttons=0)
    return send


def _radio_rc(pitch: int):
    def send(client: Client) -> None:  # channels centred at 0 in this message's 13-bit form
        tx_radio_rc_channels(client, [0, pitch, 0, 0, 0, 0, 0, 0])
    return send


def _mission_item(client: Client, name: str, seq: int) -> None:
    tx(client, name, target_system=1, target_component=1, seq=seq, frame=mav.MAV_FRAME_GLOBAL,
       command=mav.MAV_CMD_NAV_WAYPOINT, current=0, autocontinue=1,
       **({"x": e7(HOME_LAT), "y": e7(HOME_LON)} if name == "MISSION_ITEM_INT" else {"x": HOME_LAT, "y": HOME_LON}),
       z=HOME_ALT_M)


TARGET = {"target_system": 1, "target_component": 1}  # the vehicle's autopilot


WAYS: dict[str, Way] = {
    # --- the link and the GCS ---
    "HEARTBEAT": Way(GROUND, lambda c: tx(c, "HEARTBEAT", type=mav.MAV_TYPE_GCS, autopilot=mav.MAV_AUTOPILOT_INVALID),
                     "every ground station's 1 Hz presence beat (the probe's own client already sends it)"),
    "SYSTEM_TIME": Way(GROUND, lambda c: tx(c, "SYSTEM_TIME", time_unix_usec=int(time.time() * 1e6)),
                       "a GCS giving a vehicle without a clock the time of day"),
    "TIMESYNC": Way(GROUND, lambda c: tx(c, "TIMESYNC", tc1=0, ts1=time.monotonic_ns()),
                    "MAVROS / MAVSDK measuring the link delay and the vehicle's clock offset"),
    "COMMAND_ACK": Way(GROUND, lambda c: tx(c, "COMMAND_ACK", command=mav.MAV_CMD_REQUEST_MESSAGE,
                                            result=mav.MAV_RESULT_ACCEPTED, target_system=1, target_component=1),
                       "a GCS acknowledging a command a vehicle sent it"),
    "COMMAND_LONG": Way(GROUND, lambda c: tx(c, "COMMAND_LONG", **TARGET, command=mav.MAV_CMD_REQUEST_MESSAGE,
                                             param1=mav.MAVLINK_MSG_ID_AUTOPILOT_VERSION),
                        "a GCS asking for the autopilot's version on connecting"),
    "COMMAND_INT": Way(GROUND, lambda c: tx(c, "COMMAND_INT", **TARGET, frame=mav.MAV_FRAME_GLOBAL,
                                            command=mav.MAV_CMD_DO_SET_HOME, param1=0, x=e7(HOME_LAT),
                                            y=e7(HOME_LON), z=HOME_ALT_M),
                       "a GCS's 'set home here' on its map (home put back where it is)"),
    "SET_MODE": Way(GROUND, lambda c: tx(c, "SET_MODE", target_system=1,
                                         base_mode=mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, custom_mode=LOITER),
                    "older GCSs' and DroneKit's mode change (LOITER)"),
    "REQUEST_DATA_STREAM": Way(GROUND, lambda c: tx(c, "REQUEST_DATA_STREAM", **TARGET,
                                                    req_stream_id=mav.MAV_DATA_STREAM_EXTENDED_STATUS,
                                                    req_message_rate=2, start_stop=1),
                               "MAVProxy / Mission Planner setting a stream group's rate (EXTENDED_STATUS 2 Hz)",
                               effect="stream_rate"),
    "AUTOPILOT_VERSION_REQUEST": Way(GROUND, lambda c: tx(c, "AUTOPILOT_VERSION_REQUEST", **TARGET),
                                     "older GCSs asking for the version and capabilities"),
    "STATUSTEXT": Way(GROUND, lambda c: tx(c, "STATUSTEXT", source=(1, mav.MAV_COMP_ID_ONBOARD_COMPUTER),
                                           severity=mav.MAV_SEVERITY_INFO, text=b"companion ready"),
                      "a companion computer announcing itself on the vehicle's network"),
    "RADIO_STATUS": Way(GROUND, lambda c: tx(c, "RADIO_STATUS", source=(51, 68), rssi=200, remrssi=190, txbuf=95,
                                             noise=40, remnoise=40),
                        "a SiK telemetry radio's link report (ArduPilot paces its streams by txbuf)"),
    "RADIO": Way(GROUND, lambda c: tx(c, "RADIO", source=(51, 68), rssi=200, remrssi=190, txbuf=95,
                                      noise=40, remnoise=40),
                 "the same report from older SiK radio firmware"),
    "DATA96": Way(GROUND, lambda c: tx(c, "DATA96", type=42, len=4, data=[1, 2, 3, 4] + [0] * 92),
                  "a companion's opaque data packet (ArduPilot lets Lua scripts read it)"),
    "NAMED_VALUE_FLOAT": Way(GROUND, lambda c: tx(c, "NAMED_VALUE_FLOAT", source=(1, mav.MAV_COMP_ID_ONBOARD_COMPUTER),
                                                  time_boot_ms=c.now_ms, name=b"cpu_temp", value=51.5),
                             "a companion computer reporting a named value (logged, read by scripts)"),
    "SETUP_SIGNING": Way(GROUND, lambda c: tx(c, "SETUP_SIGNING", **TARGET, secret_key=list(SIGNING_KEY),
                                              initial_timestamp=signing_timestamp()),
                         "a GCS installing a link-signing key (then signing its own messages)",
                         effect="signing"),
    "DEVICE_OP_READ": Way(GROUND, lambda c: tx(c, "DEVICE_OP_READ", **TARGET, request_id=7,
                                               bustype=mav.DEVICE_OP_BUSTYPE_I2C, bus=0, address=0x1E,
                                               regstart=0, count=4),
                          "MAVProxy's devop module reading a sensor's registers over I2C"),
    "DEVICE_OP_WRITE": Way(GROUND, lambda c: tx(c, "DEVICE_OP_WRITE", **TARGET, request_id=8,
                                                bustype=mav.DEVICE_OP_BUSTYPE_I2C, bus=0, address=0x1E,
                                                regstart=0x7F, count=1, data=[0] * 128),
                           "MAVProxy's devop module writing one register over I2C"),
    "SERIAL_CONTROL": Way(GROUND, lambda c: tx(c, "SERIAL_CONTROL", device=mav.SERIAL_CONTROL_DEV_SHELL,
                                               flags=mav.SERIAL_CONTROL_FLAG_RESPOND, timeout=50, count=4,
                                               data=list(b"ver\n") + [0] * 66),
                          "MAVProxy's nsh module typing into the autopilot's shell"),
    "FILE_TRANSFER_PROTOCOL": Way(GROUND, lambda c: tx(c, "FILE_TRANSFER_PROTOCOL", target_network=0, **TARGET,
                                                       payload=ftp_payload(3, b"/")),
                                  "QGroundControl's file browser listing a directory over MAVLink FTP"),
    "LED_CONTROL": Way(GROUND, lambda c: tx(c, "LED_CONTROL", **TARGET, instance=0, pattern=0, custom_len=3,
                                            custom_bytes=[255, 0, 0] + [0] * 21),
                       "a GCS setting the notify LED's colour (red)"),
    "PLAY_TUNE": Way(GROUND, lambda c: tx(c, "PLAY_TUNE", **TARGET, tune=b"MFT200L8G", tune2=b""),
                     "a GCS playing a tune on the buzzer to find the vehicle"),
    # --- parameters ---
    "PARAM_REQUEST_READ": Way(GROUND, lambda c: tx(c, "PARAM_REQUEST_READ", **TARGET, param_id=b"RTL_ALT",
                                                   param_index=-1),
                              "a GCS reading one parameter by name"),
    "PARAM_SET": Way(GROUND, lambda c: tx(c, "PARAM_SET", **TARGET, param_id=b"RTL_ALT", param_value=2000.0,
                                          param_type=mav.MAV_PARAM_TYPE_REAL32),
                     "a GCS setting one parameter (RTL_ALT 20 m)"),
    "PARAM_VALUE": Way(GROUND, lambda c: tx(c, "PARAM_VALUE", source=(1, mav.MAV_COMP_ID_CAMERA),
                                            param_id=b"CAM_MODE", param_value=1.0,
                                            param_type=mav.MAV_PARAM_TYPE_REAL32, param_count=1, param_index=0),
                       "another component on the vehicle's network answering a parameter request"),
    # --- missions, fences, rally points: a one-item upload, then download, as GCSs do ---
    "MISSION_CLEAR_ALL": Way(GROUND, lambda c: tx(c, "MISSION_CLEAR_ALL", **TARGET),
                             "a GCS's 'clear mission'"),
    "MISSION_COUNT": Way(GROUND, lambda c: tx(c, "MISSION_COUNT", **TARGET, count=1),
                         "a GCS starting a mission upload (one item: home)"),
    "MISSION_ITEM_INT": Way(GROUND, lambda c: _mission_item(c, "MISSION_ITEM_INT", 0),
                            "the upload's item, as every current GCS sends it", chained=True),
    "MISSION_WRITE_PARTIAL_LIST": Way(GROUND, lambda c: tx(c, "MISSION_WRITE_PARTIAL_LIST", **TARGET,
                                                           start_index=0, end_index=0),
                                      "a GCS rewriting one item of the mission on board"),
    "MISSION_ITEM": Way(GROUND, lambda c: _mission_item(c, "MISSION_ITEM", 0),
                        "the rewritten item, as older GCSs send it (float coordinates)", chained=True),
    "MISSION_REQUEST_LIST": Way(GROUND, lambda c: tx(c, "MISSION_REQUEST_LIST", **TARGET),
                                "a GCS starting a mission download"),
    "MISSION_REQUEST_INT": Way(GROUND, lambda c: tx(c, "MISSION_REQUEST_INT", **TARGET, seq=0),
                               "the download's request for item 0", chained=True),
    "MISSION_REQUEST": Way(GROUND, lambda c: tx(c, "MISSION_REQUEST", **TARGET, seq=0),
                           "the same request as older GCSs send it", chained=True),
    "MISSION_ACK": Way(GROUND, lambda c: tx(c, "MISSION_ACK", **TARGET, type=mav.MAV_MISSION_ACCEPTED),
                       "the GCS closing the download", chained=True),
    "MISSION_SET_CURRENT": Way(GROUND, lambda c: tx(c, "MISSION_SET_CURRENT", **TARGET, seq=0),
                               "a GCS choosing the mission item to fly next"),
    "FENCE_FETCH_POINT": Way(GROUND, lambda c: tx(c, "FENCE_FETCH_POINT", **TARGET, idx=0),
                             "an older GCS reading the fence's first point (pre-mission-protocol fences)"),
    "FENCE_POINT": Way(GROUND, lambda c: tx(c, "FENCE_POINT", **TARGET, idx=0, count=5, lat=HOME_LAT, lng=HOME_LON),
                       "an older GCS writing the fence's return point"),
    "RALLY_FETCH_POINT": Way(GROUND, lambda c: tx(c, "RALLY_FETCH_POINT", **TARGET, idx=0),
                             "an older GCS reading the first rally point"),
    "RALLY_POINT": Way(GROUND, lambda c: tx(c, "RALLY_POINT", **TARGET, idx=0, count=1, lat=e7(HOME_LAT),
                                            lng=e7(HOME_LON), alt=30),
                       "an older GCS writing one rally point"),
    # --- logs: list, fetch a little, end, then erase, as a log browser does ---
    "LOG_REQUEST_LIST": Way(GROUND, lambda c: tx(c, "LOG_REQUEST_LIST", **TARGET, start=0, end=0xFFFF),
                            "a GCS's log browser listing the logs on board"),
    "LOG_REQUEST_DATA": Way(GROUND, lambda c: tx(c, "LOG_REQUEST_DATA", **TARGET, id=1, ofs=0, count=360),
                            "the log browser fetching the start of log 1"),
    "LOG_REQUEST_END": Way(GROUND, lambda c: tx(c, "LOG_REQUEST_END", **TARGET),
                           "the log browser ending the transfer (ArduPilot resumes logging)"),
    "REMOTE_LOG_BLOCK_STATUS": Way(GROUND, lambda c: tx(c, "REMOTE_LOG_BLOCK_STATUS", **TARGET, seqno=0,
                                                        status=mav.MAV_REMOTE_LOG_DATA_BLOCK_ACK),
                                   "MAVProxy's dataflash_logger acknowledging a streamed log block"),
    "LOG_ERASE": Way(GROUND, lambda c: tx(c, "LOG_ERASE", **TARGET), "the log browser's 'erase all logs'"),
    # --- GPS, RTK, origin ---
    "SET_GPS_GLOBAL_ORIGIN": Way(GROUND, lambda c: tx(c, "SET_GPS_GLOBAL_ORIGIN", target_system=1,
                                                      latitude=e7(HOME_LAT), longitude=e7(HOME_LON),
                                                      altitude=int(HOME_ALT_M * 1000)),
                                 "a GCS giving a vehicle without GPS its EKF origin (here: the same)"),
    "GPS_INPUT": Way(GROUND, lambda c: tx(c, "GPS_INPUT", time_usec=c.now_ms * 1000, gps_id=0,
                                          ignore_flags=0, time_week_ms=0, time_week=2300, fix_type=3,
                                          lat=e7(HOME_LAT), lon=e7(HOME_LON), alt=HOME_ALT_M, hdop=0.8, vdop=1.0,
                                          horiz_accuracy=0.5, vert_accuracy=0.8, speed_accuracy=0.2,
                                          satellites_visible=14),
                     "a companion feeding an external GPS (needs GPS1_TYPE 14 on ArduCopter)",
                     repeat_hz=5, effect="sensor"),
    "GPS_RTCM_DATA": Way(GROUND, lambda c: tx(c, "GPS_RTCM_DATA", flags=0, len=6, data=[0xD3, 0, 0, 0, 0, 0] + [0] * 174),
                         "a GCS injecting RTK corrections (current form)", repeat_hz=1, effect="sensor"),
    "GPS_INJECT_DATA": Way(GROUND, lambda c: tx(c, "GPS_INJECT_DATA", **TARGET, len=6,
                                                data=[0xD3, 0, 0, 0, 0, 0] + [0] * 104),
                           "older GCSs injecting RTK corrections", repeat_hz=1, effect="sensor"),
    "TERRAIN_CHECK": Way(GROUND, lambda c: tx(c, "TERRAIN_CHECK", lat=e7(north_of(HOME_LAT, 100)), lon=e7(HOME_LON)),
                         "a GCS asking whether the vehicle has terrain data for a point"),
    "TERRAIN_DATA": Way(GROUND, lambda c: tx(c, "TERRAIN_DATA", lat=e7(HOME_LAT), lon=e7(HOME_LON),
                                             grid_spacing=100, gridbit=0, data=[584] * 16),
                        "a GCS answering the vehicle's TERRAIN_REQUEST with a block of heights"),
    # --- companion-computer position and sensor inputs (defaults: none of them configured) ---
    "VISION_POSITION_ESTIMATE": Way(GROUND, lambda c: tx(c, "VISION_POSITION_ESTIMATE", usec=c.now_ms * 1000),
                                    "a VIO / SLAM camera's pose (VISO_TYPE must name MAVLink)",
                                    repeat_hz=10, effect="sensor"),
    "GLOBAL_VISION_POSITION_ESTIMATE": Way(GROUND, lambda c: tx(c, "GLOBAL_VISION_POSITION_ESTIMATE",
                                                                usec=c.now_ms * 1000),
                                           "a VIO system's pose in a global frame", repeat_hz=10, effect="sensor"),
    "VICON_POSITION_ESTIMATE": Way(GROUND, lambda c: tx(c, "VICON_POSITION_ESTIMATE", usec=c.now_ms * 1000),
                                   "a motion-capture system's pose", repeat_hz=10, effect="sensor"),
    "VISION_SPEED_ESTIMATE": Way(GROUND, lambda c: tx(c, "VISION_SPEED_ESTIMATE", usec=c.now_ms * 1000),
                                 "a VIO camera's velocity", repeat_hz=10, effect="sensor"),
    "VISION_POSITION_DELTA": Way(GROUND, lambda c: tx(c, "VISION_POSITION_DELTA", time_usec=c.now_ms * 1000,
                                                      time_delta_usec=100000, angle_delta=[0, 0, 0],
                                                      position_delta=[0, 0, 0], confidence=90),
                                 "a tracking camera's (T265-style) position change", repeat_hz=10, effect="sensor"),
    "ODOMETRY": Way(GROUND, lambda c: tx(c, "ODOMETRY", time_usec=c.now_ms * 1000, frame_id=mav.MAV_FRAME_LOCAL_FRD,
                                         child_frame_id=mav.MAV_FRAME_BODY_FRD, q=[1, 0, 0, 0],
                                         pose_covariance=[float("nan")] + [0] * 20,
                                         velocity_covariance=[float("nan")] + [0] * 20, quality=100),
                    "MAVROS forwarding a VIO system's odometry", repeat_hz=10, effect="sensor"),
    "ATT_POS_MOCAP": Way(GROUND, lambda c: tx(c, "ATT_POS_MOCAP", time_usec=c.now_ms * 1000, q=[1, 0, 0, 0],
                                              covariance=[float("nan")] + [0] * 20),
                         "a motion-capture system's attitude and position", repeat_hz=10, effect="sensor"),
    "OPTICAL_FLOW": Way(GROUND, lambda c: tx(c, "OPTICAL_FLOW", time_usec=c.now_ms * 1000, sensor_id=0, quality=200,
                                             ground_distance=0.1),
                        "a companion's optical-flow sensor (FLOW_TYPE must name MAVLink)",
                        repeat_hz=10, effect="sensor"),
    "DISTANCE_SENSOR": Way(GROUND, lambda c: tx(c, "DISTANCE_SENSOR", time_boot_ms=c.now_ms, min_distance=20,
                                                max_distance=4000, current_distance=150,
                                                type=mav.MAV_DISTANCE_SENSOR_LASER, id=0,
                                                orientation=mav.MAV_SENSOR_ROTATION_PITCH_270, covariance=255),
                           "a companion's downward rangefinder (RNGFND1_TYPE 10 left at its default 0)",
                           repeat_hz=10, effect="sensor"),
    "OBSTACLE_DISTANCE": Way(GROUND, lambda c: tx(c, "OBSTACLE_DISTANCE", time_usec=c.now_ms * 1000,
                                                  sensor_type=mav.MAV_DISTANCE_SENSOR_LASER,
                                                  distances=[800] * 8 + [65535] * 64, increment=45,
                                                  min_distance=20, max_distance=2000, frame=mav.MAV_FRAME_BODY_FRD),
                             "a companion's 360° scan for avoidance (PRX1_TYPE left at 0)",
                             repeat_hz=10, effect="sensor"),
    "OBSTACLE_DISTANCE_3D": Way(GROUND, lambda c: tx(c, "OBSTACLE_DISTANCE_3D", time_boot_ms=c.now_ms,
                                                     sensor_type=mav.MAV_DISTANCE_SENSOR_LASER,
                                                     frame=mav.MAV_FRAME_BODY_FRD, obstacle_id=65535,
                                                     x=5.0, y=0.0, z=0.0, min_distance=0.2, max_distance=20.0),
                                "a companion's 3D obstacle for avoidance", repeat_hz=10, effect="sensor"),
    "LANDING_TARGET": Way(GROUND, lambda c: tx(c, "LANDING_TARGET", time_usec=c.now_ms * 1000, target_num=0,
                                               frame=mav.MAV_FRAME_BODY_FRD, angle_x=0.05, angle_y=-0.02,
                                               distance=5.0, size_x=0.1, size_y=0.1),
                          "an IR-LOCK / camera's landing-target bearing (PLND_ENABLED left at 0)",
                          repeat_hz=10, effect="sensor"),
    "ADSB_VEHICLE": Way(GROUND, lambda c: tx(c, "ADSB_VEHICLE", ICAO_address=0xABCDEF, lat=e7(north_of(HOME_LAT, 800)),
                                             lon=e7(HOME_LON), altitude_type=mav.ADSB_ALTITUDE_TYPE_GEOMETRIC,
                                             altitude=int((HOME_ALT_M + 100) * 1000), heading=18000,
                                             hor_velocity=3000, ver_velocity=0, callsign=b"TEST1",
                                             emitter_type=mav.ADSB_EMITTER_TYPE_LIGHT, tslc=1,
                                             flags=mav.ADSB_FLAGS_VALID_COORDS | mav.ADSB_FLAGS_VALID_ALTITUDE
                                             | mav.ADSB_FLAGS_VALID_HEADING | mav.ADSB_FLAGS_VALID_VELOCITY
                                             | mav.ADSB_FLAGS_VALID_CALLSIGN, squawk=1200),
                        "a GCS or ADSB receiver reporting traffic 800 m north (ADSB_TYPE left at 0)",
                        repeat_hz=1, effect="sensor"),
    "EFI_STATUS": Way(GROUND, lambda c: tx(c, "EFI_STATUS", health=1, rpm=0.0),
                      "an engine controller's status (EFI_TYPE left at 0)", repeat_hz=5, effect="sensor"),
    "LOWEHEISER_GOV_EFI": Way(GROUND, lambda c: tx(c, "LOWEHEISER_GOV_EFI", volt_batt=50.0, efi_index=0),
                              "a Loweheiser generator's governor report", repeat_hz=5, effect="sensor"),
    "GLOBAL_POSITION_INT": Way(GROUND, lambda c: tx(c, "GLOBAL_POSITION_INT", source=(2, 1), time_boot_ms=c.now_ms,
                                                    lat=e7(north_of(HOME_LAT, 30)), lon=e7(HOME_LON),
                                                    alt=int((HOME_ALT_M + 10) * 1000), relative_alt=10000, hdg=0),
                               "another vehicle's position (what FOLLOW mode follows; FOLL_ENABLE left at 0)",
                               repeat_hz=5, effect="sensor"),
    "FOLLOW_TARGET": Way(GROUND, lambda c: tx(c, "FOLLOW_TARGET", source=(2, 1), timestamp=c.now_ms,
                                              est_capabilities=1, lat=e7(north_of(HOME_LAT, 30)), lon=e7(HOME_LON),
                                              alt=HOME_ALT_M + 10),
                         "a ground station's 'follow me' position", repeat_hz=5, effect="sensor"),
    # --- uAvionix ADSB transponder, OpenDroneID ---
    "UAVIONIX_ADSB_OUT_CFG": Way(GROUND, lambda c: tx(c, "UAVIONIX_ADSB_OUT_CFG", ICAO=0xABCDEF, callsign=b"TEST1",
                                                      emitterType=mav.ADSB_EMITTER_TYPE_LIGHT, stallSpeed=0),
                                 "a GCS configuring a uAvionix transponder"),
    "UAVIONIX_ADSB_OUT_DYNAMIC": Way(GROUND, lambda c: tx(c, "UAVIONIX_ADSB_OUT_DYNAMIC", gpsLat=e7(HOME_LAT),
                                                          gpsLon=e7(HOME_LON), gpsFix=3, numSats=10,
                                                          squawk=1200),
                                     "a uAvionix transponder's dynamic report"),
    "UAVIONIX_ADSB_TRANSCEIVER_HEALTH_REPORT": Way(GROUND, lambda c: tx(c, "UAVIONIX_ADSB_TRANSCEIVER_HEALTH_REPORT",
                                                                        rfHealth=mav.UAVIONIX_ADSB_RF_HEALTH_OK),
                                                   "a uAvionix transceiver's health"),
    "UAVIONIX_ADSB_OUT_CONTROL": Way(GROUND, lambda c: tx(c, "UAVIONIX_ADSB_OUT_CONTROL", state=0, baroAltMSL=0,
                                                          squawk=1200, emergencyStatus=0, flight_id=b"TEST1",
                                                          x_bit=0),
                                     "a GCS controlling a uAvionix transponder"),
    "OPEN_DRONE_ID_BASIC_ID": Way(GROUND, lambda c: tx(c, "OPEN_DRONE_ID_BASIC_ID", target_system=0, target_component=0,
                                                       id_or_mac=[0] * 20, id_type=1, ua_type=2,
                                                       uas_id=list(b"SN1234567890") + [0] * 8),
                                  "a Remote ID module's or GCS's basic ID"),
    "OPEN_DRONE_ID_SELF_ID": Way(GROUND, lambda c: tx(c, "OPEN_DRONE_ID_SELF_ID", id_or_mac=[0] * 20,
                                                      description_type=0, description=b"survey"),
                                 "a GCS's self ID for Remote ID"),
    "OPEN_DRONE_ID_SYSTEM": Way(GROUND, lambda c: tx(c, "OPEN_DRONE_ID_SYSTEM", id_or_mac=[0] * 20,
                                                     operator_location_type=0, operator_latitude=e7(HOME_LAT),
                                                     operator_longitude=e7(HOME_LON)),
                                "a GCS's operator location for Remote ID"),
    "OPEN_DRONE_ID_OPERATOR_ID": Way(GROUND, lambda c: tx(c, "OPEN_DRONE_ID_OPERATOR_ID", id_or_mac=[0] * 20,
                                                          operator_id_type=0, operator_id=b"OP123"),
                                     "a GCS's operator ID for Remote ID"),
    "OPEN_DRONE_ID_ARM_STATUS": Way(GROUND, lambda c: tx(c, "OPEN_DRONE_ID_ARM_STATUS", status=0, error=b""),
                                    "a Remote ID module reporting it is ready"),
    "OPEN_DRONE_ID_SYSTEM_UPDATE": Way(GROUND, lambda c: tx(c, "OPEN_DRONE_ID_SYSTEM_UPDATE", **TARGET,
                                                            operator_latitude=e7(HOME_LAT),
                                                            operator_longitude=e7(HOME_LON)),
                                       "a GCS updating the operator location for Remote ID", repeat_hz=1),
    # --- cameras and gimbals (no mount or camera configured by default) ---
    "DIGICAM_CONTROL": Way(GROUND, lambda c: tx(c, "DIGICAM_CONTROL", **TARGET, shot=1),
                           "an older GCS's 'take a picture'"),
    "GOPRO_HEARTBEAT": Way(GROUND, lambda c: tx(c, "GOPRO_HEARTBEAT", source=(1, mav.MAV_COMP_ID_GIMBAL),
                                                status=mav.GOPRO_HEARTBEAT_STATUS_CONNECTED),
                           "a GoPro in a Solo gimbal saying it is there"),
    "CAMERA_INFORMATION": Way(GROUND, lambda c: tx(c, "CAMERA_INFORMATION", source=(1, mav.MAV_COMP_ID_CAMERA),
                                                   time_boot_ms=c.now_ms, vendor_name=[0] * 32, model_name=[0] * 32,
                                                   cam_definition_uri=b""),
                              "a MAVLink camera describing itself"),
    "GIMBAL_REPORT": Way(GROUND, lambda c: tx(c, "GIMBAL_REPORT", source=(1, mav.MAV_COMP_ID_GIMBAL), **TARGET,
                                              delta_time=0.01),
                         "a Solo gimbal's report"),
    "GIMBAL_DEVICE_INFORMATION": Way(GROUND, lambda c: tx(c, "GIMBAL_DEVICE_INFORMATION",
                                                          source=(1, mav.MAV_COMP_ID_GIMBAL), time_boot_ms=c.now_ms,
                                                          vendor_name=b"acme", model_name=b"g1", custom_name=b"",
                                                          pitch_min=-1.57, pitch_max=0.5, gimbal_device_id=1),
                                     "a MAVLink gimbal describing itself"),
    "GIMBAL_DEVICE_ATTITUDE_STATUS": Way(GROUND, lambda c: tx(c, "GIMBAL_DEVICE_ATTITUDE_STATUS",
                                                              source=(1, mav.MAV_COMP_ID_GIMBAL), target_system=0,
                                                              target_component=0, time_boot_ms=c.now_ms,
                                                              q=[1, 0, 0, 0], gimbal_device_id=1),
                                         "a MAVLink gimbal's attitude", repeat_hz=10),
    "GIMBAL_MANAGER_SET_ATTITUDE": Way(GROUND, lambda c: tx(c, "GIMBAL_MANAGER_SET_ATTITUDE", **TARGET, flags=0,
                                                            gimbal_device_id=0,
                                                            q=q_from_euler(0, math.radians(-30), 0),
                                                            angular_velocity_x=float("nan"),
                                                            angular_velocity_y=float("nan"),
                                                            angular_velocity_z=float("nan")),
                                       "a GCS pointing the gimbal 30° down"),
    "GIMBAL_MANAGER_SET_PITCHYAW": Way(GROUND, lambda c: tx(c, "GIMBAL_MANAGER_SET_PITCHYAW", **TARGET, flags=0,
                                                            gimbal_device_id=0, pitch=math.radians(-30), yaw=0.0,
                                                            pitch_rate=float("nan"), yaw_rate=float("nan")),
                                       "a GCS pointing the gimbal by pitch and yaw"),
    "OSD_PARAM_CONFIG": Way(GROUND, lambda c: tx(c, "OSD_PARAM_CONFIG", **TARGET, request_id=1, osd_screen=1,
                                                 osd_index=1, param_id=b"RTL_ALT", config_type=0,
                                                 min_value=0, max_value=10000, increment=100),
                            "a GCS placing a parameter on the OSD's parameter screen"),
    "OSD_PARAM_SHOW_CONFIG": Way(GROUND, lambda c: tx(c, "OSD_PARAM_SHOW_CONFIG", **TARGET, request_id=2,
                                                      osd_screen=1, osd_index=1),
                                 "a GCS reading the OSD's parameter screen"),
    # --- CAN passthrough (MAVCAN) ---
    "CAN_FRAME": Way(GROUND, lambda c: tx(c, "CAN_FRAME", **TARGET, bus=0, len=8, id=0x123, data=[0] * 8),
                     "MAVCAN: a GCS sending a frame onto the vehicle's CAN bus"),
    "CANFD_FRAME": Way(GROUND, lambda c: tx(c, "CANFD_FRAME", **TARGET, bus=0, len=8, id=0x123, data=[0] * 64),
                       "MAVCAN: the same for a CAN FD frame"),
    "CAN_FILTER_MODIFY": Way(GROUND, lambda c: tx(c, "CAN_FILTER_MODIFY", **TARGET, bus=0,
                                                  operation=mav.CAN_FILTER_ADD, num_ids=1, ids=[0x123] + [0] * 15),
                             "MAVCAN: a GCS choosing which frames it is forwarded"),
    # --- flying: setpoints in GUIDED ---
    "SET_POSITION_TARGET_LOCAL_NED": Way(FLYING_GUIDED, _local_target,
                                         "a companion (MAVROS) sending a position 10 m north, local frame",
                                         for_s=8.0, effect="move"),
    "SET_POSITION_TARGET_GLOBAL_INT": Way(FLYING_GUIDED, _global_target,
                                          "a companion or GCS sending a point 10 m east and 5 m up",
                                          for_s=8.0, effect="move"),
    "SET_ATTITUDE_TARGET": Way(FLYING_GUIDED, _attitude_target,
                               "a companion flying attitude and thrust (10° nose down), streamed at 10 Hz",
                               repeat_hz=10, for_s=2.0, effect="tilt"),
    # --- flying: sticks in LOITER ---
    "RC_CHANNELS_OVERRIDE": Way(FLYING_LOITER, _override(1300),
                                "a joystick through the GCS: pitch stick forward, streamed at 10 Hz",
                                repeat_hz=10, for_s=3.0, effect="move", center=_override(1500)),
    "MANUAL_CONTROL": Way(FLYING_LOITER, _manual(500),
                          "QGroundControl's joystick: pitch half forward, streamed at 10 Hz",
                          repeat_hz=10, for_s=3.0, effect="move", center=_manual(0)),
    "RADIO_RC_CHANNELS": Way(FLYING_LOITER, _radio_rc(-1300),
                             "a MAVLink radio receiver's channels: pitch forward, streamed at 10 Hz",
                             repeat_hz=10, for_s=3.0, effect="move", center=_radio_rc(0)),
}
# Steps of one exchange are sent in this order (the mission upload before its download, logs
# listed before one is fetched and erased, the parameter list last: its stream lasts seconds).
ORDER = ["MISSION_CLEAR_ALL", "MISSION_COUNT", "MISSION_ITEM_INT", "MISSION_WRITE_PARTIAL_LIST", "MISSION_ITEM",
         "MISSION_REQUEST_LIST", "MISSION_REQUEST_INT", "MISSION_REQUEST", "MISSION_ACK", "MISSION_SET_CURRENT",
         "LOG_REQUEST_LIST", "LOG_REQUEST_DATA", "LOG_REQUEST_END", "REMOTE_LOG_BLOCK_STATUS", "LOG_ERASE"]
LAST = ["PARAM_REQUEST_LIST", "SETUP_SIGNING"]  # signing last: it changes what the link accepts
WAYS["PARAM_REQUEST_LIST"] = Way(GROUND, lambda c: tx(c, "PARAM_REQUEST_LIST", **TARGET),
                                 "every GCS's parameter download on connecting")


def signing_timestamp() -> int:
    """MAVLink signing's clock: 10 µs units since 2015-01-01."""
    return int((time.time() - 1420070400) * 100_000)


# ----- observing ----------------------------------------------------------------------------------
SENSOR_FIELDS = ("onboard_control_sensors_present", "onboard_control_sensors_enabled",
                 "onboard_control_sensors_health")
SENSOR_BITS = {v.name: k for k, v in mav.enums["MAV_SYS_STATUS_SENSOR"].items() if k & (k - 1) == 0 and k}
# Parameters ArduCopter saves and announces by itself (PARAM_VALUE unprompted): its run-time
# counter every 30 s or so, its flight time on landing.
SELF_SAVED = {"STAT_RUNTIME", "STAT_FLTTIME"}
BOARD_ID = re.compile(r"^[0-9a-f]{32}$")  # the board's unique id, said with the banner: each board's own


def unprompted(msg) -> bool:
    """A message the vehicle sends of its own accord, never a reply: its texts (recorded as texts),
    its own TIMESYNC requests (tc1 0), parameters it saves by itself."""
    kind = msg.get_type()
    return (kind == "STATUSTEXT" or (kind == "TIMESYNC" and msg.tc1 == 0)
            or (kind == "PARAM_VALUE" and msg.param_id in SELF_SAVED))


class Watch:
    """Every message of the run, stamped with vehicle time, and the types streamed in the
    present state."""

    def __init__(self, client: Client):
        self.c = client
        self.log: list[tuple[int, str]] = []
        self.background: set[str] = set()
        self.unusual_ms = 0  # when the last message that was not streamed arrived
        client.listeners.append(self.take)

    def take(self, msg) -> None:
        kind = msg.get_type()
        if unprompted(msg):
            return
        self.log.append((self.c.now_ms, kind))
        if kind not in self.background:
            self.unusual_ms = self.c.now_ms

    def types(self, start_ms: int, end_ms: int) -> set[str]:
        found = set()
        for stamp, kind in reversed(self.log):  # newest first: the windows asked about are recent
            if stamp < start_ms:
                break
            if stamp <= end_ms:
                found.add(kind)
        return found

    def types_after(self, mark: int, end_ms: int) -> set[str]:
        """Types logged since `mark` (len(log) when the message went) up to vehicle time end_ms:
        a reply can carry the very stamp the message was sent at."""
        return {kind for stamp, kind in self.log[mark:] if stamp <= end_ms}

    def calibrate(self, sim_s: float = 5.0) -> None:
        """The types streamed in this state: those seen at least twice over `sim_s` (HOME_POSITION
        and TERRAIN_REQUEST come every 2 s on Firefly, so a 1 s window alone would catch them by
        chance; a late answer to an earlier command comes once, and is no stream)."""
        start = self.c.now_ms
        self.c.idle(sim_s)
        counts: dict[str, int] = {}
        for stamp, kind in self.log:
            if stamp >= start:
                counts[kind] = counts.get(kind, 0) + 1
        # An ACK is never a stream: two of them here are a client's retried command, answered twice.
        self.background = {kind for kind, n in counts.items() if n >= 2} - {"COMMAND_ACK", "MISSION_ACK"}
        self.unusual_ms = 0

    def settle(self) -> None:
        """Until a whole second passes with nothing but the streams (a transfer's last replies)."""
        # Strictly more than a second: the window before a message starts a second back, inclusive.
        self.c.wait(lambda: self.c.now_ms - self.unusual_ms > 1000, SETTLE_MAX_S, what="a quiet link")


def sensor_bits(client: Client) -> dict[str, int]:
    s = client.last.get("SYS_STATUS")
    return {f: getattr(s, f) for f in SENSOR_FIELDS} if s else {}


def bits_changed(before: dict, after: dict) -> list[str]:
    changed = []
    for field in SENSOR_FIELDS:
        diff = before.get(field, 0) ^ after.get(field, 0)
        for name, bit in SENSOR_BITS.items():
            if diff & bit:
                state = "on" if after.get(field, 0) & bit else "off"
                changed.append(f"{field.rsplit('_', 1)[1]}:{name.removeprefix('MAV_SYS_STATUS_')}:{state}")
    return sorted(changed)


def stream(client: Client, way: Way, sim_s: float, send=None) -> None:
    """Send the message as its sender does for `sim_s` vehicle seconds (once, or at repeat_hz)."""
    send = send or way.send
    end = client.now_ms + sim_s * 1000
    send(client)
    if not way.repeat_hz:
        client.idle(sim_s)
        return
    period = 1000.0 / way.repeat_hz
    next_ms = client.now_ms + period
    while client.now_ms < end:
        client.wait(lambda: client.now_ms >= min(next_ms, end), sim_s + 5, what="vehicle time")
        if client.now_ms >= next_ms and client.now_ms < end:
            send(client)
            next_ms += period


def observe(client: Client, watch: Watch, name: str, way: Way, trace: Trace, previous_replies: set[str]) -> set[str]:
    state = way.state
    if not way.chained:
        watch.settle()
    t0 = client.now_ms
    before = watch.types(t0 - 1000, t0 - 1)
    bits_before = sensor_bits(client)
    pos0, att0 = (local(client), client.last["ATTITUDE"]) if "LOCAL_POSITION_NED" in client.last else (None, None)
    if way.center:  # sticks centred first, as a joystick is when a pilot takes over, then the mode
        stream(client, Way(state, way.center, "", repeat_hz=10), 0.5)
        client.set_mode(LOITER)
        client.wait(lambda: client.mode == LOITER, 5, what="LOITER")
        t0 = client.now_ms
        before = watch.types(t0 - 1000, t0 - 1) | {"COMMAND_ACK"}  # the ACK of our mode change
        pos0, att0 = local(client), client.last["ATTITUDE"]
    mark = len(watch.log)
    stream(client, way, max(way.for_s, WINDOW_S))
    window = watch.types_after(mark, t0 + int(WINDOW_S * 1000))
    replies = sorted(window - before - watch.background - (previous_replies if way.chained else set()))
    trace.fact(f"{state}.replies", replies)
    if way.effect == "sensor":
        trace.fact(f"{state}.sensors_changed", bits_changed(bits_before, sensor_bits(client)))
    elif way.effect in ("move", "tilt"):
        if way.effect == "tilt":  # the attitude asked for, while it is still being asked for
            trace.fact(f"{state}.pitch_deg", math.degrees(client.last["ATTITUDE"].pitch), TILT)
        n, e, d = local(client)
        dn, de = n - pos0[0], e - pos0[1]
        if state == FLYING_GUIDED and way.effect == "move":  # a setpoint is in the earth frame
            trace.fact(f"{state}.moved_north_m", dn, MOVE)
            trace.fact(f"{state}.moved_east_m", de, MOVE)
        else:  # sticks and attitude act in the body frame, whichever way the nose points
            heading = att0.yaw
            trace.fact(f"{state}.moved_forward_m", dn * math.cos(heading) + de * math.sin(heading), MOVE)
            trace.fact(f"{state}.moved_right_m", -dn * math.sin(heading) + de * math.cos(heading), MOVE)
        trace.fact(f"{state}.climbed_m", pos0[2] - d, CLIMB)
        turned = math.degrees(client.last["ATTITUDE"].yaw - att0.yaw)
        trace.fact(f"{state}.turned_deg", (turned + 180) % 360 - 180, TURN)
    elif way.effect == "stream_rate":
        start = client.now_ms
        client.idle(2.0)
        end = start + 2000  # a client that fell behind reads past the end of its wait: count 2 s only
        count = sum(1 for stamp, kind in watch.log if kind == "SYS_STATUS" and start < stamp <= end)
        trace.fact(f"{state}.sys_status_hz", count / 2.0, RATE)
    elif way.effect == "signing":
        observe_signing(client, trace, state)
    client.fresh_heartbeat()
    trace.fact(f"{state}.said", [t for t in said(client.texts_since(t0)) if not BOARD_ID.match(t)])
    trace.fact(f"{state}.mode_after", mode_name(client.mode))
    trace.fact(f"{state}.armed_after", client.armed)
    if way.center:  # sticks back to the middle, GUIDED again, then the override released
        stream(client, Way(state, way.center, "", repeat_hz=10), 1.0)
        client.set_mode(GUIDED)
        client.wait(lambda: client.mode == GUIDED, 5, what="GUIDED")
        if name == "RC_CHANNELS_OVERRIDE":
            tx(client, "RC_CHANNELS_OVERRIDE", target_system=1, target_component=1,
               **{f"chan{i}_raw": 0 for i in range(1, 9)}, **{f"chan{i}_raw": 65535 for i in range(9, 19)})
    return set(replies)


def answered(client: Client, name: bytes = b"RTL_ALT") -> bool:
    """Whether a PARAM_REQUEST_READ is answered within 1 s."""
    seen = client.received.get("PARAM_VALUE", 0)
    tx(client, "PARAM_REQUEST_READ", target_system=1, target_component=1, param_id=name, param_index=-1)
    return client.try_wait(lambda: client.received.get("PARAM_VALUE", 0) > seen, 1.0)


def observe_signing(client: Client, trace: Trace, state: str) -> None:
    """With a key installed: is an unsigned request still answered (ArduPilot always accepts
    unsigned messages on its first link, SERIAL0, taken to be a secure USB cable), does the
    vehicle sign what it sends, is a signed request answered, and once the key is cleared (all
    zeros, as GCSs clear it) is an unsigned one answered again?"""
    trace.fact(f"{state}.unsigned_answered", answered(client))
    client.conn.setup_signing(SIGNING_KEY, sign_outgoing=True, allow_unsigned_callback=lambda *_: True,
                              link_id=0)
    signed = []  # pymavlink marks a message signed when its signature checks with our key
    with client.listening(lambda m: m.get_type() == "HEARTBEAT" and signed.append(m.get_signed())):
        client.fresh_heartbeat()
    trace.fact(f"{state}.vehicle_signs", signed[-1])
    trace.fact(f"{state}.signed_answered", answered(client))
    tx(client, "SETUP_SIGNING", target_system=1, target_component=1, secret_key=[0] * 32, initial_timestamp=0)
    client.idle(0.5)
    client.conn.disable_signing()
    trace.fact(f"{state}.unsigned_answered_after_clear", answered(client))


# ----- the run ------------------------------------------------------------------------------------
def plan(names: list[str]) -> dict[str, list[str]]:
    """The in-scope messages per state, in the order they are sent."""
    missing = [n for n in names if n not in WAYS]
    if missing:
        raise KeyError(f"no way to send {missing}: add them to WAYS")
    ordered = [n for n in ORDER if n in names] + [n for n in names if n not in ORDER and n not in LAST] \
        + [n for n in LAST if n in names]
    by_state: dict[str, list[str]] = {GROUND: [], FLYING_GUIDED: [], FLYING_LOITER: []}
    for n in ordered:
        by_state[WAYS[n].state].append(n)
    return by_state


def run(target, names: list[str] | None = None) -> dict[str, Trace]:
    by_state = plan(names or in_scope())
    traces: dict[str, Trace] = {}
    client = target.boot()
    watch = Watch(client)
    try:
        reach_disarmed_in(client, GUIDED)
        watch.calibrate()
        previous: set[str] = set()
        for name in by_state[GROUND]:
            way = WAYS[name]
            if not way.chained:
                reach_disarmed_in(client, GUIDED)
            previous = observe(client, watch, name, way, traces.setdefault(name, Trace()), previous)
            if way.effect == "stream_rate":
                client.request_streams(10)  # the rates the probe's client asked for, back
        if by_state[FLYING_GUIDED] or by_state[FLYING_LOITER]:
            if not answered(client):  # the link did not come back from signing: a fresh vehicle
                client = target.boot()
                watch = Watch(client)
            reach_flying(client)
            watch.calibrate()
            for name in by_state[FLYING_GUIDED] + by_state[FLYING_LOITER]:
                reach_flying(client)
                observe(client, watch, name, WAYS[name], traces.setdefault(name, Trace()), set())
                stop_here(client)
    finally:
        target.close()
    return traces


def stop_here(client: Client) -> None:
    """Hold position in GUIDED (a zero velocity, as a companion stops the vehicle) and let it settle."""
    client.set_mode(GUIDED)
    try:
        client.wait(lambda: client.mode == GUIDED, 5, what="GUIDED")
    except ProbeTimeout:
        return
    tx(client, "SET_POSITION_TARGET_LOCAL_NED", time_boot_ms=client.now_ms, target_system=1, target_component=1,
       coordinate_frame=mav.MAV_FRAME_LOCAL_NED, type_mask=0b0000_1111_1100_0111)
    client.idle(3.0)

"""Command microservice: COMMAND_LONG / COMMAND_INT -> one COMMAND_ACK each.

Handlers are a table by command id; each returns a Result and may queue extra messages. Params
the handler uses are checked for NaN/inf before any state changes. An exact retry of the
previous command (clients resend after 0.5 s without an ack) replays the previous result instead
of acting twice.
"""
from __future__ import annotations

import math
import struct
from typing import NamedTuple

from ..estimate import TOLD_DELAY_MAX_S
from ..modes.numbers import ModeNumber
from ..results import Result, Severity
from ..safety.arming import FORCE_ARM_MAGIC, FORCE_DISARM_MAGIC, REPORTED_CHECKS, prearm_failures
from .dialect import mavlink as mav
from ..c_casts import as_int16, as_uint16, as_uint32
from .camera_commands import HANDLERS as CAMERA_HANDLERS
from .camera_messages import REQUESTABLE as CAMERA_REQUESTABLE
from .command_locations import TERRAIN_ALT_FRAMES, is_location, target_ned, terrain_target_ned
from .do_item_commands import HANDLERS as DO_ITEM_HANDLERS
from .housekeeping_commands import HANDLERS as HOUSEKEEPING_HANDLERS
from .mount_commands import HANDLERS as MOUNT_HANDLERS
from .mount_messages import REQUESTABLE as MOUNT_REQUESTABLE
from .winch_messages import REQUESTABLE as WINCH_REQUESTABLE

# Messages ArduCopter ACCEPTS a REQUEST_MESSAGE for although it has nothing to send (a device's
# report with no device made at boot: measured for the gimbal's, the winch's and the camera's). A
# payload family joins here.
ACCEPTED_UNSENT = MOUNT_REQUESTABLE | WINCH_REQUESTABLE | CAMERA_REQUESTABLE
from .payload_commands import HANDLERS as PAYLOAD_HANDLERS
from .external_nav_messages import origin_taken
from .preflight import HANDLERS as PREFLIGHT_HANDLERS

MAV_CMD_DO_SET_GLOBAL_ORIGIN = 611  # MAVLink's, newer than this pymavlink's dialect
RETRY_WINDOW_S = 1.5  # an unconfirmed repeat this close, in wall and in sim time, is a retry
INT32_MAX = 2**31 - 1


class Command(NamedTuple):
    command: int
    p1: float
    p2: float
    p3: float
    p4: float
    p5: float  # latitude in degrees for positional commands
    p6: float  # longitude in degrees
    p7: float  # altitude [m]
    frame: int
    is_int: bool
    confirmation: int
    src: tuple  # (system id, component id)

    @classmethod
    def from_long(cls, m):
        return cls(m.command, m.param1, m.param2, m.param3, m.param4, m.param5, m.param6, m.param7,
                   mav.MAV_FRAME_GLOBAL, False, m.confirmation, (m.get_srcSystem(), m.get_srcComponent()))

    @classmethod
    def from_int(cls, m):
        return cls(m.command, m.param1, m.param2, m.param3, m.param4, m.x * 1e-7, m.y * 1e-7, m.z,
                   m.frame, True, 0, (m.get_srcSystem(), m.get_srcComponent()))


def _finite(*values) -> bool:
    return all(math.isfinite(v) for v in values)


def _int_param(value: float, low: int, high: int) -> int | None:
    if not math.isfinite(value) or value != int(value) or not low <= value <= high:
        return None
    return int(value)


# ----- handlers: (session, Command) -> Result ----------------------------------------------------
def arm_disarm(s, c: Command) -> Result:
    if not _finite(c.p1, c.p2):
        return Result.DENIED
    if c.p1 == 1:
        return s.vehicle.arm(force=c.p2 == FORCE_ARM_MAGIC)
    if c.p1 == 0:
        return s.vehicle.disarm("gcs", force=c.p2 == FORCE_DISARM_MAGIC)
    return Result.DENIED


def takeoff(s, c: Command) -> Result:
    if not _finite(c.p7):
        return Result.DENIED
    return s.vehicle.takeoff(c.p7)


def land(s, c: Command) -> Result:
    return s.vehicle.set_mode(ModeNumber.LAND)


def return_to_launch(s, c: Command) -> Result:
    return s.vehicle.set_mode(ModeNumber.RTL)


def do_land_start(s, c: Command) -> Result:
    return s.vehicle.auto_rtl("land_start")


def do_return_path_start(s, c: Command) -> Result:
    return s.vehicle.auto_rtl("return_path")


def do_set_mode(s, c: Command) -> Result:
    base = _int_param(c.p1, 0, 255)
    custom = _int_param(c.p2, 0, 2**32 - 1)
    if base is None or custom is None:
        return Result.DENIED
    return s.set_mode(base, custom)


def do_change_speed(s, c: Command) -> Result:
    """As ArduCopter: a speed that is not positive (NaN included) DENIED, speed type 4 (the
    enum's end) DENIED; types 0 (air, taken as ground) and 1 (ground) the horizontal speed, 2 the
    climb and 3 the descent speed; the mode takes it or FAILED (any other type too)."""
    if not c.p2 > 0:
        return Result.DENIED
    speed_type = math.floor(c.p1) if math.isfinite(c.p1) else -1
    if speed_type == 4:  # SPEED_TYPE_ENUM_END
        return Result.DENIED
    if speed_type == 2:
        return s.vehicle.set_vertical_speed(c.p2, None)
    if speed_type == 3:
        return s.vehicle.set_vertical_speed(None, c.p2)
    if not 0 <= speed_type <= 1:
        return Result.FAILED
    return s.vehicle.set_speed(c.p2)


def do_pause_continue(s, c: Command) -> Result:
    """As ArduCopter: param 1 = 0 pauses, 1 goes on (as a byte reads them); the mode does it or
    says it failed; any other value DENIED."""
    v = s.vehicle
    action = as_uint16(c.p1) & 0xFF
    if action > 1:
        return Result.DENIED
    result = v.pause(action == 0)
    if result != Result.ACCEPTED:
        v.notify("Failed to pause" if action == 0 else "Failed to resume", Severity.INFO)
    return result


def do_aux_function(s, c: Command) -> Result:
    """As ArduPilot: param 1 the function (RCn_OPTION's numbers, autopilot/rc/aux.py), param 2
    the switch position (0 low, 1 middle, 2 high; above 2 DENIED); a function it does not know
    FAILED with "Invalid channel option (N)"; a mode that refuses is still ACCEPTED."""
    if c.p2 > 2:
        return Result.DENIED
    position = as_uint16(c.p2) & 0xFF if math.isfinite(c.p2) else 0
    return s.vehicle.aux_function(as_uint16(c.p1) if math.isfinite(c.p1) else 0, position)


def do_set_servo(s, c: Command) -> Result:
    """As ArduPilot: param 1 the output (1-16), param 2 the PWM, both cut to integers as its
    uint8 / uint16 take them; an output missing or in use FAILED (servo_relay.py)."""
    return s.vehicle.set_servo(as_uint16(c.p1) & 0xFF, as_uint16(c.p2))


def do_repeat_servo(s, c: Command) -> Result:
    """Param 3 the number of cycles (an int16), param 4 the cycle time [s] (to whole ms)."""
    cycle_ms = as_uint16(c.p4 * 1000.0) if math.isfinite(c.p4) else 0
    return s.vehicle.repeat_servo(as_uint16(c.p1) & 0xFF, as_uint16(c.p2), as_int16(c.p3), cycle_ms / 1000.0)


def do_set_relay(s, c: Command) -> Result:
    """Param 1 the relay (0-5), param 2 the state (1 on, 0 off, else toggle); FAILED for one that
    is not a relay (servo_relay.py)."""
    return s.vehicle.set_relay(as_uint16(c.p1) & 0xFF, as_uint16(c.p2) & 0xFF)


def do_repeat_relay(s, c: Command) -> Result:
    """Param 2 the number of cycles (an int16), param 3 the cycle time [s] (to whole ms)."""
    cycle_ms = as_uint16(c.p3 * 1000.0) if math.isfinite(c.p3) else 0
    return s.vehicle.repeat_relay(as_uint16(c.p1) & 0xFF, as_int16(c.p2), cycle_ms / 1000.0)


def do_reposition(s, c: Command) -> Result:
    if not c.is_int:
        return Result.UNSUPPORTED  # ArduCopter takes a position command only as COMMAND_INT
    v = s.vehicle
    change_mode = _int_param(c.p2, 0, 255) if math.isfinite(c.p2) else 0
    if v.mode.number != ModeNumber.GUIDED and not (change_mode and change_mode & mav.MAV_DO_REPOSITION_FLAGS_CHANGE_MODE):
        return Result.DENIED
    if not is_location(s, c):
        return Result.DENIED
    terrain = c.frame in TERRAIN_ALT_FRAMES
    target = terrain_target_ned(s, c) if terrain else target_ned(s, c)
    # ArduCopter: GUIDED cannot take the destination yet, or it lies beyond the fence (checked
    # before any mode change: measured, FAILED from AUTO and the mode kept); in a terrain frame,
    # no terrain under the vehicle (set_destination fails: FAILED)
    if target is None or (terrain and v.terrain_offset_m() is None):
        return Result.FAILED
    if not terrain and not v.destination_within_fence(*target):
        return Result.FAILED
    if v.mode.number != ModeNumber.GUIDED and v.set_mode(ModeNumber.GUIDED) != Result.ACCEPTED:
        return Result.FAILED
    if math.isfinite(c.p1) and c.p1 > 0:
        v.set_speed(c.p1)
    yaw = math.radians(c.p4) if math.isfinite(c.p4) else None
    result = v.guided_goto(*target, yaw=yaw, terrain=terrain)
    return Result.FAILED if terrain and result != Result.ACCEPTED else result


def do_set_home(s, c: Command) -> Result:
    """As ArduPilot: param 1 = 1 (or latitude and longitude 0) is here, once the EKF has an
    origin; any other param 1 but 0 FAILED; a point that is no location DENIED. A COMMAND_LONG's
    altitude is above sea level (ArduPilot converts it in MAV_FRAME_GLOBAL)."""
    v = s.vehicle
    if c.p1 == 1 or (c.p5 == 0 and c.p6 == 0):
        return _home_told(s, v.set_home(None))
    if c.p1 != 0:  # NaN included
        return Result.FAILED
    if not c.is_int:
        c = c._replace(frame=mav.MAV_FRAME_GLOBAL)
    if not is_location(s, c):
        return Result.DENIED
    target = target_ned(s, c)
    return Result.FAILED if target is None else _home_told(s, v.set_home(target))


def do_set_global_origin(s, c: Command) -> Result:
    """As ArduPilot's set_ekf_origin: a point that is no location (or 0, 0) DENIED; FAILED once the
    EKF has an origin; else the origin, and GPS_GLOBAL_ORIGIN and HOME_POSITION with it, as for the
    SET_GPS_GLOBAL_ORIGIN message (external_nav_messages.py)."""
    if not c.is_int:
        c = c._replace(frame=mav.MAV_FRAME_GLOBAL)
    if not is_location(s, c) or (c.p5 == 0 and c.p6 == 0):
        return Result.DENIED
    if not s.vehicle.set_gps_global_origin(c.p5, c.p6, c.p7):
        return Result.FAILED
    origin_taken(s)
    return Result.ACCEPTED


def _home_told(s, result: Result) -> Result:
    """A home set (or asked for) is followed, as on ArduCopter, by HOME_POSITION and the EKF
    origin (GPS_GLOBAL_ORIGIN)."""
    if result == Result.ACCEPTED:
        s.queue(s.build(mav.MAVLINK_MSG_ID_HOME_POSITION))
        s.queue(s.build(mav.MAVLINK_MSG_ID_GPS_GLOBAL_ORIGIN))
    return result


def get_home_position(s, c: Command) -> Result:
    if s.vehicle.home_ned is None:
        return Result.FAILED
    return _home_told(s, Result.ACCEPTED)


def loiter_unlimited(s, c: Command) -> Result:
    """As ArduCopter: LOITER, in any state, or FAILED where LOITER cannot be entered."""
    return Result.ACCEPTED if s.vehicle.set_mode(ModeNumber.LOITER) == Result.ACCEPTED else Result.FAILED


def flight_termination(s, c: Command) -> Result:
    """As ArduCopter (no advanced failsafe configured): param 1 above 0.5 stops the motors at
    once, in flight too, and is ACCEPTED also when already disarmed; anything else FAILED."""
    if not c.p1 > 0.5:  # NaN included
        return Result.FAILED
    s.vehicle.disarm("termination", force=True)
    return Result.ACCEPTED


def run_prearm_checks(s, c: Command) -> Result:
    """As ArduCopter: TEMPORARILY_REJECTED while armed; otherwise every failing pre-arm check is
    said ("PreArm: ...") and the command ACCEPTED, whatever the checks found. The pre-arm checks
    only (AP_Arming::pre_arm_checks): the ARM's own, such as leaning, are not run."""
    v = s.vehicle
    if v.armed:
        return Result.TEMPORARILY_REJECTED
    failures = prearm_failures(v, REPORTED_CHECKS)
    for reason in failures:
        v.notify(f"PreArm: {reason}", Severity.CRITICAL)
    v.prearm_checked(failures)
    return Result.ACCEPTED


def adsb_out_ident(s, c: Command) -> Result:
    """As AP_ADSB::ident_start: with the ADS-B list running (ADSB_TYPE), "ADSB: IDENT!"."""
    if not s.vehicle.traffic.available():
        return Result.FAILED
    s.vehicle.notify("ADSB: IDENT!", Severity.INFO)
    return Result.ACCEPTED


def request_autopilot_capabilities(s, c: Command) -> Result:
    if c.p1 != 1:  # as ArduCopter: only "1: request autopilot version" is asked for
        return Result.FAILED
    s.queue(s.build(mav.MAVLINK_MSG_ID_AUTOPILOT_VERSION))
    return Result.ACCEPTED


def request_message(s, c: Command) -> Result:
    msg_id = _int_param(c.p1, 0, 2**24)
    if msg_id is None:
        return Result.DENIED
    msg = s.build(msg_id)
    if msg is None:
        return Result.ACCEPTED if msg_id in ACCEPTED_UNSENT else Result.FAILED
    s.queue(msg)
    return Result.ACCEPTED


def set_message_interval(s, c: Command) -> Result:
    msg_id = _int_param(c.p1, 0, 2**24)
    if msg_id is None or not math.isfinite(c.p2):
        return Result.DENIED
    return Result.ACCEPTED if s.streams.set_interval_us(msg_id, c.p2) else Result.FAILED


def get_message_interval(s, c: Command) -> Result:
    msg_id = _int_param(c.p1, 0, 65535)  # MESSAGE_INTERVAL's message_id is 16 bits
    if msg_id is None:
        return Result.DENIED
    interval = s.streams.interval_s(msg_id)
    interval_us = -1 if interval == math.inf else min(round(interval * 1e6), INT32_MAX)  # an int32 field
    s.queue(s.codec.message_interval_encode(msg_id, interval_us))
    return Result.ACCEPTED


def condition_yaw(s, c: Command) -> Result:
    """As ArduCopter: an angle of 0-360 degrees, absolute (param 4 = 0) or relative (1), else
    FAILED; any rate (not above 0, NaN too: the default slew) and direction (param 3 as a signed
    byte: below 0 counter-clockwise, 0 the shorter way, above 0 clockwise)."""
    if not (0 <= c.p1 <= 360 and c.p4 in (0, 1)):  # NaN fails too
        return Result.FAILED
    direction = ((as_uint16(c.p3) & 0xFF) ^ 0x80) - 0x80  # (int8_t)
    return s.vehicle.set_yaw(c.p1, relative=c.p4 == 1, direction=direction, rate_deg_s=c.p2)


def do_follow(s, c: Command) -> Result:
    """FOLLOW's lead is system param 1 (1..255, as a byte), else DENIED; as ArduPilot, the
    follow library's FOLL_SYSID is set (Firefly saves it, where ArduPilot sets it unsaved)."""
    if not 0 < c.p1 <= 255:  # NaN too
        return Result.DENIED
    s.vehicle.params.set("FOLL_SYSID", int(c.p1))
    return Result.ACCEPTED


def mission_start(s, c: Command) -> Result:
    return s.vehicle.mission_start()


def battery_reset(s, c: Command) -> Result:
    """Param 1 the batteries (a mask; bit 0 the one SITL has), param 2 the percentage left: the
    monitor counts from there (measured: ACCEPTED armed, disarmed and flying; 10 % then reads
    10 %). Bits of batteries the vehicle lacks are passed over, as AP_BattMonitor does; a NaN
    percentage is ArduPilot's constrain of a NaN: 50 %, and its internal error."""
    if as_uint16(c.p1) & 1:
        percentage = c.p2
        if math.isnan(percentage):
            s.vehicle.constraining_nan()
            percentage = 50.0
        s.vehicle.estimate.reset_battery(percentage)
    return Result.ACCEPTED


def set_ekf_source_set(s, c: Command) -> Result:
    """Source sets 1 to 3 (param 1 cut to a whole number, as ArduPilot's uint32_t cast), else DENIED."""
    if not (math.isfinite(c.p1) and 1 <= int(c.p1) <= 3):
        return Result.DENIED
    s.vehicle.use_source_set(int(c.p1))
    return Result.ACCEPTED


def external_position_estimate(s, c: Command) -> Result:
    """A client's horizontal position for a dead-reckoning EKF: x, y; param 2 the seconds it took
    to work out, param 3 its accuracy [m]; param 1 the sender's time, which ArduPilot's link lag
    correction makes "now" for a sender whose clock keeps time (measured: 100 s ahead, 3 s behind,
    NaN and inf moved nothing).
    As ArduCopter: COMMAND_INT only (COMMAND_LONG UNSUPPORTED); DENIED in a frame other than
    GLOBAL or GLOBAL_INT or with an altitude (z not NaN); FAILED where the estimate will not take
    one (vehicle.take_position_estimate). The processing time is ArduPilot's: milliseconds as a
    uint32_t, taken off the time stamp only when less than it, and no more than 5 s old."""
    if not c.is_int:
        return Result.UNSUPPORTED
    if c.frame not in (mav.MAV_FRAME_GLOBAL, mav.MAV_FRAME_GLOBAL_INT) or not math.isnan(c.p7):
        return Result.DENIED
    v = s.vehicle
    processing_ms = as_uint32(c.p2 * 1e3)
    age_ms = processing_ms if processing_ms < int(v.time_s * 1e3) else 0
    return v.take_position_estimate(c.p5, c.p6, min(age_ms / 1e3, TOLD_DELAY_MAX_S), c.p3)


HANDLERS = {
    mav.MAV_CMD_COMPONENT_ARM_DISARM: arm_disarm,
    mav.MAV_CMD_BATTERY_RESET: battery_reset,
    mav.MAV_CMD_SET_EKF_SOURCE_SET: set_ekf_source_set,
    mav.MAV_CMD_EXTERNAL_POSITION_ESTIMATE: external_position_estimate,
    mav.MAV_CMD_NAV_TAKEOFF: takeoff,
    mav.MAV_CMD_NAV_LAND: land,
    mav.MAV_CMD_NAV_RETURN_TO_LAUNCH: return_to_launch,
    mav.MAV_CMD_DO_SET_MODE: do_set_mode,
    mav.MAV_CMD_DO_LAND_START: do_land_start,
    mav.MAV_CMD_DO_RETURN_PATH_START: do_return_path_start,
    mav.MAV_CMD_DO_CHANGE_SPEED: do_change_speed,
    mav.MAV_CMD_DO_REPOSITION: do_reposition,
    mav.MAV_CMD_DO_SET_HOME: do_set_home,
    MAV_CMD_DO_SET_GLOBAL_ORIGIN: do_set_global_origin,
    mav.MAV_CMD_GET_HOME_POSITION: get_home_position,
    mav.MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES: request_autopilot_capabilities,
    mav.MAV_CMD_REQUEST_MESSAGE: request_message,
    mav.MAV_CMD_SET_MESSAGE_INTERVAL: set_message_interval,
    mav.MAV_CMD_GET_MESSAGE_INTERVAL: get_message_interval,
    mav.MAV_CMD_CONDITION_YAW: condition_yaw,
    mav.MAV_CMD_MISSION_START: mission_start,
    mav.MAV_CMD_DO_FOLLOW: do_follow,
    mav.MAV_CMD_DO_PAUSE_CONTINUE: do_pause_continue,
    mav.MAV_CMD_DO_AUX_FUNCTION: do_aux_function,
    mav.MAV_CMD_DO_SET_SERVO: do_set_servo,
    mav.MAV_CMD_DO_REPEAT_SERVO: do_repeat_servo,
    mav.MAV_CMD_DO_SET_RELAY: do_set_relay,
    mav.MAV_CMD_DO_REPEAT_RELAY: do_repeat_relay,
    mav.MAV_CMD_NAV_LOITER_UNLIM: loiter_unlimited,
    mav.MAV_CMD_DO_FLIGHTTERMINATION: flight_termination,
    mav.MAV_CMD_RUN_PREARM_CHECKS: run_prearm_checks,
    # A multicopter flies the VTOL takeoff and landing as the plain ones (ArduCopter does too).
    mav.MAV_CMD_NAV_VTOL_TAKEOFF: takeoff,
    mav.MAV_CMD_NAV_VTOL_LAND: land,
    **PREFLIGHT_HANDLERS,  # reboot, storage, calibrations, banner (preflight.py)
    **DO_ITEM_HANDLERS,  # fence switch, mission current and tags, ROI (do_item_commands.py)
    **CAMERA_HANDLERS,  # CAM1: pictures, intervals, distance triggering, zoom, focus (camera_commands.py)
    **PAYLOAD_HANDLERS,  # parachute, sprayer, gripper, winch, motor test (payload_commands.py)
    **HOUSEKEEPING_HANDLERS,  # link, board and calibration odds and ends (housekeeping_commands.py)
    **MOUNT_HANDLERS,  # MNT1: the gimbal's commands, DO_SET_ROI_SYSID (mount_commands.py)
    mav.MAV_CMD_DO_ADSB_OUT_IDENT: adsb_out_ident,
}


# Queries answer with fresh data every time; everything else replays its result on a retry.
QUERIES = {mav.MAV_CMD_GET_HOME_POSITION, mav.MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES, mav.MAV_CMD_RUN_PREARM_CHECKS,
           mav.MAV_CMD_DO_SEND_BANNER,
           mav.MAV_CMD_REQUEST_MESSAGE, mav.MAV_CMD_SET_MESSAGE_INTERVAL,
           mav.MAV_CMD_GET_MESSAGE_INTERVAL}


_PARAMS = struct.Struct("<7d")


def retry_key(c: Command) -> tuple:
    """What makes a command the same command again: sender, id, frame and the parameters' bits
    (so a retry carrying NaN matches its original, which NaN's own == never does)."""
    return (c.src, c.command, c.frame, c.is_int,
            _PARAMS.pack(c.p1, c.p2, c.p3, c.p4, c.p5, c.p6, c.p7))


class CommandService:
    """Runs each command once: a retry of the last command is answered with its result. A retry
    is the same command (retry_key) sent again with confirmation > 0 (MAVSDK and QGroundControl
    count their resends there), whatever the speedup; or, with confirmation 0, within
    RETRY_WINDOW_S of both the link clock (the wall time a client's retry timer runs in) and sim
    time. ArduCopter runs every command it receives; a deliberate repeat, seconds of vehicle time
    later, is run again here too (at speedup 20 a script's repeat 0.1 s of wall time later is 2 s
    of flight). Every command gets its COMMAND_ACK, also when its handler fails."""

    def __init__(self):
        self._last: tuple | None = None  # (key, result, sim time, link time)

    def _is_retry(self, c: Command, key: tuple, now_s: float, link_s: float) -> bool:
        last = self._last
        if c.command in QUERIES or last is None or last[0] != key:
            return False
        return c.confirmation > 0 or (now_s - last[2] <= RETRY_WINDOW_S and link_s - last[3] <= RETRY_WINDOW_S)

    def handle(self, session, c: Command, now_s: float, link_s: float):
        key = retry_key(c)
        last = self._last
        if last is not None and self._is_retry(c, key, now_s, link_s):
            result = last[1]
        else:
            handler = HANDLERS.get(c.command)
            try:
                result = Result.UNSUPPORTED if handler is None else handler(session, c)
            except Exception as exc:  # noqa: BLE001 - a bug: counted, and the command still answered
                session.handler_failed(f"command {c.command}", exc)
                result = Result.FAILED
            self._last = (key, result, now_s, link_s)
        return session.codec.command_ack_encode(c.command, int(result), 0, 0, c.src[0], c.src[1])

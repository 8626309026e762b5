"""The camera mount (AP_Mount), a servo gimbal (MNT1_TYPE 1) as ArduCopter SITL runs it: its
commands' answers, the GIMBAL_* messages, the attitude it reports and the PWMs it puts out.

no_mount      MNT1_TYPE 0: each mount and gimbal command's answer, the ROI commands', and
              REQUEST_MESSAGE for the GIMBAL_* messages (answer, replies).
servo         MNT1_TYPE 1 with tilt on output 9 (SERVOn_FUNCTION 7), pan on 10 (6), roll on 11 (8),
              all set at power-on (MNT1_TYPE is read at boot): the attitude at boot (the default
              mode, RC targeting with no RC input: the middle of each range), GIMBAL_MANAGER_INFORMATION
              and _STATUS, the GIMBAL_DEVICE_ATTITUDE_STATUS stream's rate; then each command and
              message in turn, good and bad: its answer, the reported attitude (roll, pitch, yaw
              [deg]) and flags half a second later, the three outputs' PWMs; how soon it gets
              there (the first attitude sent after a 45 degree move); a pitch rate held for a
              second; DO_SET_ROI_SYSID with another system's GLOBAL_POSITION_INT heard; who
              controls the gimbal (DO_GIMBAL_MANAGER_CONFIGURE) and the GIMBAL_MANAGER_STATUS it
              volunteers.
roi_flying    the servo gimbal, hovering in GUIDED at 10 m facing north: DO_SET_ROI_LOCATION 40 m
              east of home on the ground (the gimbal pans to it; does the vehicle turn?), the
              gimbal's attitude and the vehicle's heading after 6 s; DO_SET_ROI_NONE; DO_MOUNT_CONTROL
              yaw 60 (does the vehicle turn?).
tilt_only     tilt alone (output 9), no pan: the same ROI and DO_MOUNT_CONTROL in flight, where
              ArduCopter turns the vehicle instead.
mission       the servo gimbal in AUTO, legs north at 10 m: DO_MOUNT_CONTROL, DO_GIMBAL_MANAGER_PITCHYAW,
              DO_SET_ROI_LOCATION (a point 30 m east on the ground) and DO_SET_ROI_NONE before each leg:
              the gimbal's pitch and yaw, its flags and the vehicle's heading hovering at the end of
              each leg; then GUIDED (leaving AUTO puts the gimbal back in its default mode).
tilt_mission  tilt alone in AUTO: DO_MOUNT_CONTROL with yaw 90 (ArduCopter turns the vehicle by it,
              and the waypoint that starts next takes the heading back: measured, no turn) and
              DO_SET_ROI_LOCATION (the vehicle faces it, the gimbal tilts to it): heading and pitch
              hovering at the end of each leg.
rc_targeting  the servo gimbal with channel 9 its pitch (RCn_OPTION 213) and 10 its yaw (214), moved
              by RC_CHANNELS_OVERRIDE: the attitude at the receiver's own PWMs and at 1800 / 1200;
              DO_MOUNT_CONTROL held while the sticks stay, given back to RC targeting once one
              moves; MNT1_RC_RATE 30: the pitch rate at 1800.
"""
from __future__ import annotations

import math

from ..client import Client, mav
from ..facts import Tol, Trace
from ..targets import run_each
from .missions import upload
from .states import GUIDED, reach_flying
from .surface_mission import Geometry, item

AREA = "mount"
TILT, PAN, ROLL = 9, 10, 11  # the outputs
SERVO_BOOT = {"MNT1_TYPE": 1, f"SERVO{TILT}_FUNCTION": 7, f"SERVO{PAN}_FUNCTION": 6, f"SERVO{ROLL}_FUNCTION": 8}
TILT_BOOT = {"MNT1_TYPE": 1, f"SERVO{TILT}_FUNCTION": 7}
# MAVLink 2 messages the client's dialect module does not name
MSG_MANAGER_INFORMATION, MSG_MANAGER_STATUS, MSG_DEVICE_INFORMATION = 280, 281, 283
MSG_DEVICE_ATTITUDE_STATUS, MSG_AUTOPILOT_STATE_FOR_GIMBAL, MSG_MOUNT_STATUS = 285, 286, 158
CMD_PITCHYAW, CMD_MANAGER_CONFIGURE = 1000, 1001  # MAV_CMD_DO_GIMBAL_MANAGER_PITCHYAW, _CONFIGURE
FLAG_RETRACT, FLAG_NEUTRAL, FLAG_YAW_LOCK = 1, 2, 16  # GIMBAL_MANAGER_FLAGS
NAN = float("nan")
HOME_LAT, HOME_LON, HOME_ALT_M = -35.363261, 149.165230, 584.0  # targets.HOME
OTHER_SYSID = 9  # another vehicle the gimbal is pointed at
ANGLE = Tol(abs=2.0, why="the servo gimbal takes the vehicle's lean off roll and pitch (on the ground each "
                         "airframe sits within a few tenths of a degree of level), and an earth-frame yaw is "
                         "reported in the body frame: ArduCopter's SITL sits at 358-2 degrees, Firefly's at 0")
PWM = Tol(abs=8, why="the lean the servo gimbal takes off: a degree of tilt is 7 us over its 110 degrees; a "
                     "degree of pan 2.2 us")
HEADING = Tol(abs=4.0, why="the hover's heading hold")
ROI_ANGLE = Tol(abs=3.0, why="a point 40 m off seen from a hover held within a metre and half a degree")


def _euler_deg(q) -> list[float]:
    w, x, y, z = q
    roll = math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2 * (w * y - z * x))))
    yaw = math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    out = [round(math.degrees(a), 1) for a in (roll, pitch, yaw)]
    out[2] = (out[2] + 180.0) % 360.0 - 180.0  # 180 and -180 are one yaw: -180
    return out


def _request(c: Client, msg_id: int) -> tuple[int | None, list]:
    replies: list = []

    def take(msg) -> None:
        if msg.get_msgId() == msg_id:
            replies.append(msg)
    with c.listening(take):
        result = c.command(mav.MAV_CMD_REQUEST_MESSAGE, msg_id)
        c.idle(0.3)
    return result, replies


def _gimbal(c: Client, trace: Trace, name: str, settle_s: float = 0.5, home: bool = False) -> None:
    """The attitude and flags reported, and the outputs, `settle_s` from now. Looking at home
    from on top of it (home: True), the pan follows centimetres of GPS drift: left out."""
    c.idle(settle_s)
    c.fresh("GIMBAL_DEVICE_ATTITUDE_STATUS")
    c.fresh("SERVO_OUTPUT_RAW")
    status = c.last["GIMBAL_DEVICE_ATTITUDE_STATUS"]
    trace.fact(f"{name}.attitude", _euler_deg(status.q)[:2 if home else 3], ANGLE)
    trace.fact(f"{name}.flags", status.flags)
    out = c.last["SERVO_OUTPUT_RAW"]
    trace.fact(f"{name}.pwm", [getattr(out, f"servo{n}_raw") for n in ((TILT, ROLL) if home else (TILT, PAN, ROLL))],
               PWM)


def _step(c: Client, trace: Trace, name: str, command: int, *params: float, home: bool = False) -> None:
    trace.fact(f"{name}.result", c.command(command, *params))
    _gimbal(c, trace, name, home=home)


COMMANDS = (  # (name, command, params) sent to a vehicle with no mount
    ("mount_control", mav.MAV_CMD_DO_MOUNT_CONTROL, (-30, 0, 20, 0, 0, 0, 2)),
    ("mount_configure", mav.MAV_CMD_DO_MOUNT_CONFIGURE, (2,)),
    ("pitchyaw", CMD_PITCHYAW, (-30, 20, NAN, NAN, 0, 0, 0)),
    ("manager_configure", CMD_MANAGER_CONFIGURE, (-2, -2)),
    ("roi_sysid", mav.MAV_CMD_DO_SET_ROI_SYSID, (5,)),
    ("roi_location", mav.MAV_CMD_DO_SET_ROI_LOCATION, (0, 0, 0, 0, -35.363, 149.166, 0)),
    ("roi_none", mav.MAV_CMD_DO_SET_ROI_NONE, ()),
)
REQUESTS = (("manager_information", MSG_MANAGER_INFORMATION), ("manager_status", MSG_MANAGER_STATUS),
            ("device_information", MSG_DEVICE_INFORMATION), ("device_attitude_status", MSG_DEVICE_ATTITUDE_STATUS))


def no_mount(c: Client, trace: Trace) -> None:
    for name, command, params in COMMANDS:
        trace.fact(f"{name}.result", c.command(command, *params))
    for name, msg_id in REQUESTS + (("autopilot_state_for_gimbal", MSG_AUTOPILOT_STATE_FOR_GIMBAL),):
        result, replies = _request(c, msg_id)
        trace.fact(f"request.{name}", [result, len(replies) > 0])
    c.idle(1.0)
    trace.fact("attitude_status_streamed", c.received.get("GIMBAL_DEVICE_ATTITUDE_STATUS", 0))


def servo(c: Client, trace: Trace) -> None:
    c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_SERVO_OUTPUT_RAW, 100_000)
    _gimbal(c, trace, "boot", settle_s=0.1)
    status = c.last["GIMBAL_DEVICE_ATTITUDE_STATUS"]
    trace.fact("boot.device", [status.gimbal_device_id, status.failure_flags, status.target_system,
                               status.target_component, math.isnan(status.angular_velocity_x)])
    # the stream: GIMBAL_DEVICE_ATTITUDE_STATUS in EXTRA3, asked for at 10 Hz with the rest
    start, seen = c.now_ms, c.received.get("GIMBAL_DEVICE_ATTITUDE_STATUS", 0)
    c.idle(3.0)
    trace.fact("stream_hz", (c.received.get("GIMBAL_DEVICE_ATTITUDE_STATUS", 0) - seen) * 1000.0 / (c.now_ms - start),
               Tol(abs=1.5, why="ten a second counted over three seconds of a loaded client"))
    result, replies = _request(c, MSG_MANAGER_INFORMATION)
    info = replies[0] if replies else None
    trace.fact("manager_information", [result, len(replies)] + ([] if info is None else [
        info.cap_flags, info.gimbal_device_id,
        *(round(math.degrees(getattr(info, f)), 1) for f in ("roll_min", "roll_max", "pitch_min", "pitch_max",
                                                             "yaw_min", "yaw_max"))]))
    _manager_status(c, trace, "manager_status")
    for name, msg_id in (("device_information", MSG_DEVICE_INFORMATION), ("mount_status", MSG_MOUNT_STATUS),
                         ("device_attitude_status", MSG_DEVICE_ATTITUDE_STATUS),
                         ("autopilot_state_for_gimbal", MSG_AUTOPILOT_STATE_FOR_GIMBAL)):
        result, replies = _request(c, msg_id)
        trace.fact(f"request.{name}", [result, len(replies) > 0])  # (the attitude is streamed too)
    # DO_MOUNT_CONTROL: param 7 the mode; 2 (MAVLink targeting) pitch, roll, yaw in params 1-3
    _step(c, trace, "control_angles", mav.MAV_CMD_DO_MOUNT_CONTROL, -30, 10, 45, 0, 0, 0, 2)
    _step(c, trace, "control_beyond_limits", mav.MAV_CMD_DO_MOUNT_CONTROL, 40, -50, -200, 0, 0, 0, 2)
    _step(c, trace, "control_centidegrees", mav.MAV_CMD_DO_MOUNT_CONTROL, -3000, 0, 0, 0, 0, 0, 2)
    _step(c, trace, "control_nan_angle", mav.MAV_CMD_DO_MOUNT_CONTROL, NAN, 0, 0, 0, 0, 0, 2)
    _step(c, trace, "control_retract", mav.MAV_CMD_DO_MOUNT_CONTROL, 0, 0, 0, 0, 0, 0, 0)
    _step(c, trace, "control_neutral", mav.MAV_CMD_DO_MOUNT_CONTROL, 0, 0, 0, 0, 0, 0, 1)
    _step(c, trace, "control_rc", mav.MAV_CMD_DO_MOUNT_CONTROL, 0, 0, 0, 0, 0, 0, 3)
    _step(c, trace, "control_sysid", mav.MAV_CMD_DO_MOUNT_CONTROL, 0, 0, 0, 0, 0, 0, 5)
    _step(c, trace, "control_home", mav.MAV_CMD_DO_MOUNT_CONTROL, 0, 0, 0, 0, 0, 0, 6, home=True)
    _step(c, trace, "control_gps_in_p1p2", mav.MAV_CMD_DO_MOUNT_CONTROL, -35.36, 149.16, 0, 0, 0, 0, 4, home=True)
    _step(c, trace, "control_mode_7", mav.MAV_CMD_DO_MOUNT_CONTROL, 0, 0, 0, 0, 0, 0, 7, home=True)
    _step(c, trace, "control_mode_9", mav.MAV_CMD_DO_MOUNT_CONTROL, 0, 0, 0, 0, 0, 0, 9, home=True)
    _step(c, trace, "control_mode_nan", mav.MAV_CMD_DO_MOUNT_CONTROL, 0, 0, 0, 0, 0, 0, NAN)
    # DO_MOUNT_CONFIGURE: param 1 the mode
    _step(c, trace, "configure_neutral", mav.MAV_CMD_DO_MOUNT_CONFIGURE, 1)
    _step(c, trace, "configure_mavlink", mav.MAV_CMD_DO_MOUNT_CONFIGURE, 2)
    _step(c, trace, "configure_home", mav.MAV_CMD_DO_MOUNT_CONFIGURE, 6, home=True)
    _step(c, trace, "configure_mode_7", mav.MAV_CMD_DO_MOUNT_CONFIGURE, 7, home=True)
    _step(c, trace, "configure_nan", mav.MAV_CMD_DO_MOUNT_CONFIGURE, NAN)
    _step(c, trace, "configure_rc", mav.MAV_CMD_DO_MOUNT_CONFIGURE, 3)
    # DO_GIMBAL_MANAGER_PITCHYAW: pitch, yaw [deg], pitch rate, yaw rate [deg/s], flags (p5), device (p7)
    _step(c, trace, "pitchyaw_angles", CMD_PITCHYAW, -45, 30, NAN, NAN, 0, 0, 0)
    _step(c, trace, "pitchyaw_yaw_lock", CMD_PITCHYAW, -20, 90, NAN, NAN, FLAG_YAW_LOCK, 0, 0)
    _step(c, trace, "pitchyaw_device1", CMD_PITCHYAW, -10, -30, NAN, NAN, 0, 0, 1)
    _step(c, trace, "pitchyaw_device2", CMD_PITCHYAW, -60, 0, NAN, NAN, 0, 0, 2)
    _step(c, trace, "pitchyaw_beyond_limits", CMD_PITCHYAW, 60, 270, NAN, NAN, 0, 0, 0)
    _step(c, trace, "pitchyaw_retract", CMD_PITCHYAW, -45, 30, NAN, NAN, FLAG_RETRACT, 0, 0)
    _step(c, trace, "pitchyaw_neutral", CMD_PITCHYAW, -45, 30, NAN, NAN, FLAG_NEUTRAL, 0, 0)
    _step(c, trace, "pitchyaw_half", CMD_PITCHYAW, -45, NAN, NAN, NAN, 0, 0, 0)
    _step(c, trace, "pitchyaw_all_nan", CMD_PITCHYAW, NAN, NAN, NAN, NAN, FLAG_YAW_LOCK, 0, 0)
    _step(c, trace, "pitchyaw_zero", CMD_PITCHYAW, 0, 0, NAN, NAN, 0, 0, 0)
    # instant or slewed: the first attitude sent at least 60 ms after a command from -45 to 0 pitch
    _step(c, trace, "slew_from", CMD_PITCHYAW, -45, 0, NAN, NAN, 0, 0, 0)
    c.command(CMD_PITCHYAW, 0, 0, NAN, NAN, 0, 0, 0)
    asked = c.now_ms
    c.wait(lambda: c.last["GIMBAL_DEVICE_ATTITUDE_STATUS"].time_boot_ms >= asked + 60, 2.0, what="an attitude after")
    trace.fact("slew.first_pitch", _euler_deg(c.last["GIMBAL_DEVICE_ATTITUDE_STATUS"].q)[1], ANGLE)
    # a rate: pitch 10 deg/s down for a second, then held
    trace.fact("rate.result", c.command(CMD_PITCHYAW, NAN, NAN, -10, 0, 0, 0, 0))
    c.fresh("GIMBAL_DEVICE_ATTITUDE_STATUS")
    t0, p0 = c.now_ms, _euler_deg(c.last["GIMBAL_DEVICE_ATTITUDE_STATUS"].q)[1]
    c.idle(1.0)
    c.fresh("GIMBAL_DEVICE_ATTITUDE_STATUS")
    t1, p1 = c.now_ms, _euler_deg(c.last["GIMBAL_DEVICE_ATTITUDE_STATUS"].q)[1]
    trace.fact("rate.deg_s", (p1 - p0) * 1000.0 / max(t1 - t0, 1), Tol(abs=1.5, why="a rate read off two 10 Hz "
                                                                                 "samples a second apart"))
    trace.fact("rate.stop_result", c.command(CMD_PITCHYAW, NAN, NAN, 0, 0, 0, 0, 0))
    c.fresh("GIMBAL_DEVICE_ATTITUDE_STATUS")
    held = _euler_deg(c.last["GIMBAL_DEVICE_ATTITUDE_STATUS"].q)
    c.idle(1.0)
    c.fresh("GIMBAL_DEVICE_ATTITUDE_STATUS")
    trace.fact("rate.held", abs(_euler_deg(c.last["GIMBAL_DEVICE_ATTITUDE_STATUS"].q)[1] - held[1]) < 0.3)
    trace.fact("rate.held_flags", c.last["GIMBAL_DEVICE_ATTITUDE_STATUS"].flags)
    # the manager's messages: GIMBAL_MANAGER_SET_PITCHYAW [rad] and GIMBAL_MANAGER_SET_ATTITUDE
    c.conn.mav.gimbal_manager_set_pitchyaw_send(1, 1, 0, 0, math.radians(-20), math.radians(-40), NAN, NAN)
    _gimbal(c, trace, "set_pitchyaw")
    c.conn.mav.gimbal_manager_set_pitchyaw_send(1, 1, FLAG_YAW_LOCK, 3, math.radians(-70), 0, NAN, NAN)
    _gimbal(c, trace, "set_pitchyaw_device3")
    c.conn.mav.gimbal_manager_set_pitchyaw_send(1, 1, FLAG_NEUTRAL, 0, NAN, NAN, NAN, NAN)
    _gimbal(c, trace, "set_pitchyaw_neutral")
    half = math.radians(25) / 2  # pitch -25 deg, yaw 0: q of a rotation about y
    c.conn.mav.gimbal_manager_set_attitude_send(1, 1, 0, 0, [math.cos(half), 0, -math.sin(half), 0], NAN, NAN, NAN)
    _gimbal(c, trace, "set_attitude")
    c.conn.mav.gimbal_manager_set_attitude_send(1, 1, 0, 0, [NAN, NAN, NAN, NAN], NAN, NAN, NAN)
    _gimbal(c, trace, "set_attitude_nan")
    c.conn.mav.gimbal_manager_set_attitude_send(1, 1, FLAG_RETRACT, 0, [1, 0, 0, 0], NAN, NAN, NAN)
    _gimbal(c, trace, "set_attitude_retract")
    # ROI commands as they move the gimbal (on the ground, facing north)
    _step(c, trace, "roi_location", mav.MAV_CMD_DO_SET_ROI_LOCATION, 0, 0, 0, 0, -35.363261, 149.165230 + 0.0004, 0)
    _step(c, trace, "roi_none", mav.MAV_CMD_DO_SET_ROI_NONE)
    _step(c, trace, "roi_sysid", mav.MAV_CMD_DO_SET_ROI_SYSID, 7)
    _step(c, trace, "roi_sysid_nan", mav.MAV_CMD_DO_SET_ROI_SYSID, NAN)
    # another system's GLOBAL_POSITION_INT, 30 m east of home and 10 m above it: pointed at once it is the one
    other = mav.MAVLink(c.conn, srcSystem=OTHER_SYSID, srcComponent=1)
    lat, lon = round(HOME_LAT * 1e7), round((HOME_LON + 30.0 / (111319.49 * math.cos(math.radians(HOME_LAT)))) * 1e7)

    def tell_position() -> None:
        other.global_position_int_send(c.now_ms, lat, lon, round((HOME_ALT_M + 10.0) * 1000), 10_000, 0, 0, 0, 0)
    tell_position()
    _gimbal(c, trace, "other_system_unnamed")
    trace.fact("roi_sysid_other.result", c.command(mav.MAV_CMD_DO_SET_ROI_SYSID, OTHER_SYSID))
    tell_position()
    _gimbal(c, trace, "roi_sysid_other")
    # who controls the gimbal: param 1 / 2 the system / component (-2 the sender, -3 the sender leaves)
    _manager_configure(c, trace, "manager_self", -2, -2, 0)
    _manager_configure(c, trace, "manager_other", 5, 6, 0)
    _manager_configure(c, trace, "manager_leave_not_in", -3, -3, 0)
    _manager_configure(c, trace, "manager_same", 5, 6, 0)
    _manager_configure(c, trace, "manager_keep", -1, -1, 0)
    _manager_configure(c, trace, "manager_beyond", 300, 1, 0)
    _manager_configure(c, trace, "manager_below", -4, 1, 0)
    _manager_configure(c, trace, "manager_device2", -2, -2, 2)
    _manager_configure(c, trace, "manager_self_again", -2, -2, 1)
    _manager_configure(c, trace, "manager_leave", -3, -3, 0)
    _manager_configure(c, trace, "manager_nan", NAN, NAN, 0)


def _manager_status(c: Client, trace: Trace, name: str) -> None:
    result, replies = _request(c, MSG_MANAGER_STATUS)
    s = replies[0] if replies else None
    trace.fact(name, [result, len(replies)] + ([] if s is None else [
        s.flags, s.gimbal_device_id, s.primary_control_sysid, s.primary_control_compid,
        s.secondary_control_sysid, s.secondary_control_compid]))


def _manager_configure(c: Client, trace: Trace, name: str, sysid: float, compid: float, device: float) -> None:
    volunteered: list = []

    def take(msg) -> None:
        if msg.get_msgId() == MSG_MANAGER_STATUS:
            volunteered.append(msg)
    with c.listening(take):
        trace.fact(f"{name}.result", c.command(CMD_MANAGER_CONFIGURE, sysid, compid, 0, 0, 0, 0, device))
        c.idle(0.3)
    trace.fact(f"{name}.status_sent", len(volunteered))
    _manager_status(c, trace, f"{name}.status")


def _heading_deg(c: Client) -> float:
    """-180..180: north is 0 whichever side of it the heading holds."""
    return (math.degrees(c.last["ATTITUDE"].yaw) + 180.0) % 360.0 - 180.0


def _flying(c: Client, trace: Trace, pan: bool) -> None:
    c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_SERVO_OUTPUT_RAW, 100_000)
    reach_flying(c, 10.0)
    c.idle(2.0)
    trace.fact("start_heading", _heading_deg(c), HEADING)
    east = 149.165230 + 40.0 / (111319.49 * math.cos(math.radians(35.363261)))
    trace.fact("roi.result", c.command(mav.MAV_CMD_DO_SET_ROI_LOCATION, 0, 0, 0, 0, -35.363261, east, 0))
    c.idle(6.0)
    c.fresh("GIMBAL_DEVICE_ATTITUDE_STATUS")
    status = c.last["GIMBAL_DEVICE_ATTITUDE_STATUS"]
    trace.fact("roi.attitude", _euler_deg(status.q)[1:], ROI_ANGLE)
    trace.fact("roi.flags", status.flags)
    trace.fact("roi.heading", _heading_deg(c), HEADING)
    trace.fact("roi_none.result", c.command(mav.MAV_CMD_DO_SET_ROI_NONE))
    c.idle(1.0)
    c.fresh("GIMBAL_DEVICE_ATTITUDE_STATUS")
    trace.fact("roi_none.attitude", _euler_deg(c.last["GIMBAL_DEVICE_ATTITUDE_STATUS"].q)[1:], ROI_ANGLE)
    trace.fact("roi_none.flags", c.last["GIMBAL_DEVICE_ATTITUDE_STATUS"].flags)
    heading = _heading_deg(c)
    trace.fact("control.result", c.command(mav.MAV_CMD_DO_MOUNT_CONTROL, -20, 0, 60, 0, 0, 0, 2))
    c.idle(6.0)
    c.fresh("GIMBAL_DEVICE_ATTITUDE_STATUS")
    trace.fact("control.attitude", _euler_deg(c.last["GIMBAL_DEVICE_ATTITUDE_STATUS"].q)[1:], ROI_ANGLE)
    trace.fact("control.turned", (_heading_deg(c) - heading + 180.0) % 360.0 - 180.0, HEADING)
    c.fresh("SERVO_OUTPUT_RAW")
    out = c.last["SERVO_OUTPUT_RAW"]
    trace.fact("control.pwm", [getattr(out, f"servo{n}_raw") for n in ((TILT, PAN) if pan else (TILT,))],
               Tol(abs=12, why="the hover's lean, taken off the tilt: a degree is 7 us"))
    c.set_mode(GUIDED)


def roi_flying(c: Client, trace: Trace) -> None:
    _flying(c, trace, True)


def tilt_only(c: Client, trace: Trace) -> None:
    _flying(c, trace, False)


def _geometry(c: Client) -> Geometry:
    c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_GLOBAL_POSITION_INT, 100_000)
    c.wait(lambda: "GLOBAL_POSITION_INT" in c.last, 10, what="position")
    return Geometry(c.last["GLOBAL_POSITION_INT"].lat, c.last["GLOBAL_POSITION_INT"].lon)


def _fly(c: Client, trace: Trace, geo: Geometry, items: list, stops: tuple, settle_s: float) -> None:
    """Upload and fly `items`; at each stop (seq, (north, east)), hovering there with that waypoint
    current (the do items before it run as it becomes current), `settle_s` later: the gimbal's
    pitch, yaw and flags and the vehicle's heading."""
    trace.fact("upload", upload(c, items))
    c.set_mode(GUIDED)
    c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    c.try_wait(lambda: c.armed, 10)
    trace.fact("start", c.command(mav.MAV_CMD_MISSION_START))
    for seq, (north, east) in stops:
        def hovering_there() -> bool:
            g = c.last["GLOBAL_POSITION_INT"]
            n, e = geo.ne(g.lat, g.lon)
            return (c.last["MISSION_CURRENT"].seq == seq and math.hypot(n - north, e - east) < 0.5
                    and math.hypot(g.vx, g.vy) < 30)
        c.wait(lambda: "MISSION_CURRENT" in c.last and hovering_there(), 90, what=f"hovering at item {seq}")
        c.idle(settle_s)
        c.fresh("GIMBAL_DEVICE_ATTITUDE_STATUS")
        status = c.last["GIMBAL_DEVICE_ATTITUDE_STATUS"]
        trace.fact(f"wp{seq}.attitude", _euler_deg(status.q)[1:], ROI_ANGLE)
        trace.fact(f"wp{seq}.flags", status.flags)
        trace.fact(f"wp{seq}.heading", _heading_deg(c), HEADING)


def mission(c: Client, trace: Trace) -> None:
    geo = _geometry(c)
    wp, hold = mav.MAV_CMD_NAV_WAYPOINT, (6, 0, 0, 0)  # each waypoint held 6 s: the gimbal read in the hover
    items = [item(mav.MAV_CMD_NAV_TAKEOFF, geo, alt=10),  # 1
             item(mav.MAV_CMD_DO_MOUNT_CONTROL, geo, (-40, 0, 30, 0), alt=2),  # 2
             item(wp, geo, hold, at=(20.0, 0.0), alt=10),  # 3
             item(CMD_PITCHYAW, geo, (-60, -45, 0, 0)),  # 4 (AP_Mission refuses NaN rates in a mission)
             item(wp, geo, hold, at=(40.0, 0.0), alt=10),  # 5
             item(mav.MAV_CMD_DO_SET_ROI_LOCATION, geo, at=(40.0, 30.0), alt=0),  # 6
             item(wp, geo, hold, at=(50.0, 0.0), alt=10),  # 7
             item(mav.MAV_CMD_DO_SET_ROI_NONE, geo),  # 8
             item(wp, geo, hold, at=(60.0, 0.0), alt=10),  # 9
             item(mav.MAV_CMD_NAV_LAND, geo)]
    _fly(c, trace, geo, items, ((3, (20.0, 0.0)), (5, (40.0, 0.0)), (7, (50.0, 0.0)), (9, (60.0, 0.0))), 1.0)
    c.set_mode(GUIDED)  # out of AUTO: the gimbal back to its default mode
    c.idle(1.0)
    c.fresh("GIMBAL_DEVICE_ATTITUDE_STATUS")
    trace.fact("guided.flags", c.last["GIMBAL_DEVICE_ATTITUDE_STATUS"].flags)
    trace.fact("guided.attitude", _euler_deg(c.last["GIMBAL_DEVICE_ATTITUDE_STATUS"].q)[1:], ROI_ANGLE)


def tilt_mission(c: Client, trace: Trace) -> None:
    geo = _geometry(c)
    wp, hold = mav.MAV_CMD_NAV_WAYPOINT, (8, 0, 0, 0)
    items = [item(mav.MAV_CMD_NAV_TAKEOFF, geo, alt=10),  # 1
             item(mav.MAV_CMD_DO_MOUNT_CONTROL, geo, (-30, 0, 90, 0), alt=2),  # 2
             item(wp, geo, hold, at=(20.0, 0.0), alt=10),  # 3
             item(mav.MAV_CMD_DO_SET_ROI_LOCATION, geo, at=(0.0, -20.0), alt=0),  # 4
             item(wp, geo, hold, at=(30.0, 0.0), alt=10),  # 5
             item(mav.MAV_CMD_NAV_LAND, geo)]
    _fly(c, trace, geo, items, ((3, (20.0, 0.0)), (5, (30.0, 0.0))), 3.0)


RC_BOOT = {**SERVO_BOOT, "RC9_OPTION": 213, "RC10_OPTION": 214}
LEAVE = 65535  # RC_CHANNELS_OVERRIDE: channels 1-8 left as they are


def _sticks(c: Client, pitch_pwm: int, yaw_pwm: int, hold_s: float) -> None:
    """Channels 9 and 10 overridden for `hold_s`, resent every 0.2 s (overrides time out)."""
    end = c.now_ms + hold_s * 1000
    while c.now_ms < end:
        c.conn.mav.rc_channels_override_send(1, 1, *([LEAVE] * 8), pitch_pwm, yaw_pwm)
        c.idle(0.2)


def rc_targeting(c: Client, trace: Trace) -> None:
    c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_SERVO_OUTPUT_RAW, 100_000)
    c.fresh("RC_CHANNELS")
    trace.fact("receiver_pwm", [c.last["RC_CHANNELS"].chan9_raw, c.last["RC_CHANNELS"].chan10_raw])
    _gimbal(c, trace, "receiver", settle_s=0.1)
    _sticks(c, 1800, 1200, 1.0)
    _gimbal(c, trace, "sticks", settle_s=0.0)
    trace.fact("control.result", c.command(mav.MAV_CMD_DO_MOUNT_CONTROL, -60, 0, 0, 0, 0, 0, 2))
    _sticks(c, 1800, 1200, 1.0)
    _gimbal(c, trace, "control_held", settle_s=0.0)
    _sticks(c, 1300, 1200, 1.0)
    _gimbal(c, trace, "stick_moved", settle_s=0.0)
    trace.fact("rate_set", c.set_param("MNT1_RC_RATE", 30))
    _sticks(c, 1500, 1500, 0.5)
    c.fresh("GIMBAL_DEVICE_ATTITUDE_STATUS")
    t0, p0 = c.now_ms, _euler_deg(c.last["GIMBAL_DEVICE_ATTITUDE_STATUS"].q)[1]
    _sticks(c, 1800, 1500, 1.0)
    c.fresh("GIMBAL_DEVICE_ATTITUDE_STATUS")
    t1, p1 = c.now_ms, _euler_deg(c.last["GIMBAL_DEVICE_ATTITUDE_STATUS"].q)[1]
    trace.fact("rate.deg_s", (p1 - p0) * 1000.0 / max(t1 - t0, 1), Tol(abs=3.0, why="18 deg/s read off two 10 Hz "
                                                                                 "samples a second apart"))


PROBES = {"no_mount": (no_mount, None), "servo": (servo, SERVO_BOOT), "roi_flying": (roi_flying, SERVO_BOOT),
          "tilt_only": (tilt_only, TILT_BOOT), "mission": (mission, SERVO_BOOT),
          "tilt_mission": (tilt_mission, TILT_BOOT), "rc_targeting": (rc_targeting, RC_BOOT)}


def run(target) -> dict[str, Trace]:
    return run_each(target, PROBES)

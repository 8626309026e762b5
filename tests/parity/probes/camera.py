"""The autopilot's camera (AP_Camera) with CAM1_TYPE 1, a servo camera on output 9 (SERVO9_FUNCTION
10), both set at power-on: CAM1_TYPE is read at boot.

commands      disarmed, then armed on the ground: each camera command's result and the pictures
              it took (CAMERA_FEEDBACK), the trigger output's PWM off and on and how long it stays
              on; the answers to REQUEST_MESSAGE for the camera's messages; an interval capture
              (three pictures a second apart: count and spacing); CAM1_INTRVAL_MIN postponing
              a picture asked too soon.
survey_leg    AUTO: DO_SET_CAM_TRIGG_DIST 10 m with a picture at once at the start of a 60 m leg
              north, 0 at its end, then a leg east: the trigger points (north/east of home, within
              1 m), their count, and each feedback's fields (heights, attitude, index, flags).
guided_dist   distance triggering outside AUTO: 8 m set by command, flown 30 m north in GUIDED
              (CAM_AUTO_ONLY 0: pictures), then back with CAM_AUTO_ONLY 1 (none).
relay_camera  CAM1_TYPE 2 (a relay camera) set and saved, rebooted: the commands' answers and
              pictures (a zoom and a focus among them), an interval, CAMERA_INFORMATION.
converted_type CAM1_TYPE never set, SERVO9_FUNCTION 10: CAM1_TYPE after boot, a picture.
camera_v2     disarmed, the servo camera of `commands` as a camera protocol v2 client (MAVSDK, QGC) sees
              it: REQUEST_MESSAGE for each of the protocol's camera and video messages (the ACK, how
              many ACKs, how many replies and the fields a client reads in the first), the deprecated
              REQUEST_CAMERA_* / REQUEST_VIDEO_STREAM_* commands, image_count over two pictures, and
              each of the protocol's other commands (mode, every zoom and focus type, tracking, video
              capture and streaming, storage format, reset) with what came back; CAMERA_SETTINGS and
              CAMERA_CAPTURE_STATUS after them. The camera has a zoom and a focus output too
              (SERVO10/11_FUNCTION 180/92): their PWM at boot and after each zoom and focus
              command, and a continuous zoom's and focus's speed and hold.
no_camera_v2  no camera (CAM1_TYPE 0): REQUEST_MESSAGE for each camera message (the ACKs, the replies).
servo_configure the servo camera of `commands` with ISO, aperture and shutter-speed outputs
              (SERVO12/13/14_FUNCTION 90/91/93): their PWM at boot, after a DO_DIGICAM_CONFIGURE
              asking for each (the ISO output's pulse: PWM and length) and after one asking none.
"""
from __future__ import annotations

import math
import time

from ..client import Client, ProbeTimeout, mav
from ..facts import Tol, Trace
from .missions import upload
from .states import GUIDED, reach_flying
from .surface_mission import ALT_M, Geometry, item
from ..targets import ready, run_each

AREA = "camera"
# The trigger output is read off SERVO_OUTPUT_RAW at 50 Hz: at 20x that is a thousand messages a
# wall second, more than a client on a busy machine drains; at 10x, as the reference is recorded
FIREFLY_SPEEDUP = "10"
# (ArduCopter takes CAM1_TYPE from a defaults file as unsaved, and derives an unsaved one at boot
# from the servo functions: with a trigger output it is 1, so the two agree. A relay camera needs
# CAM1_TYPE saved: relay_camera sets it and reboots.)
BOOT_PARAMS = {"CAM1_TYPE": 1, "SERVO9_FUNCTION": 10}
SERVO = 9
POSITION = Tol(abs=1.0, why="where a picture is taken: 50 Hz checks along a leg flown at up to 10 m/s by two "
                            "airframes; within a metre")
HOLD = Tol(abs=0.12, why="the shutter is held for 5 or 6 updates of AP_Camera's 50 Hz (0.1-0.12 s); the "
                         "reference's SERVO_OUTPUT_RAW asked at 50 Hz comes 20 to 100 ms apart at 10x (recorded 0.1, "
                         "then 0.2)")
SPACING = Tol(abs=0.12, why="an interval is checked at 50 Hz against the scheduler's own timing")
HEIGHT = Tol(abs=0.3, why="height on the leg within the position controllers' hold")
ANGLE = Tol(abs=5.0, why="attitude while cruising: the airframes lean differently for the same speed")
YAW = Tol(abs=5.0, why="heading along a leg north")
LIMIT_S = 90.0
REBOOT_WAIT_S = 60.0  # wall seconds for a rebooted vehicle to speak again
# MAVLink 2 messages the client's dialect module does not name
MSG_CAMERA_FEEDBACK, MSG_CAMERA_INFORMATION, MSG_CAMERA_SETTINGS = 180, 259, 260
MSG_CAMERA_CAPTURE_STATUS, MSG_CAMERA_FOV_STATUS = 262, 271
MSG_VIDEO_STREAM_INFORMATION, MSG_VIDEO_STREAM_STATUS, MSG_CAMERA_THERMAL_RANGE = 269, 270, 277
# What a camera protocol v2 client may get back from a camera command (camera_v2)
V2_REPLIES = ("CAMERA_INFORMATION", "CAMERA_SETTINGS", "CAMERA_CAPTURE_STATUS", "CAMERA_FOV_STATUS",
              "VIDEO_STREAM_INFORMATION", "VIDEO_STREAM_STATUS", "CAMERA_FEEDBACK", "CAMERA_IMAGE_CAPTURED",
              "STORAGE_INFORMATION", "CAMERA_THERMAL_RANGE")
V2_SETTLE_S = 0.5  # ACKs and replies counted this long after the first ACK
# camera_v2's servo camera also has a zoom (SERVOn_FUNCTION 180) and a focus (92) output: the lens
# a servo camera drives, from 0 % at SERVOn_MIN to 100 % at SERVOn_MAX
ZOOM_SERVO, FOCUS_SERVO = 10, 11
V2_PARAMS = {**BOOT_PARAMS, f"SERVO{ZOOM_SERVO}_FUNCTION": 180, f"SERVO{FOCUS_SERVO}_FUNCTION": 92}
RATE_WINDOW_S = 1.5  # a continuous zoom or focus timed over this much vehicle time
# servo_configure's servo camera also has an ISO (SERVOn_FUNCTION 90), an aperture (91) and a
# shutter-speed (93) output, which DO_DIGICAM_CONFIGURE drives
ISO_SERVO, APERTURE_SERVO, SHUTTER_SERVO = 12, 13, 14
CONFIGURE_OUTPUTS = (ISO_SERVO, APERTURE_SERVO, SHUTTER_SERVO)
CONFIGURE_PARAMS = {**BOOT_PARAMS, f"SERVO{ISO_SERVO}_FUNCTION": 90, f"SERVO{APERTURE_SERVO}_FUNCTION": 91,
                    f"SERVO{SHUTTER_SERVO}_FUNCTION": 93}
LENS_RATE = Tol(abs=3.0, why="a continuous zoom's or focus's speed [us/s] from two whole-microsecond PWMs "
                             "1.5 s apart (1 us in 1.5 s is 0.7 us/s) on the autopilot's 50 Hz steps")
INT32_MAX = 2**31 - 1


def _feedbacks(log: list) -> list:
    return [m for _, m in log if m.get_type() == "CAMERA_FEEDBACK"]


def _servo(log: list, output: int = SERVO) -> list[tuple[int, int]]:
    return [(t, getattr(m, f"servo{output}_raw")) for t, m in log if m.get_type() == "SERVO_OUTPUT_RAW"]


def _record(c: Client, log: list):
    def take(msg):
        if msg.get_type() in ("CAMERA_FEEDBACK", "SERVO_OUTPUT_RAW", "CAMERA_INFORMATION", "CAMERA_SETTINGS",
                              "CAMERA_CAPTURE_STATUS", "CAMERA_FOV_STATUS", "COMMAND_ACK"):
            log.append((c.now_ms, msg))
    return c.listening(take)


def _command(c: Client, trace: Trace, name: str, command: int, *params: float, settle_s: float = 0.6) -> None:
    log: list = []
    with _record(c, log):
        trace.fact(f"{name}.result", c.command(command, *params))
        c.idle(settle_s)
    trace.fact(f"{name}.pictures", len(_feedbacks(log)))


def _held_s(log: list, output: int = SERVO) -> float | None:
    """How long the trigger output (or `output`) stayed at CAM1_SERVO_ON after it first went there."""
    servo = _servo(log, output)
    on = next((t for t, pwm in servo if pwm == 1300), None)
    off = None if on is None else next((t for t, pwm in servo if t > on and pwm != 1300), None)
    return None if off is None else (off - on) / 1000.0


def commands(c: Client, trace: Trace) -> None:
    c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_SERVO_OUTPUT_RAW, 20_000)
    c.fresh("SERVO_OUTPUT_RAW")
    trace.fact("servo_off_pwm", c.last["SERVO_OUTPUT_RAW"].servo9_raw)
    log: list = []
    with _record(c, log):
        trace.fact("shoot.result", c.command(mav.MAV_CMD_DO_DIGICAM_CONTROL, 0, 0, 0, 0, 1, 0, 0))
        c.idle(1.0)
    c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_SERVO_OUTPUT_RAW, 500_000)
    shots = _feedbacks(log)
    trace.fact("shoot.pictures", len(shots))
    trace.fact("shoot.servo_on_pwm", max((pwm for _, pwm in _servo(log)), default=None))
    trace.fact("shoot.held_s", _held_s(log), HOLD)
    if shots:
        f = shots[0]
        trace.fact("shoot.feedback", {"img_idx": f.img_idx, "cam_idx": f.cam_idx, "flags": f.flags,
                                      "alt_rel": round(f.alt_rel, 1), "completed_captures": f.completed_captures,
                                      "target_system": f.target_system, "foc_len": f.foc_len})
    for msg_id, fields in ((MSG_CAMERA_INFORMATION, ("lens_id", "flags", "focal_length", "gimbal_device_id")),
                           (MSG_CAMERA_SETTINGS, ("mode_id",)),
                           (MSG_CAMERA_CAPTURE_STATUS, ("image_status", "image_interval", "image_count")),
                           (MSG_CAMERA_FEEDBACK, ("img_idx", "flags")),
                           (MSG_CAMERA_FOV_STATUS, ("lat_image", "alt_image"))):
        log = []
        with _record(c, log):
            result = c.command(mav.MAV_CMD_REQUEST_MESSAGE, msg_id)
            c.idle(0.3)
        replies = [m for _, m in log if m.get_msgId() == msg_id]
        name = replies[0].get_type() if replies else str(msg_id)
        trace.fact(f"request.{name}", [result, len(replies), *(getattr(replies[0], f) for f in fields)] if replies
                   else [result, 0])
    # an interval capture: three pictures a second apart
    log = []
    with _record(c, log):
        trace.fact("interval.result", c.command(mav.MAV_CMD_IMAGE_START_CAPTURE, 0, 1.0, 3))
        c.idle(0.3)
        c.command(mav.MAV_CMD_REQUEST_MESSAGE, MSG_CAMERA_CAPTURE_STATUS)
        c.idle(3.5)
    shots = [t for t, m in log if m.get_type() == "CAMERA_FEEDBACK"]
    trace.fact("interval.pictures", len(shots))
    trace.fact("interval.spacing_s", [(b - a) / 1000.0 for a, b in zip(shots, shots[1:])], SPACING)
    status = [m for _, m in log if m.get_type() == "CAMERA_CAPTURE_STATUS"]
    trace.fact("interval.status_while", [status[0].image_status, status[0].image_interval] if status else None)
    for name, command, params in (
            ("start_forever", mav.MAV_CMD_IMAGE_START_CAPTURE, (0, 0.5, 0)),
            ("stop_all", mav.MAV_CMD_IMAGE_STOP_CAPTURE, (0,)),
            ("start_one_cam1", mav.MAV_CMD_IMAGE_START_CAPTURE, (1, 0, 0)),
            ("start_negative", mav.MAV_CMD_IMAGE_START_CAPTURE, (-1, 0, 0)),
            ("start_cam2", mav.MAV_CMD_IMAGE_START_CAPTURE, (2, 0, 0)),
            ("start_count_no_interval", mav.MAV_CMD_IMAGE_START_CAPTURE, (0, 0, 3)),
            ("stop_cam1", mav.MAV_CMD_IMAGE_STOP_CAPTURE, (1,)),
            ("stop_cam2", mav.MAV_CMD_IMAGE_STOP_CAPTURE, (2,)),
            ("stop_negative", mav.MAV_CMD_IMAGE_STOP_CAPTURE, (-1,)),
            ("source_all", mav.MAV_CMD_SET_CAMERA_SOURCE, (0, 1, 0)),
            ("source_cam1", mav.MAV_CMD_SET_CAMERA_SOURCE, (1, 1, 0)),
            ("source_cam3", mav.MAV_CMD_SET_CAMERA_SOURCE, (3, 1, 0)),
            ("configure", mav.MAV_CMD_DO_DIGICAM_CONFIGURE, (1, 0, 0, 0, 0, 0, 0)),
            ("control_no_shot", mav.MAV_CMD_DO_DIGICAM_CONTROL, (0, 0, 0, 0, 0)),
            ("trigg_dist_once", mav.MAV_CMD_DO_SET_CAM_TRIGG_DIST, (0, 0, 1)),
            ("trigg_dist_no_shot", mav.MAV_CMD_DO_SET_CAM_TRIGG_DIST, (0, 0, 0))):
        _command(c, trace, name, command, *params, settle_s=1.7 if name == "start_forever" else 0.6)
    # CAM1_INTRVAL_MIN: a picture asked for too soon waits until it has passed
    c.set_param("CAM1_INTRVAL_MIN", 2.0)
    log = []
    with _record(c, log):
        c.command(mav.MAV_CMD_DO_DIGICAM_CONTROL, 0, 0, 0, 0, 1)
        first = c.now_ms
        c.idle(0.5)
        c.command(mav.MAV_CMD_DO_DIGICAM_CONTROL, 0, 0, 0, 0, 1)
        c.idle(3.0)
    shots = [t for t, m in log if m.get_type() == "CAMERA_FEEDBACK"]
    trace.fact("interval_min.pictures", len(shots))
    trace.fact("interval_min.gap_s", (shots[1] - shots[0]) / 1000.0 if len(shots) > 1 else None, SPACING)
    c.set_param("CAM1_INTRVAL_MIN", 0.0)
    del first
    # armed on the ground, then flying
    c.set_mode(GUIDED)
    c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    c.try_wait(lambda: c.armed, 10)
    _command(c, trace, "armed_shoot", mav.MAV_CMD_DO_DIGICAM_CONTROL, 0, 0, 0, 0, 1)
    reach_flying(c)
    log = []
    with _record(c, log):
        trace.fact("flying_shoot.result", c.command(mav.MAV_CMD_IMAGE_START_CAPTURE, 0, 0, 1))
        c.idle(0.6)
    shots = _feedbacks(log)
    trace.fact("flying_shoot.pictures", len(shots))
    trace.fact("flying_shoot.alt_rel", shots[0].alt_rel if shots else None, HEIGHT)


def _start(c: Client) -> Geometry:
    c.request_streams(2)
    c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_GLOBAL_POSITION_INT, 100_000)
    c.wait(lambda: "GLOBAL_POSITION_INT" in c.last, 10, what="position")
    return Geometry(c.last["GLOBAL_POSITION_INT"].lat, c.last["GLOBAL_POSITION_INT"].lon)


def survey_leg(c: Client, trace: Trace) -> None:
    geo = _start(c)
    items = [item(mav.MAV_CMD_NAV_TAKEOFF, geo, alt=ALT_M), item(mav.MAV_CMD_NAV_WAYPOINT, geo, at=(0.5, 0.0), alt=ALT_M),
             item(mav.MAV_CMD_DO_SET_CAM_TRIGG_DIST, geo, (10, 0, 1, 0)),
             item(mav.MAV_CMD_NAV_WAYPOINT, geo, at=(60.0, 0.0), alt=ALT_M),
             item(mav.MAV_CMD_DO_SET_CAM_TRIGG_DIST, geo, (0, 0, 0, 0)),
             item(mav.MAV_CMD_NAV_WAYPOINT, geo, at=(60.0, 30.0), alt=ALT_M), item(mav.MAV_CMD_NAV_LAND, geo)]
    trace.fact("upload", upload(c, items))
    c.set_mode(GUIDED)
    c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    c.try_wait(lambda: c.armed, 10)
    log: list = []
    with _record(c, log):
        trace.fact("start", c.command(mav.MAV_CMD_MISSION_START))
        c.wait(lambda: not c.armed, 2 * LIMIT_S, what="the mission flown and landed")
    shots = _feedbacks(log)
    trace.fact("pictures", len(shots))
    points = [geo.ne(m.lat, m.lng) for m in shots]
    for i, (n, e) in enumerate(points):
        trace.fact(f"picture{i + 1}.north_m", n, POSITION)
        trace.fact(f"picture{i + 1}.east_m", e, POSITION)
    trace.fact("img_idx", [m.img_idx for m in shots])
    trace.fact("flags", sorted({m.flags for m in shots}))
    trace.fact("cam_idx", sorted({m.cam_idx for m in shots}))
    on_leg = shots[1:]
    if on_leg:
        trace.fact("leg.alt_rel", sum(m.alt_rel for m in on_leg) / len(on_leg), HEIGHT)
        trace.fact("leg.alt_msl_minus_rel", round(sum(m.alt_msl - m.alt_rel for m in on_leg) / len(on_leg), 1), HEIGHT)
        trace.fact("leg.yaw_range", [min(m.yaw for m in on_leg) >= 0, max(m.yaw for m in on_leg) < 360])
        heading = math.degrees(math.atan2(sum(math.sin(math.radians(m.yaw)) for m in on_leg),
                                          sum(math.cos(math.radians(m.yaw)) for m in on_leg)))
        trace.fact("leg.yaw_deg", heading, YAW)
        trace.fact("leg.pitch_deg", sum(m.pitch for m in on_leg) / len(on_leg), ANGLE)
        trace.fact("leg.roll_deg", sum(m.roll for m in on_leg) / len(on_leg), ANGLE)
        spacing = [math.dist(a, b) for a, b in zip(points[1:], points[2:])]
        trace.fact("leg.min_spacing_m", min(spacing) if spacing else None, Tol(abs=0.3, why="the 50 Hz check's "
                                                                                "overshoot at cruise speed"))


def guided_dist(c: Client, trace: Trace) -> None:
    geo = _start(c)
    reach_flying(c)
    trace.fact("trigg_dist.result", c.command(mav.MAV_CMD_DO_SET_CAM_TRIGG_DIST, 8, 0, 0))
    log: list = []
    with _record(c, log):
        lat, lon = geo.latlon((30.0, 0.0))
        c.conn.mav.set_position_target_global_int_send(0, 1, 1, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, 0b110111111000,
                                                       lat, lon, 10.0, 0, 0, 0, 0, 0, 0, 0, 0)
        c.wait(lambda: geo.ne(c.last["GLOBAL_POSITION_INT"].lat, c.last["GLOBAL_POSITION_INT"].lon)[0] > 29.0,
               LIMIT_S, what="30 m north")
        c.idle(2.0)
    shots = _feedbacks(log)
    trace.fact("guided.pictures", len(shots))
    trace.fact("guided.north_m", [geo.ne(m.lat, m.lng)[0] for m in shots], POSITION)
    c.set_param("CAM_AUTO_ONLY", 1)
    log = []
    with _record(c, log):
        lat, lon = geo.latlon((0.0, 0.0))
        c.conn.mav.set_position_target_global_int_send(0, 1, 1, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, 0b110111111000,
                                                       lat, lon, 10.0, 0, 0, 0, 0, 0, 0, 0, 0)
        c.wait(lambda: geo.ne(c.last["GLOBAL_POSITION_INT"].lat, c.last["GLOBAL_POSITION_INT"].lon)[0] < 1.0,
               LIMIT_S, what="back home")
        c.idle(1.0)
    trace.fact("auto_only.pictures", len(_feedbacks(log)))


def rebooted(c: Client) -> Client:
    """PREFLIGHT_REBOOT_SHUTDOWN, and a client for the vehicle that comes back, ready to arm. The
    reboot is seen in wall time (the new vehicle's clock starts again, below the client's, and
    ArduCopter streams nothing until asked, so streams are asked for while waiting)."""
    c.idle(3.0)  # up long enough that the new clock is seen to go back (by more than 2 s)
    newest = c.now_ms
    went_back: list[int] = []

    def watch(msg) -> None:
        stamp = getattr(msg, "time_boot_ms", None)
        if stamp is not None and msg.get_type() != "TIMESYNC" and stamp + 2000 < newest:
            went_back.append(stamp)
    with c.listening(watch):
        if c.command(mav.MAV_CMD_PREFLIGHT_REBOOT_SHUTDOWN, 1) != mav.MAV_RESULT_ACCEPTED:
            raise ProbeTimeout("reboot refused")
        wall0 = asked = time.monotonic()
        while not went_back:
            if time.monotonic() - wall0 > REBOOT_WAIT_S:
                raise ProbeTimeout("no reboot seen")
            c.pump(0.05)
            if time.monotonic() - asked > 0.5:
                c.request_streams()
                asked = time.monotonic()
    url = c.url
    c.close()
    return ready(Client(url), 10)


def relay_camera(c: Client, trace: Trace) -> None:
    # CAM1_TYPE set and saved, then a reboot, as a user sets a camera up: ArduCopter builds the
    # camera at boot, and a CAM1_TYPE it finds unsaved (a defaults file's) it derives from the
    # older CAM_TRIGG_TYPE and the servo functions instead (AP_Camera::convert_params)
    trace.fact("type_set", c.set_param("CAM1_TYPE", 2))
    c = rebooted(c)
    for name, command, params in (("shoot", mav.MAV_CMD_DO_DIGICAM_CONTROL, (0, 0, 0, 0, 1)),
                                  ("start_one", mav.MAV_CMD_IMAGE_START_CAPTURE, (0, 0, 1)),
                                  ("trigg_dist_once", mav.MAV_CMD_DO_SET_CAM_TRIGG_DIST, (0, 0, 1)),
                                  ("source_all", mav.MAV_CMD_SET_CAMERA_SOURCE, (0, 1, 0)),
                                  ("zoom_range", mav.MAV_CMD_SET_CAMERA_ZOOM, (mav.ZOOM_TYPE_RANGE, 50)),
                                  ("focus_range", mav.MAV_CMD_SET_CAMERA_FOCUS, (mav.FOCUS_TYPE_RANGE, 50))):
        _command(c, trace, name, command, *params)
    log: list = []
    with _record(c, log):
        trace.fact("interval.result", c.command(mav.MAV_CMD_IMAGE_START_CAPTURE, 0, 0.5, 3))
        c.idle(2.5)
    trace.fact("interval.img_idx", [m.img_idx for m in _feedbacks(log)])
    log = []
    with _record(c, log):
        c.command(mav.MAV_CMD_REQUEST_MESSAGE, MSG_CAMERA_INFORMATION)
        c.idle(0.3)
    trace.fact("information", len([m for _, m in log if m.get_type() == "CAMERA_INFORMATION"]))


def converted_type(c: Client, trace: Trace) -> None:
    c.conn.mav.param_request_read_send(1, 1, b"CAM1_TYPE", -1)
    c.last.pop("PARAM_VALUE", None)
    c.wait(lambda: "PARAM_VALUE" in c.last and c.last["PARAM_VALUE"].param_id == "CAM1_TYPE", 5, what="CAM1_TYPE")
    trace.fact("cam1_type", c.last["PARAM_VALUE"].param_value)
    _command(c, trace, "shoot", mav.MAV_CMD_DO_DIGICAM_CONTROL, 0, 0, 0, 0, 1)


def _exchange(c: Client, command: int, *params: float) -> tuple[int | None, int, list]:
    """A command sent once: its first ACK's result, how many ACKs it got (exactly one is the
    rule) and the camera messages that came back within V2_SETTLE_S of vehicle time after it."""
    log: list = []

    def take(msg) -> None:
        kind = msg.get_type()
        if kind in V2_REPLIES or (kind == "COMMAND_ACK" and msg.command == command):
            log.append(msg)
    with c.listening(take):
        result = c.command(command, *params)
        c.idle(V2_SETTLE_S)
    acks = sum(m.get_type() == "COMMAND_ACK" for m in log)
    return result, acks, [m for m in log if m.get_type() != "COMMAND_ACK"]


def _visible(value):
    """A field as a client reads it: text for a name (a uint8 array or a string, NULs dropped),
    "NaN" for an unknown float (NaN equals nothing, a recording included)."""
    if isinstance(value, float) and math.isnan(value):
        return "NaN"
    if isinstance(value, list) and all(isinstance(v, int) for v in value) and len(value) == 32:
        return bytes(value).rstrip(b"\0").decode(errors="replace")
    if isinstance(value, (str, bytes)):
        text = value.decode(errors="replace") if isinstance(value, bytes) else value
        return text.rstrip("\0")
    return value


# REQUEST_MESSAGE (param 2 as MAVSDK and QGC send it: 0, every stream) and the fields a client
# reads; "uri" and "cam_definition_uri" as their presence (a stream's address names a port). The
# names are spelled out: the client's dialect module (MAVLink 1's) has no table of these ids.
V2_MESSAGES = (
    (MSG_CAMERA_INFORMATION, "CAMERA_INFORMATION",
     ("vendor_name", "model_name", "firmware_version", "sensor_size_h", "sensor_size_v", "resolution_h",
      "resolution_v", "cam_definition_version", "cam_definition_uri", "camera_device_id")),
    (MSG_CAMERA_SETTINGS, "CAMERA_SETTINGS", ("mode_id", "zoomLevel", "focusLevel", "camera_device_id")),
    (MSG_CAMERA_CAPTURE_STATUS, "CAMERA_CAPTURE_STATUS",
     ("image_status", "video_status", "image_interval", "recording_time_ms", "available_capacity", "image_count",
      "camera_device_id")),
    (MSG_VIDEO_STREAM_INFORMATION, "VIDEO_STREAM_INFORMATION",
     ("stream_id", "count", "type", "flags", "framerate", "resolution_h", "resolution_v", "bitrate", "rotation",
      "hfov", "name", "uri", "encoding", "camera_device_id")),
    (MSG_VIDEO_STREAM_STATUS, "VIDEO_STREAM_STATUS",
     ("stream_id", "flags", "framerate", "resolution_h", "resolution_v", "bitrate", "rotation", "hfov",
      "camera_device_id")),
    (MSG_CAMERA_FOV_STATUS, "CAMERA_FOV_STATUS", ("hfov", "vfov", "camera_device_id")),
    (MSG_CAMERA_THERMAL_RANGE, "CAMERA_THERMAL_RANGE", ("stream_id", "max", "min", "camera_device_id")),
)
URIS = ("uri", "cam_definition_uri")


def _fields(msg, names: tuple[str, ...]) -> dict:
    seen = {name: _visible(getattr(msg, name)) for name in names}
    seen.update({name: bool(seen[name]) for name in URIS if name in seen})
    if msg.get_type() == "CAMERA_FOV_STATUS":  # where the camera is (no mount: the vehicle) and its roll/pitch
        seen["located"] = msg.lat_camera != INT32_MAX and msg.lon_camera != INT32_MAX
        seen["q_x_y"] = [round(msg.q[1], 3), round(msg.q[2], 3)]
    return seen


def _request(c: Client, msg_id: int, names: tuple[str, ...] = ()) -> dict:
    result, acks, replies = _exchange(c, mav.MAV_CMD_REQUEST_MESSAGE, msg_id, 0)
    mine = [m for m in replies if m.get_msgId() == msg_id]
    return {"result": result, "acks": acks, "replies": len(mine), **(_fields(mine[0], names) if mine else {})}


# The deprecated requests (param 1 = 1: "request it"; for a stream, the stream id: 0 every stream)
V2_DEPRECATED = (("request_camera_information", mav.MAV_CMD_REQUEST_CAMERA_INFORMATION, (1,)),
                 ("request_camera_settings", mav.MAV_CMD_REQUEST_CAMERA_SETTINGS, (1,)),
                 ("request_camera_capture_status", mav.MAV_CMD_REQUEST_CAMERA_CAPTURE_STATUS, (1,)),
                 ("request_video_stream_information", mav.MAV_CMD_REQUEST_VIDEO_STREAM_INFORMATION, (0,)),
                 ("request_video_stream_status", mav.MAV_CMD_REQUEST_VIDEO_STREAM_STATUS, (0,)))
# The protocol's other commands, each as a client sends it (camera/stream id 0: all)
V2_COMMANDS = (
    ("mode_image", mav.MAV_CMD_SET_CAMERA_MODE, (0, mav.CAMERA_MODE_IMAGE)),
    ("mode_video", mav.MAV_CMD_SET_CAMERA_MODE, (0, mav.CAMERA_MODE_VIDEO)),
    ("zoom_step", mav.MAV_CMD_SET_CAMERA_ZOOM, (mav.ZOOM_TYPE_STEP, 1)),
    ("zoom_range_25", mav.MAV_CMD_SET_CAMERA_ZOOM, (mav.ZOOM_TYPE_RANGE, 25)),
    ("zoom_range_150", mav.MAV_CMD_SET_CAMERA_ZOOM, (mav.ZOOM_TYPE_RANGE, 150)),
    ("zoom_range_negative", mav.MAV_CMD_SET_CAMERA_ZOOM, (mav.ZOOM_TYPE_RANGE, -10)),
    ("zoom_range_33", mav.MAV_CMD_SET_CAMERA_ZOOM, (mav.ZOOM_TYPE_RANGE, 33.3)),
    ("zoom_focal_length", mav.MAV_CMD_SET_CAMERA_ZOOM, (mav.ZOOM_TYPE_FOCAL_LENGTH, 35)),
    ("zoom_hfov", mav.MAV_CMD_SET_CAMERA_ZOOM, (mav.ZOOM_TYPE_HORIZONTAL_FOV, 60)),
    ("focus_step", mav.MAV_CMD_SET_CAMERA_FOCUS, (mav.FOCUS_TYPE_STEP, 1)),
    ("focus_range_75", mav.MAV_CMD_SET_CAMERA_FOCUS, (mav.FOCUS_TYPE_RANGE, 75)),
    ("focus_meters", mav.MAV_CMD_SET_CAMERA_FOCUS, (mav.FOCUS_TYPE_METERS, 10)),
    ("focus_auto", mav.MAV_CMD_SET_CAMERA_FOCUS, (mav.FOCUS_TYPE_AUTO,)),
    ("focus_auto_single", mav.MAV_CMD_SET_CAMERA_FOCUS, (mav.FOCUS_TYPE_AUTO_SINGLE,)),
    ("focus_auto_continuous", mav.MAV_CMD_SET_CAMERA_FOCUS, (mav.FOCUS_TYPE_AUTO_CONTINUOUS,)),
    ("track_point", mav.MAV_CMD_CAMERA_TRACK_POINT, (0.5, 0.5, 0.05)),
    ("track_rectangle", mav.MAV_CMD_CAMERA_TRACK_RECTANGLE, (0.4, 0.4, 0.6, 0.6)),
    ("stop_tracking", mav.MAV_CMD_CAMERA_STOP_TRACKING, ()),
    ("video_start_capture", mav.MAV_CMD_VIDEO_START_CAPTURE, (0, 0)),
    ("video_start_capture_stream1", mav.MAV_CMD_VIDEO_START_CAPTURE, (1, 1)),
    ("video_stop_capture", mav.MAV_CMD_VIDEO_STOP_CAPTURE, (0,)),
    ("video_start_streaming", mav.MAV_CMD_VIDEO_START_STREAMING, (0,)),
    ("video_stop_streaming", mav.MAV_CMD_VIDEO_STOP_STREAMING, (0,)),
    ("storage_format", mav.MAV_CMD_STORAGE_FORMAT, (1, 1)),
    ("storage_format_unconfirmed", mav.MAV_CMD_STORAGE_FORMAT, (1, 0)),
    ("storage_format_all", mav.MAV_CMD_STORAGE_FORMAT, (0, 1)),
    ("reset_settings", mav.MAV_CMD_RESET_CAMERA_SETTINGS, (1,)),
)


def _answer(c: Client, command: int, params: tuple) -> dict:
    result, acks, replies = _exchange(c, command, *params)
    return {"result": result, "acks": acks, "replies": sorted({m.get_type() for m in replies})}


def _lens_sample(c: Client) -> tuple[int, list[int]]:
    """A SERVO_OUTPUT_RAW sent from now on: its stamp [us] and the zoom and focus outputs' PWM."""
    c.fresh("SERVO_OUTPUT_RAW")
    raw = c.last["SERVO_OUTPUT_RAW"]
    return raw.time_usec, [getattr(raw, f"servo{ZOOM_SERVO}_raw"), getattr(raw, f"servo{FOCUS_SERVO}_raw")]


def _drift(c: Client, trace: Trace, name: str, command: int, params: tuple, lens: int) -> None:
    """A continuous zoom or focus (`lens` 0: the zoom output, 1: the focus output): its answer and
    how fast the output moves [us/s] over RATE_WINDOW_S; then the hold (rate 0), its answer and how
    far the output moves in the RATE_WINDOW_S after it."""
    trace.fact(name, _answer(c, command, params))
    t1, moving = _lens_sample(c)
    c.idle(RATE_WINDOW_S)
    t2, moved = _lens_sample(c)
    trace.fact(f"{name}.rate_us_s", (moved[lens] - moving[lens]) / ((t2 - t1) / 1e6), LENS_RATE)
    trace.fact(f"{name}_hold", _answer(c, command, (params[0], 0)))
    _, held = _lens_sample(c)
    c.idle(RATE_WINDOW_S)
    trace.fact(f"{name}_hold.moved_us", _lens_sample(c)[1][lens] - held[lens])


def camera_v2(c: Client, trace: Trace) -> None:
    for msg_id, name, fields in V2_MESSAGES:
        trace.fact(f"request.{name}", _request(c, msg_id, fields))
    for name, command, params in V2_DEPRECATED:
        trace.fact(name, _answer(c, command, params))
    counts = []
    for shot in (1, 2):  # a picture, then the count (the shutter is held 0.1 s: they are a second apart)
        trace.fact(f"shot{shot}", _answer(c, mav.MAV_CMD_IMAGE_START_CAPTURE, (0, 0, 1)))
        c.idle(0.5)
        counts.append(_request(c, MSG_CAMERA_CAPTURE_STATUS, ("image_count",)).get("image_count"))
    trace.fact("image_count", counts)
    c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_SERVO_OUTPUT_RAW, 100_000)
    trace.fact("lens_outputs_at_boot", _lens_sample(c)[1])
    for name, command, params in V2_COMMANDS:
        trace.fact(name, _answer(c, command, params))
        if command in (mav.MAV_CMD_SET_CAMERA_ZOOM, mav.MAV_CMD_SET_CAMERA_FOCUS):
            trace.fact(f"{name}.lens_outputs", _lens_sample(c)[1])
    _drift(c, trace, "zoom_continuous_in", mav.MAV_CMD_SET_CAMERA_ZOOM, (mav.ZOOM_TYPE_CONTINUOUS, 1), 0)
    _drift(c, trace, "focus_continuous_in", mav.MAV_CMD_SET_CAMERA_FOCUS, (mav.FOCUS_TYPE_CONTINUOUS, -1), 1)
    trace.fact("settings_after", _request(c, MSG_CAMERA_SETTINGS, ("mode_id", "zoomLevel", "focusLevel")))
    trace.fact("capture_status_after", _request(c, MSG_CAMERA_CAPTURE_STATUS,
                                                ("image_status", "video_status", "recording_time_ms")))


def _outputs(c: Client, outputs: tuple[int, ...]) -> list[int]:
    """These outputs' PWM from a SERVO_OUTPUT_RAW sent from now on."""
    c.fresh("SERVO_OUTPUT_RAW")
    return [getattr(c.last["SERVO_OUTPUT_RAW"], f"servo{n}_raw") for n in outputs]


def servo_configure(c: Client, trace: Trace) -> None:
    c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_SERVO_OUTPUT_RAW, 20_000)
    trace.fact("outputs_at_boot", _outputs(c, CONFIGURE_OUTPUTS))
    log: list = []
    with _record(c, log):  # mode 0, shutter speed 125, aperture 1234, ISO 100
        trace.fact("configure.result", c.command(mav.MAV_CMD_DO_DIGICAM_CONFIGURE, 0, 125, 1234, 100))
        c.idle(0.6)
    trace.fact("configure.iso_on_pwm", max((pwm for _, pwm in _servo(log, ISO_SERVO)), default=None))
    trace.fact("configure.iso_held_s", _held_s(log, ISO_SERVO), HOLD)
    trace.fact("configure.outputs_after", _outputs(c, CONFIGURE_OUTPUTS))
    trace.fact("configure_zeros.result", c.command(mav.MAV_CMD_DO_DIGICAM_CONFIGURE, 0, 0, 0, 0))
    c.idle(0.3)
    trace.fact("configure_zeros.outputs_after", _outputs(c, CONFIGURE_OUTPUTS))
    c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_SERVO_OUTPUT_RAW, 500_000)


def no_camera_v2(c: Client, trace: Trace) -> None:
    for msg_id, name, _ in ((MSG_CAMERA_FEEDBACK, "CAMERA_FEEDBACK", ()), *V2_MESSAGES):
        trace.fact(f"request.{name}", _request(c, msg_id))


PROBES = {"commands": (commands, BOOT_PARAMS), "survey_leg": (survey_leg, BOOT_PARAMS),
          "guided_dist": (guided_dist, BOOT_PARAMS),
          # CAM1_TYPE 2 (set by the probe): a relay camera on SITL's relay 1 (RELAY1_FUNCTION 4: the camera)
          "relay_camera": (relay_camera, {"RELAY1_FUNCTION": 4}),
          # CAM1_TYPE left alone, a trigger output set: the camera is a servo camera after boot
          "converted_type": (converted_type, {"SERVO9_FUNCTION": 10}),
          "camera_v2": (camera_v2, V2_PARAMS),
          # no camera at all (CAM1_TYPE 0, no trigger output): what a camera client asking finds
          "no_camera_v2": (no_camera_v2, None),
          "servo_configure": (servo_configure, CONFIGURE_PARAMS)}


def run(target) -> dict[str, Trace]:
    return run_each(target, PROBES)

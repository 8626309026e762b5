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
              pictures, an interval, CAMERA_INFORMATION.
converted_type CAM1_TYPE never set, SERVO9_FUNCTION 10: CAM1_TYPE after boot, a picture.
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


def _feedbacks(log: list) -> list:
    return [m for _, m in log if m.get_type() == "CAMERA_FEEDBACK"]


def _servo(log: list) -> list[tuple[int, int]]:
    return [(t, m.servo9_raw) for t, m in log if m.get_type() == "SERVO_OUTPUT_RAW"]


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


def _held_s(log: list) -> float | None:
    """How long the trigger output stayed at CAM1_SERVO_ON after the first picture in `log`."""
    servo = _servo(log)
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
                                  ("source_all", mav.MAV_CMD_SET_CAMERA_SOURCE, (0, 1, 0))):
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


PROBES = {"commands": (commands, BOOT_PARAMS), "survey_leg": (survey_leg, BOOT_PARAMS),
          "guided_dist": (guided_dist, BOOT_PARAMS),
          # CAM1_TYPE 2 (set by the probe): a relay camera on SITL's relay 1 (RELAY1_FUNCTION 4: the camera)
          "relay_camera": (relay_camera, {"RELAY1_FUNCTION": 4}),
          # CAM1_TYPE left alone, a trigger output set: the camera is a servo camera after boot
          "converted_type": (converted_type, {"SERVO9_FUNCTION": 10})}


def run(target) -> dict[str, Trace]:
    return run_each(target, PROBES)

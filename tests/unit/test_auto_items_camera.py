"""CAM1 (payload/camera.py) on the real vehicle model: the shutter's output, pictures by command,
by interval and by distance in AUTO, and the camera commands' answers as ArduCopter's."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.mavlink.camera_commands import HANDLERS
from firefly.autopilot.mavlink.commands import Command
from firefly.autopilot.mavlink.dialect import mavlink as mav
from firefly.autopilot.mission import MissionItem
from firefly.autopilot.params import ParamStore
from firefly.autopilot.results import Result
from firefly.autopilot.vehicle import Vehicle, VehicleConfig

from ._util import fly_until
from .test_auto import takeoff, wp_at

SERVO9 = 8  # 0-based


def camera_vehicle(kind: int = 1, trigger_output: bool = True, **params) -> Vehicle:
    store = ParamStore()
    store.set("CAM1_TYPE", kind)
    if trigger_output:
        store.set("SERVO9_FUNCTION", 10)
    for name, value in params.items():
        store.set(name, value)
    v = Vehicle(VehicleConfig(), store)
    v.run_until(0.5)
    return v


def pictures(v: Vehicle, seconds: float) -> list[tuple[float, object]]:
    """Run `seconds`; each picture reported (as the session drains them) with its time."""
    taken = []
    end = v.time_s + seconds
    while v.time_s < end - 1e-9:
        v.run_until(v.time_s + 0.01)
        if v.camera.feedback_due:
            v.camera.feedback_due = False
            taken.append((v.time_s, v.camera.feedback))
    return taken


def command(v: Vehicle, number: int, *params: float) -> Result:
    p = (list(params) + [0.0] * 7)[:7]
    session = type("Session", (), {"vehicle": v})()
    return HANDLERS[number](session, Command(number, *p, mav.MAV_FRAME_GLOBAL, False, 0, (255, 190)))


def test_a_picture_holds_the_trigger_output_for_cam1_duration_and_is_reported():
    v = camera_vehicle()
    assert v.servo_pwm[SERVO9] == 1100  # CAM1_SERVO_OFF from boot
    assert command(v, mav.MAV_CMD_DO_DIGICAM_CONTROL, 0, 0, 0, 0, 1) == Result.ACCEPTED
    assert v.servo_pwm[SERVO9] == 1300 and v.camera.feedback_due
    f = v.camera.feedback
    assert f.image_index == 1 and f.alt_rel_m == 0.0 and f.time_usec == v.unix_time_us()
    v.run_until(v.time_s + 0.08)
    assert v.servo_pwm[SERVO9] == 1300
    v.run_until(v.time_s + 0.06)
    assert v.servo_pwm[SERVO9] == 1100 and not v.camera.busy


def test_without_a_camera_commands_answer_as_arducopters_and_nothing_runs():
    v = camera_vehicle(kind=0, trigger_output=False)
    assert command(v, mav.MAV_CMD_DO_DIGICAM_CONTROL, 0, 0, 0, 0, 1) == Result.ACCEPTED
    assert command(v, mav.MAV_CMD_DO_SET_CAM_TRIGG_DIST, 10, 0, 1) == Result.ACCEPTED
    assert command(v, mav.MAV_CMD_IMAGE_START_CAPTURE, 0, 1, 3) == Result.FAILED
    assert command(v, mav.MAV_CMD_IMAGE_STOP_CAPTURE, 0) == Result.ACCEPTED
    assert command(v, mav.MAV_CMD_SET_CAMERA_SOURCE, 0, 1, 0) == Result.DENIED
    assert not v.camera.busy and v.camera.image_index == 0 and v.servo_pwm[SERVO9] == 0


def test_cam1_type_left_unset_with_a_trigger_output_becomes_a_servo_camera_at_boot():
    v = camera_vehicle(kind=0)
    assert v.params["CAM1_TYPE"] == 1 and v.camera.present and v.servo_pwm[SERVO9] == 1100


def test_capture_commands_refuse_what_the_reference_refuses():
    v = camera_vehicle()
    assert command(v, mav.MAV_CMD_IMAGE_START_CAPTURE, -1, 0, 0) == Result.UNSUPPORTED
    assert command(v, mav.MAV_CMD_IMAGE_START_CAPTURE, 2, 0, 0) == Result.FAILED  # no camera 2
    assert command(v, mav.MAV_CMD_IMAGE_START_CAPTURE, 0, 0, 3) == Result.FAILED  # three, no interval
    assert command(v, mav.MAV_CMD_IMAGE_STOP_CAPTURE, 2) == Result.UNSUPPORTED
    assert command(v, mav.MAV_CMD_IMAGE_STOP_CAPTURE, 1) == Result.ACCEPTED
    assert command(v, mav.MAV_CMD_SET_CAMERA_SOURCE, 1, 1, 0) == Result.DENIED
    assert v.camera.image_index == 0


def test_an_interval_capture_takes_its_count_a_interval_apart_then_stops():
    v = camera_vehicle()
    assert command(v, mav.MAV_CMD_IMAGE_START_CAPTURE, 0, 1.0, 3) == Result.ACCEPTED
    taken = pictures(v, 4.5)
    assert len(taken) == 3
    gaps = [b[0] - a[0] for a, b in zip(taken, taken[1:])]
    assert all(abs(g - 1.0) < 0.03 for g in gaps), gaps
    assert [f.image_index for _, f in taken] == [1, 2, 3]
    status = v.camera_status()
    assert not status.capturing and status.interval_s == 1.0


def test_a_picture_asked_within_cam1_intrval_min_waits_for_it():
    v = camera_vehicle(CAM1_INTRVAL_MIN=2.0)
    v.run_until(3.0)
    assert command(v, mav.MAV_CMD_DO_DIGICAM_CONTROL, 0, 0, 0, 0, 1) == Result.ACCEPTED
    first = v.time_s
    v.camera.feedback_due = False
    v.run_until(v.time_s + 0.5)
    command(v, mav.MAV_CMD_DO_DIGICAM_CONTROL, 0, 0, 0, 0, 1)
    assert not v.camera.feedback_due  # postponed
    taken = pictures(v, 2.0)
    assert len(taken) == 1 and abs(taken[0][0] - first - 2.0) < 0.03


@pytest.mark.parametrize("auto_only", [0, 1])
def test_auto_triggers_by_distance_along_a_leg_from_the_picture_taken_at_its_start(auto_only):
    v = camera_vehicle(CAM_AUTO_ONLY=auto_only)  # AUTO triggers either way
    v.mission.replace(0, [takeoff(), wp_at(v, 0.5, 0), MissionItem(206, 3, 10, 0, 1, 0), wp_at(v, 60, 0),
                          MissionItem(206, 3, 0), wp_at(v, 60, 30), MissionItem(21, 3)])
    v.set_mode(4)
    v.arm()
    v.set_mode(3)
    v.mission_start()
    taken = pictures(v, 45.0)
    norths = [v.ned_of(f.lat_e7 * 1e-7, f.lon_e7 * 1e-7, f.alt_msl_m)[0] for _, f in taken]
    assert len(taken) == 6, norths  # at the start, then every 10 m up to 50 (the leg ends at 60)
    assert abs(norths[0] - 0.5) < 0.5
    spacing = [b - a for a, b in zip(norths, norths[1:])]
    assert all(9.99 <= s < 10.6 for s in spacing), spacing  # places sent to 1e-7 degrees: a centimetre
    assert all(abs(f.alt_rel_m - 10.0) < 0.3 for _, f in taken[1:])
    assert v.camera.trigg_dist_m == 0 and v.params["CAM1_TRIGG_DIST"] == 0


def test_distance_triggering_waits_outside_auto_when_cam_auto_only():
    v = camera_vehicle(CAM_AUTO_ONLY=1)
    v.set_mode(4)
    v.arm()
    v.takeoff(10.0)
    assert fly_until(v, lambda x: x.home_ned[2] - x.body.d_m > 9.5, 20.0)
    assert command(v, mav.MAV_CMD_DO_SET_CAM_TRIGG_DIST, 5) == Result.ACCEPTED
    v.guided_goto(30.0, 0.0, v.body.d_m)
    assert not pictures(v, 12.0) and v.body.n_m > 25.0
    v.params.set("CAM_AUTO_ONLY", 0)
    v.guided_goto(0.0, 0.0, v.body.d_m)
    taken = pictures(v, 12.0)
    assert len(taken) >= 4 and math.isclose(v.camera.trigg_dist_m, 5.0)


def test_each_picture_is_logged_as_a_cam_record_as_arducopter_writes_it(tmp_path):
    from firefly.autopilot.dataflash.recorder import Recorder

    from .test_dataflash import MemorySink, read_log, run

    v = camera_vehicle(LOG_DISARMED=1)
    sink = MemorySink()
    rec = Recorder(v, sink)
    v.camera.picture_listener = rec.picture
    run(v, rec, 0.5)
    assert command(v, mav.MAV_CMD_DO_DIGICAM_CONTROL, 0, 0, 0, 0, 1) == Result.ACCEPTED
    run(v, rec, 0.5)
    cams = read_log(tmp_path, sink.logs[-1])["CAM"]
    assert len(cams) == 1
    cam, f = cams[0], v.camera.feedback
    assert (cam.I, cam.Img, cam.RelAlt) == (0, 1, 0.0)
    assert math.isclose(cam.Lat, f.lat_e7 * 1e-7) and math.isclose(cam.Alt, f.alt_msl_m)
    assert abs(cam.GPSAlt - f.alt_msl_m) < 1.0 and 0 <= cam.Y < 360 and cam.GPSWeek > 2000


def test_mission_items_shoot_start_and_stop_an_interval_capture():
    """DIGICAM_CONTROL (x = 1: shoot), IMAGE_START_CAPTURE every 1 s until stopped, then
    IMAGE_STOP_CAPTURE two waypoints on: pictures only between the two, a second apart."""
    v = camera_vehicle()
    v.mission.replace(0, [takeoff(), MissionItem(203, 2, x=1), MissionItem(2000, 2, 0, 1.0, 0),
                          wp_at(v, 20, 0), MissionItem(2001, 2, 0), wp_at(v, 20, 20), MissionItem(21, 3)])
    v.set_mode(4)
    v.arm()
    v.set_mode(3)
    v.mission_start()
    taken = pictures(v, 40.0)
    assert len(taken) >= 4
    easts = [v.ned_of(f.lat_e7 * 1e-7, f.lon_e7 * 1e-7, f.alt_msl_m)[1] for _, f in taken]
    assert max(easts) < 1.5  # none on the leg east, after IMAGE_STOP_CAPTURE (the corner is rounded)
    assert v.body.e_m > 19.0  # ... which was flown
    gaps = [b[0] - a[0] for a, b in zip(taken[1:], taken[2:])]
    assert all(abs(g - 1.0) < 0.03 for g in gaps), gaps
    assert [f.image_index for _, f in taken] == list(range(1, len(taken) + 1))
    assert not v.camera.busy and not v.camera_status().capturing


ZOOM, FOCUS = 9, 10  # 0-based: outputs 10 and 11


def lens_vehicle(kind: int = 1) -> Vehicle:
    """A camera of `kind` with a zoom output (SERVO10_FUNCTION 180) and a focus output (SERVO11 92)."""
    return camera_vehicle(kind, trigger_output=kind == 1, SERVO10_FUNCTION=180, SERVO11_FUNCTION=92)


def test_a_servo_camera_puts_its_lens_in_the_middle_then_where_a_percentage_asks():
    v = lens_vehicle()
    assert v.servo_pwm[ZOOM] == v.servo_pwm[FOCUS] == 1500  # 500 of 0..1000 over 1100..1900
    for percent, pwm in ((25, 1300), (150, 1900), (-10, 1100), (33.3, 1366)):
        assert command(v, mav.MAV_CMD_SET_CAMERA_ZOOM, mav.ZOOM_TYPE_RANGE, percent) == Result.ACCEPTED
        assert v.servo_pwm[ZOOM] == pwm, percent
    assert command(v, mav.MAV_CMD_SET_CAMERA_FOCUS, mav.FOCUS_TYPE_RANGE, 75) == Result.ACCEPTED
    assert (v.servo_pwm[ZOOM], v.servo_pwm[FOCUS]) == (1366, 1700)
    v.params.set("SERVO10_REVERSED", 1)
    assert v.servo_pwm[ZOOM] == 1633  # scaled afresh: 333 of 1000 from the top, 1100 + 667 * 0.8


def test_a_continuous_zoom_or_focus_moves_its_output_each_update_until_held():
    v = lens_vehicle()
    assert command(v, mav.MAV_CMD_SET_CAMERA_ZOOM, mav.ZOOM_TYPE_CONTINUOUS, 1) == Result.ACCEPTED
    assert command(v, mav.MAV_CMD_SET_CAMERA_FOCUS, mav.FOCUS_TYPE_CONTINUOUS, -1) == Result.ACCEPTED
    assert v.camera.busy
    v.run_until(v.time_s + 2.0)
    assert 1575 <= v.servo_pwm[ZOOM] <= 1581 and 1419 <= v.servo_pwm[FOCUS] <= 1425  # 40 us/s: 1 of 1000 at 50 Hz
    assert command(v, mav.MAV_CMD_SET_CAMERA_ZOOM, mav.ZOOM_TYPE_CONTINUOUS, 0) == Result.ACCEPTED
    assert command(v, mav.MAV_CMD_SET_CAMERA_FOCUS, mav.FOCUS_TYPE_CONTINUOUS, 0) == Result.ACCEPTED
    held = v.servo_pwm[ZOOM], v.servo_pwm[FOCUS]
    v.run_until(v.time_s + 1.0)
    assert (v.servo_pwm[ZOOM], v.servo_pwm[FOCUS]) == held and not v.camera.busy
    command(v, mav.MAV_CMD_SET_CAMERA_ZOOM, mav.ZOOM_TYPE_CONTINUOUS, 50)
    v.run_until(v.time_s + 1.0)
    assert v.servo_pwm[ZOOM] == 1900  # held to its range


def test_a_nan_zoom_rate_keeps_the_zoom_in_the_middle_with_arducopters_internal_error():
    v = lens_vehicle()
    command(v, mav.MAV_CMD_SET_CAMERA_ZOOM, mav.ZOOM_TYPE_RANGE, 10)
    assert command(v, mav.MAV_CMD_SET_CAMERA_ZOOM, mav.ZOOM_TYPE_CONTINUOUS, math.nan) == Result.ACCEPTED
    v.run_until(v.time_s + 0.1)
    assert v.servo_pwm[ZOOM] == 1500 and v.internal_error_bits != 0


def test_zoom_focus_tracking_and_video_answer_as_arducopters_by_camera_type():
    focus = mav.MAV_CMD_SET_CAMERA_FOCUS
    servo = lens_vehicle()
    assert [command(servo, mav.MAV_CMD_SET_CAMERA_ZOOM, t, 1) for t in
            (mav.ZOOM_TYPE_STEP, mav.ZOOM_TYPE_FOCAL_LENGTH, mav.ZOOM_TYPE_HORIZONTAL_FOV, 1.5, math.nan)] == \
        [Result.UNSUPPORTED] * 5
    assert [command(servo, focus, t, 1) for t in
            (mav.FOCUS_TYPE_STEP, mav.FOCUS_TYPE_METERS, 9, math.nan, mav.FOCUS_TYPE_AUTO, mav.FOCUS_TYPE_AUTO_SINGLE,
             mav.FOCUS_TYPE_AUTO_CONTINUOUS, 2.5)] == \
        [Result.DENIED] * 4 + [Result.UNSUPPORTED] * 3 + [Result.ACCEPTED]  # 2.5: cut to a range focus
    relay = lens_vehicle(kind=2)
    none = lens_vehicle(kind=0)
    mavlink_camera = lens_vehicle(kind=6)  # a MAVLink camera (none found here; the thermal one has no lens either)
    for v, zoom_result, focus_result in ((relay, Result.UNSUPPORTED, Result.UNSUPPORTED),
                                         (none, Result.UNSUPPORTED, Result.FAILED),
                                         (mavlink_camera, Result.UNSUPPORTED, Result.FAILED)):
        assert command(v, mav.MAV_CMD_SET_CAMERA_ZOOM, mav.ZOOM_TYPE_RANGE, 50) == zoom_result
        assert command(v, focus, mav.FOCUS_TYPE_RANGE, 50) == focus_result
        assert command(v, focus, mav.FOCUS_TYPE_STEP, 1) == Result.DENIED
        assert v.servo_pwm[ZOOM] == v.servo_pwm[FOCUS] == 0  # nothing drives the lens outputs
    for v in (servo, relay, none, mavlink_camera):
        assert [command(v, c, 0.5, 0.5, 0.6, 0.6) for c in (mav.MAV_CMD_CAMERA_TRACK_POINT,
                mav.MAV_CMD_CAMERA_TRACK_RECTANGLE, mav.MAV_CMD_CAMERA_STOP_TRACKING)] == [Result.UNSUPPORTED] * 3
        assert [command(v, c, 0) for c in (mav.MAV_CMD_VIDEO_START_CAPTURE, mav.MAV_CMD_VIDEO_STOP_CAPTURE)] == \
            [Result.FAILED] * 2


def test_mission_zoom_and_focus_items_move_the_lens_as_the_commands_do():
    from firefly.autopilot.modes.auto_items.camera import CameraItem

    v = lens_vehicle()
    ctx = type("Context", (), {"camera": v.camera})()
    for item in (MissionItem(531, 2, mav.ZOOM_TYPE_RANGE, 25), MissionItem(532, 2, mav.FOCUS_TYPE_RANGE, 75),
                 MissionItem(531, 2, mav.ZOOM_TYPE_STEP, 90), MissionItem(532, 2, mav.FOCUS_TYPE_AUTO, 0)):
        assert CameraItem().start(None, ctx, 0, item)  # done as it starts, whatever the camera makes of it
    assert (v.servo_pwm[ZOOM], v.servo_pwm[FOCUS]) == (1300, 1700)


def test_request_message_for_the_camera_messages_as_arducopter_answers_with_a_camera_or_none():
    from ._session_link import Link
    from ._util import of_type

    camera_messages = (mav.MAVLINK_MSG_ID_CAMERA_FEEDBACK, mav.MAVLINK_MSG_ID_CAMERA_INFORMATION,
                       mav.MAVLINK_MSG_ID_CAMERA_SETTINGS, mav.MAVLINK_MSG_ID_CAMERA_CAPTURE_STATUS,
                       mav.MAVLINK_MSG_ID_VIDEO_STREAM_INFORMATION, mav.MAVLINK_MSG_ID_CAMERA_FOV_STATUS)
    for kind in (0, 1):
        link = Link(lens_vehicle(kind))
        for msg_id in (*camera_messages, mav.MAVLINK_MSG_ID_CAMERA_THERMAL_RANGE,
                       mav.MAVLINK_MSG_ID_VIDEO_STREAM_STATUS):
            ack, out = link.command(mav.MAV_CMD_REQUEST_MESSAGE, msg_id)
            sent = [m for m in out if m.get_msgId() == msg_id]
            if msg_id == mav.MAVLINK_MSG_ID_VIDEO_STREAM_STATUS:  # not one ArduCopter knows how to send
                assert (ack.result, sent) == (Result.FAILED, []), kind
            else:  # accepted; sent by a camera that has it
                assert ack.result == Result.ACCEPTED and len(sent) == (kind == 1 and msg_id in camera_messages)
    stream = of_type(link.command(mav.MAV_CMD_REQUEST_MESSAGE, mav.MAVLINK_MSG_ID_VIDEO_STREAM_INFORMATION)[1],
                     "VIDEO_STREAM_INFORMATION")[0]
    assert (stream.stream_id, stream.count, stream.flags, stream.resolution_h, stream.name, stream.uri) == \
        (0, 0, 0, 0, "", "")  # a servo camera's: no stream described


def test_digicam_configure_pulses_a_servo_cameras_iso_output_and_sets_aperture_and_shutter_speed():
    iso, aperture, shutter = 11, 12, 13  # 0-based: outputs 12, 13, 14
    v = camera_vehicle(SERVO12_FUNCTION=90, SERVO13_FUNCTION=91, SERVO14_FUNCTION=93)
    assert v.servo_pwm[iso:shutter + 1] == [1100, 0, 0]  # the ISO output off from boot; the others never set
    assert command(v, mav.MAV_CMD_DO_DIGICAM_CONFIGURE, 0, 125, 1234, 100) == Result.ACCEPTED
    assert v.servo_pwm[iso:shutter + 1] == [1300, 1234, 125] and v.camera.busy
    v.run_until(v.time_s + 0.095)
    assert v.servo_pwm[iso] == 1300  # held CAM1_DURATION (0.1 s) from the next 50 Hz update
    v.run_until(v.time_s + 0.03)
    assert v.servo_pwm[iso:shutter + 1] == [1100, 1234, 125] and not v.camera.busy
    assert command(v, mav.MAV_CMD_DO_DIGICAM_CONFIGURE, 0, 0, math.nan, 0) == Result.ACCEPTED
    assert v.servo_pwm[iso:shutter + 1] == [1100, 1234, 125] and not v.camera.busy  # none asked: unchanged
    relay = camera_vehicle(kind=2, trigger_output=False, SERVO12_FUNCTION=90, SERVO13_FUNCTION=91)
    command(relay, mav.MAV_CMD_DO_DIGICAM_CONFIGURE, 0, 125, 1234, 100)
    assert relay.servo_pwm[iso:aperture + 1] == [0, 0]  # only a servo camera drives them

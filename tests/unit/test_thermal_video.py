"""The thermal camera's live video, sans-IO (payload/thermal_palette.py, payload/thermal_video.py) and
as the camera component announces and controls it (mavlink/camera_component.py): the palette's span
and order, the frame schedule in vehicle time, and VIDEO_STREAM_INFORMATION / _STATUS, the video
commands and the HAS_VIDEO_STREAM flag, each command with its one COMMAND_ACK."""
from __future__ import annotations

import math

import numpy as np
import pytest

from firefly.autopilot.mavlink.camera_component import CameraComponent
from firefly.autopilot.mavlink.dialect import mavlink as mav, new_codec
from firefly.autopilot.payload.thermal_camera import ThermalCamera
from firefly.autopilot.payload.thermal_palette import SPAN_C, TABLE, colour, levels, luminance
from firefly.autopilot.payload.thermal_video import FrameSchedule, ThermalVideo
from firefly.sim.fire import Fire, FireWorld
from firefly.sim.thermal_camera import ThermalCameraSpec

from .test_camera_component import SYSTEM, Clock, acks, ask, look_at, wire

URI = "udp://127.0.0.1:5600"


# ----- the palette ---------------------------------------------------------------------------------
def test_the_span_ends_black_and_white_and_clips_outside_it():
    low, high = SPAN_C
    image = np.array([[low - 50.0, low, high, high + 500.0, math.nan]])
    rgb = colour(image)
    assert rgb.shape == (1, 5, 3) and rgb.dtype == np.uint8
    assert rgb[0, 0].tolist() == rgb[0, 1].tolist() == [0, 0, 0] == rgb[0, 4].tolist()  # NaN: the low end
    assert rgb[0, 2].tolist() == rgb[0, 3].tolist() == [255, 255, 255]


def test_hotter_is_never_darker_and_every_degree_tells():
    assert np.all(np.diff(luminance(TABLE)) > 0)  # strictly brighter along the palette
    ramp = np.linspace(*SPAN_C, 101)[np.newaxis, :]  # one pixel per degree across the span
    assert np.all(np.diff(levels(ramp)[0].astype(int)) >= 2)  # 2.55 levels per degree


def test_ambient_ground_is_dark_and_the_models_fire_warm():
    ground, fire = colour(np.array([[22.0, 70.0]]))[0]
    assert luminance(ground) < 40 < 120 < luminance(fire)
    assert fire[0] > fire[2]  # red over blue: a warm colour


# ----- the schedule ----------------------------------------------------------------------------------
def test_a_frame_each_period_of_vehicle_time_without_drift():
    schedule = FrameSchedule(8.7)
    taken = [(step, k) for step in range(100_000) if (k := schedule.take(step * 0.0025)) is not None]
    assert [k for _, k in taken] == list(range(len(taken)))
    assert len(taken) == math.floor(99_999 * 0.0025 * 8.7) + 1  # 250 s of ticks: no frame lost to rounding
    for step, k in taken:  # each at the first tick at or after its instant k / fps
        assert step * 0.0025 >= k / 8.7 - 1e-9 > (step - 1) * 0.0025
    assert schedule.skipped == 0


def test_a_jump_skips_the_frames_passed_and_counts_them():
    schedule = FrameSchedule(10.0)
    assert schedule.take(0.0) == 0 and schedule.take(0.05) is None
    assert schedule.take(0.55) == 5 and schedule.skipped == 4  # 1..4 passed unrendered
    assert schedule.next_s == pytest.approx(0.6)


def test_a_schedule_started_late_starts_at_its_next_instant():
    schedule = FrameSchedule(4.0, start_s=1.1)
    assert schedule.take(1.1) is None and schedule.take(1.25) == 5 and schedule.skipped == 0


@pytest.mark.parametrize("fps", [0.0, -1.0, math.nan, math.inf])
def test_a_schedule_needs_a_positive_rate(fps):
    with pytest.raises(ValueError):
        FrameSchedule(fps)


# ----- the stream as the camera gives it -------------------------------------------------------------
@pytest.fixture
def rig():
    clock = Clock()
    camera = ThermalCamera(ThermalCameraSpec(), FireWorld(fires=(Fire(0.0, 0.0),)), lambda: look_at(clock),
                           lambda: clock.t)
    video = ThermalVideo(camera, URI)
    frames: list = []
    video.on_frame = lambda rgb, index: frames.append((rgb, index))
    return clock, video, CameraComponent(camera, new_codec(SYSTEM), video=video), frames


def test_frames_in_false_colour_at_the_sensors_rate(rig):
    clock, video, component, frames = rig
    for step in range(401):  # 1 s at 400 Hz
        clock.t = step * 0.0025
        if component.due(clock.t):
            component.poll(clock.t)
    assert [k for _, k in frames] == list(range(9))  # 0 .. 8/8.7 s
    rgb = frames[0][0]
    assert rgb.shape == (120, 160, 3) and rgb.dtype == np.uint8
    centre, corner = luminance(rgb[60, 80]), luminance(rgb[0, 0])
    assert centre > corner + 50  # the fire below is brighter than the ground about it
    assert not component.due(clock.t) and video.frames == 9


def test_the_camera_says_it_has_a_stream(rig):
    info = ask(rig[2], mav.MAV_CMD_REQUEST_MESSAGE, mav.MAVLINK_MSG_ID_CAMERA_INFORMATION)[1]
    assert info.flags == mav.CAMERA_CAP_FLAGS_CAPTURE_IMAGE | mav.CAMERA_CAP_FLAGS_HAS_VIDEO_STREAM


@pytest.mark.parametrize("command, params", [
    (mav.MAV_CMD_REQUEST_MESSAGE, (mav.MAVLINK_MSG_ID_VIDEO_STREAM_INFORMATION,)),  # MAVSDK's way
    (mav.MAV_CMD_REQUEST_MESSAGE, (mav.MAVLINK_MSG_ID_VIDEO_STREAM_INFORMATION, 1)),
    (mav.MAV_CMD_REQUEST_VIDEO_STREAM_INFORMATION, (1,)),
])
def test_video_stream_information(rig, command, params):
    got = ask(rig[2], command, *params)
    assert [m.get_type() for m in got] == ["COMMAND_ACK", "VIDEO_STREAM_INFORMATION"]
    assert got[0].result == mav.MAV_RESULT_ACCEPTED
    info = got[1]
    assert (info.stream_id, info.count, info.type, info.encoding) == (
        1, 1, mav.VIDEO_STREAM_TYPE_MPEG_TS, mav.VIDEO_STREAM_ENCODING_H264)
    assert (info.resolution_h, info.resolution_v, info.hfov) == (160, 120, 57)
    assert info.framerate == pytest.approx(8.7) and info.uri == URI and info.name == "thermal"
    assert info.flags == mav.VIDEO_STREAM_STATUS_FLAGS_RUNNING | mav.VIDEO_STREAM_STATUS_FLAGS_THERMAL


def test_stop_and_start_streaming_each_acked_and_seen_in_the_status(rig):
    clock, video, component, frames = rig
    stop = ask(component, mav.MAV_CMD_VIDEO_STOP_STREAMING, 1)
    assert [(m.command, m.result) for m in acks(stop)] == [(mav.MAV_CMD_VIDEO_STOP_STREAMING, mav.MAV_RESULT_ACCEPTED)]
    status = ask(component, mav.MAV_CMD_REQUEST_MESSAGE, mav.MAVLINK_MSG_ID_VIDEO_STREAM_STATUS)
    assert [m.get_type() for m in status] == ["COMMAND_ACK", "VIDEO_STREAM_STATUS"]
    assert status[1].flags == mav.VIDEO_STREAM_STATUS_FLAGS_THERMAL  # not running
    clock.t = 2.0
    assert not video.due(clock.t)
    component.poll(clock.t)
    assert frames == []
    start = ask(component, mav.MAV_CMD_VIDEO_START_STREAMING, 0)
    assert [(m.command, m.result) for m in acks(start)] == [(mav.MAV_CMD_VIDEO_START_STREAMING, mav.MAV_RESULT_ACCEPTED)]
    component.poll(clock.t)
    assert frames == []  # 2.0 s is no frame's instant: the next is frame 18, at 2.069 s
    clock.t = 2.1
    component.poll(clock.t)
    assert [k for _, k in frames] == [18]
    assert video.schedule.skipped == 0  # a stopped stream's instants are not frames lost


@pytest.mark.parametrize("command, params", [
    (mav.MAV_CMD_VIDEO_START_STREAMING, (2,)),
    (mav.MAV_CMD_VIDEO_STOP_STREAMING, (math.nan,)),
    (mav.MAV_CMD_REQUEST_MESSAGE, (mav.MAVLINK_MSG_ID_VIDEO_STREAM_STATUS, 3)),
    (mav.MAV_CMD_REQUEST_VIDEO_STREAM_STATUS, (-1,)),
])
def test_another_stream_id_is_denied(rig, command, params):
    got = ask(rig[2], command, *params)
    assert [(m.command, m.result) for m in acks(got)] == [(command, mav.MAV_RESULT_DENIED)] and len(got) == 1


def test_without_video_the_stream_is_neither_announced_nor_controlled():
    clock = Clock()
    camera = ThermalCamera(ThermalCameraSpec(), FireWorld(), lambda: look_at(clock), lambda: clock.t)
    component = CameraComponent(camera, new_codec(SYSTEM))
    info = ask(component, mav.MAV_CMD_REQUEST_MESSAGE, mav.MAVLINK_MSG_ID_CAMERA_INFORMATION)[1]
    assert info.flags == mav.CAMERA_CAP_FLAGS_CAPTURE_IMAGE
    for command, params, result in [
            (mav.MAV_CMD_REQUEST_MESSAGE, (mav.MAVLINK_MSG_ID_VIDEO_STREAM_INFORMATION,), mav.MAV_RESULT_FAILED),
            (mav.MAV_CMD_REQUEST_VIDEO_STREAM_STATUS, (1,), mav.MAV_RESULT_FAILED),
            (mav.MAV_CMD_VIDEO_START_STREAMING, (1,), mav.MAV_RESULT_UNSUPPORTED)]:
        got = ask(component, command, *params)
        assert [(m.command, m.result) for m in acks(got)] == [(command, result)] and len(got) == 1


def test_the_video_does_not_change_the_stills(rig):
    """The stills' noise is their own: the same still with the video running or not."""
    clock, _, component, _ = rig
    for step in range(40):
        clock.t = step * 0.0025
        component.poll(clock.t)
    ask(component, mav.MAV_CMD_IMAGE_START_CAPTURE, 0, 0, 1)
    plain = ThermalCamera(ThermalCameraSpec(), FireWorld(fires=(Fire(0.0, 0.0),)), lambda: look_at(clock),
                          lambda: clock.t)
    plain.capture()
    assert component.camera.stills[0].data == plain.stills[0].data

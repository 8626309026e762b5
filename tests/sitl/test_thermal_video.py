"""The thermal camera's live video on the real process, as a user's code opens it: pymavlink asks the
camera (component 100) for VIDEO_STREAM_INFORMATION, PyAV opens the uri it gives with one call and
decodes frames of the sensor's size, a frame each 1/fps of vehicle time, with the fire under the
vehicle brighter and warmer in colour than the ground about it; the stream stops and starts on
command. MAVSDK's Camera plugin gets the same stream in its video_stream_info."""
from __future__ import annotations

import json

import av
import numpy as np
import pytest

from firefly.autopilot.mavlink.dialect import mavlink as mav  # MAVLink 2's messages (pymavlink's default is 1)
from firefly.autopilot.payload.thermal_palette import luminance
from groundstation.flight.autopilot_process import free_udp_port

from .pymav import Gcs, take_off
from .test_mavsdk_grpc import first, wait_ready
from .test_thermal_camera import CAMERA, FIRE_SCENARIO, camera_drone  # noqa: F401 - the fixture

pytestmark = [
    pytest.mark.sitl,
    pytest.mark.filterwarnings("ignore:path is deprecated:DeprecationWarning"),
]
FPS = 8.7
OPEN_TIMEOUT_US = "10000000"  # PyAV's udp:// read gives up after this long without a datagram


def frames_of(uri: str, count: int) -> list:
    """The first `count` frames PyAV decodes from the stream at `uri`: (time, RGB array)."""
    out = []
    with av.open(uri, options={"timeout": OPEN_TIMEOUT_US}) as container:
        for frame in container.decode(video=0):
            out.append((frame.time, frame.to_ndarray(format="rgb24")))
            if len(out) == count:
                break
    return out


def test_pymavlink_finds_the_stream_and_pyav_sees_the_fire(autopilot_factory, tmp_path):
    scenario = tmp_path / "fire_here.toml"
    scenario.write_text(FIRE_SCENARIO)
    port = free_udp_port()
    ap = autopilot_factory(extra=("--scenario", str(scenario), "--video-port", str(port)))
    gcs = Gcs(ap.pymavlink_url, timeout=15)
    try:
        take_off(gcs, 20.0)
        gcs.conn.target_component = CAMERA
        result, info = gcs.command_with_reply(mav.MAV_CMD_REQUEST_MESSAGE, "CAMERA_INFORMATION",
                                              mav.MAVLINK_MSG_ID_CAMERA_INFORMATION)
        assert result == mav.MAV_RESULT_ACCEPTED and info.flags & mav.CAMERA_CAP_FLAGS_HAS_VIDEO_STREAM
        result, stream = gcs.command_with_reply(mav.MAV_CMD_REQUEST_MESSAGE, "VIDEO_STREAM_INFORMATION",
                                                mav.MAVLINK_MSG_ID_VIDEO_STREAM_INFORMATION, 1)
        assert result == mav.MAV_RESULT_ACCEPTED and stream.get_srcComponent() == CAMERA
        assert (stream.stream_id, stream.type, stream.encoding) == (
            1, mav.VIDEO_STREAM_TYPE_MPEG_TS, mav.VIDEO_STREAM_ENCODING_H264)
        assert stream.uri == f"udp://127.0.0.1:{port}" and stream.framerate == pytest.approx(FPS)
        assert stream.flags & mav.VIDEO_STREAM_STATUS_FLAGS_RUNNING

        frames = frames_of(stream.uri, 12)  # what a user writes: av.open(uri)
        times = [t for t, _ in frames]
        assert all(rgb.shape == (stream.resolution_v, stream.resolution_h, 3) == (120, 160, 3) for _, rgb in frames)
        steps = np.diff(times) * FPS  # vehicle time: whole frames apart (none lost on loopback: 1 each)
        assert np.allclose(steps, np.round(steps), atol=0.01) and np.all(np.round(steps) >= 1), steps
        while gcs.conn.recv_match(blocking=False) is not None:  # what came while PyAV decoded: old
            pass
        now = gcs.recv("ATTITUDE", 5).time_boot_ms / 1000.0  # the stamps are the vehicle's clock
        assert now - 5.0 < times[-1] <= now, (times[-1], now)
        rgb = frames[-1][1]
        light = luminance(rgb)
        centre = light[50:70, 70:90].mean()  # the fire, under the vehicle
        ground = np.percentile(light, 5)
        assert centre > ground + 60, (centre, ground)
        hot = rgb[50:70, 70:90].reshape(-1, 3).mean(axis=0)
        assert hot[0] > hot[2] + 40, hot  # red over blue: warm

        # stopped: the status says so and no datagram comes; started again: frames again
        assert gcs.command(mav.MAV_CMD_VIDEO_STOP_STREAMING, 1) == mav.MAV_RESULT_ACCEPTED
        result, status = gcs.command_with_reply(mav.MAV_CMD_REQUEST_MESSAGE, "VIDEO_STREAM_STATUS",
                                                mav.MAVLINK_MSG_ID_VIDEO_STREAM_STATUS)
        assert result == mav.MAV_RESULT_ACCEPTED and not status.flags & mav.VIDEO_STREAM_STATUS_FLAGS_RUNNING
        assert gcs.command(mav.MAV_CMD_VIDEO_START_STREAMING, 1) == mav.MAV_RESULT_ACCEPTED
        assert len(frames_of(stream.uri, 3)) == 3
        assert gcs.command(mav.MAV_CMD_VIDEO_START_STREAMING, 2) == mav.MAV_RESULT_DENIED  # no stream 2
    finally:
        gcs.close()
    ap.stop()  # its exit report counts what the video did
    counters = json.loads((tmp_path / "exit-report-0.json").read_text())["vehicles"][0]["counters"]
    assert counters["video_frames"] > 15 and counters["video_frames"] == counters["video_rendered"]
    assert counters["video_encoder_errors"] == counters["video_send_errors"] == 0


async def test_mavsdk_video_stream_info(camera_drone):  # noqa: F811 - the fixture imported above
    drone = camera_drone
    await wait_ready(drone)
    update = await first(drone.camera.video_stream_info(), lambda u: u.component_id == CAMERA, 30,
                         "the thermal camera's video stream info")
    info = update.video_stream_info
    settings = info.settings
    assert info.stream_id == 1 and settings.uri == "udp://127.0.0.1:5600"
    assert (settings.horizontal_resolution_pix, settings.vertical_resolution_pix) == (160, 120)
    assert settings.frame_rate_hz == pytest.approx(FPS) and settings.horizontal_fov_deg == 57
    assert info.status == info.status.IN_PROGRESS and info.spectrum == info.spectrum.INFRARED

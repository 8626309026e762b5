"""The thermal camera on the real process, as clients use it: MAVSDK's Camera plugin (through its
gRPC server) finds component 100, takes a photo and gets its capture_info with a geotag where the
vehicle is, then fetches the still with MAVSDK's Ftp plugin; pymavlink flies over a fire, takes a
still and downloads it by MAVLink FTP from the camera, and the TIFF is radiometric: the ground at
the ambient temperature, the fire tens of degrees hotter, where the camera looked."""
from __future__ import annotations

import asyncio
import io
import math
import struct

import numpy as np
import pytest
from pymavlink import mavutil

from firefly.sim.thermal_still import load_radiometric

from .pymav import Gcs, take_off
from .test_mavsdk_grpc import M_PER_DEG_LAT, call, connected_system, first, wait_ready

pytestmark = [
    pytest.mark.sitl,
    pytest.mark.filterwarnings("ignore:path is deprecated:DeprecationWarning"),
]
mav = mavutil.mavlink
CAMERA = mav.MAV_COMP_ID_CAMERA
AMBIENT_C, FIRE_K = 22.0, 50.0
FIRE_SCENARIO = f"""
[world]
ambient_c = {AMBIENT_C}
[[fire]]
n_m = 0.0
e_m = 0.0
strength_k = {FIRE_K}
[thermal_camera]
"""


@pytest.fixture
async def camera_drone(autopilot_factory):
    """A connected mavsdk_grpc System of an autopilot with the thermal camera; its mavsdk_server
    stopped after the test (the generator runs to its end here)."""
    ap = autopilot_factory(extra=("--thermal-camera",))
    async for system in connected_system(ap.mavsdk_url):
        yield system


async def test_mavsdk_takes_a_photo_geotagged_where_the_vehicle_is(camera_drone, tmp_path):
    drone = camera_drone
    await wait_ready(drone)
    cameras = await first(drone.camera.camera_list(), lambda c: any(i.component_id == CAMERA for i in c.cameras),
                          30, "the thermal camera in the camera list")
    info = next(i for i in cameras.cameras if i.component_id == CAMERA)
    assert (info.horizontal_resolution_px, info.vertical_resolution_px) == (160, 120)
    assert info.vendor_name == "Firefly"
    where = await first(drone.telemetry.position(), lambda p: True, 10, "the vehicle's position")
    capture = await _photo(drone)
    assert capture.is_success
    assert capture.file_url == f"mftp://DCIM/IR_{capture.index:04d}.tif"
    north = (capture.position.latitude_deg - where.latitude_deg) * M_PER_DEG_LAT
    east = ((capture.position.longitude_deg - where.longitude_deg) * M_PER_DEG_LAT
            * math.cos(math.radians(where.latitude_deg)))
    assert math.hypot(north, east) < 1.0
    assert abs(capture.position.absolute_altitude_m - where.absolute_altitude_m) < 1.0
    assert abs(capture.position.relative_altitude_m) < 0.5
    # A fixed camera looking straight down: its optical axis is pitched -90 deg
    assert capture.attitude_euler_angle.pitch_deg == pytest.approx(-90.0, abs=3.0)
    # The still, fetched as the file_url says: MAVLink FTP from the camera component
    await call(drone.ftp.set_target_compid(CAMERA))
    name = capture.file_url.removeprefix("mftp://")
    await asyncio.wait_for(_download(drone, name, tmp_path), 60)
    image, geotag = load_radiometric(tmp_path / name.split("/")[-1])
    assert image.shape == (120, 160) and image.dtype == np.float32
    assert geotag.lat_deg == pytest.approx(capture.position.latitude_deg, abs=1e-6)


async def _photo(drone, attempts: int = 3):
    """take_photo and the capture_info it brings. The capture_info stream replays nothing, and its
    subscription reaches mavsdk_server some time after the call: a photo taken before that is not
    seen, so another is taken (its index then says which)."""
    for _ in range(attempts):
        waiting = asyncio.ensure_future(first(drone.camera.capture_info(), lambda c: c.component_id == CAMERA,
                                              5, "capture_info"))
        await call(drone.camera.take_photo(CAMERA))
        try:
            return await waiting
        except AssertionError:
            continue
    raise AssertionError(f"no capture_info after {attempts} photos")


async def _download(drone, path: str, local_dir) -> None:
    """The whole download: the stream ends on MAVSDK's SUCCESS, once the file is written (a
    progress of all bytes comes before the file is closed)."""
    async for _ in drone.ftp.download(path, str(local_dir), False):
        pass


class CameraFtp:
    """A minimal MAVLink FTP client of component 100: OpenFileRO, ReadFile to the end."""
    HEADER = struct.Struct("<HBBBBBxI")

    def __init__(self, gcs: Gcs):
        self.gcs, self.seq = gcs, 0

    def request(self, opcode: int, session: int = 0, offset: int = 0, data: bytes = b"", size: int | None = None):
        self.seq += 1
        payload = self.HEADER.pack(self.seq, session, opcode, len(data) if size is None else size, 0, 0, offset) + data
        gcs = self.gcs
        gcs.mav.file_transfer_protocol_send(0, gcs.conn.target_system, CAMERA, list(payload.ljust(251, b"\0")))
        reply = gcs.recv("FILE_TRANSFER_PROTOCOL", 5, lambda m: m.get_srcComponent() == CAMERA
                         and self.HEADER.unpack_from(bytes(m.payload))[0] == self.seq + 1)
        assert reply is not None, f"no FTP reply to opcode {opcode}"
        raw = bytes(reply.payload)
        _, session, op, size, _, _, _ = self.HEADER.unpack_from(raw)
        self.seq += 1
        return op, session, raw[12:12 + size]

    def read(self, path: str) -> bytes:
        op, session, data = self.request(4, data=path.encode())  # OpenFileRO
        assert op == 128, f"open refused: {data!r}"
        size = struct.unpack("<I", data)[0]
        out = b""
        while len(out) < size:
            op, _, data = self.request(5, session, offset=len(out), size=239)  # ReadFile
            assert op == 128, f"read refused at {len(out)}: {data!r}"
            out += data
        self.request(1, session)  # TerminateSession
        return out


def test_pymavlink_downloads_a_radiometric_still_of_the_fire(autopilot_factory, tmp_path):
    scenario = tmp_path / "fire_here.toml"
    scenario.write_text(FIRE_SCENARIO)
    ap = autopilot_factory(extra=("--scenario", str(scenario)))
    gcs = Gcs(ap.pymavlink_url, timeout=15)
    try:
        take_off(gcs, 20.0)
        pos = gcs.recv("GLOBAL_POSITION_INT", 5)
        gcs.conn.target_component = CAMERA
        result, captured = gcs.command_with_reply(mav.MAV_CMD_IMAGE_START_CAPTURE, "CAMERA_IMAGE_CAPTURED", 0, 0, 1)
        assert result == mav.MAV_RESULT_ACCEPTED and captured.capture_result == 1
        assert captured.get_srcComponent() == CAMERA
        assert abs(captured.lat - pos.lat) < 50 and abs(captured.lon - pos.lon) < 50  # some 0.5 m
        assert abs(captured.relative_alt - 20_000) < 1_000
        # a bad request: one answer, DENIED (an interval of 0 for more than one still)
        assert gcs.command(mav.MAV_CMD_IMAGE_START_CAPTURE, 0, 0, 5) == mav.MAV_RESULT_DENIED
        data = CameraFtp(gcs).read(captured.file_url.removeprefix("mftp://"))
    finally:
        gcs.close()
    image, geotag = load_radiometric(io.BytesIO(data))
    assert image.shape == (120, 160)
    # the ground away from the fire (the image's coolest twentieth; the radiant kernel's tails warm
    # the rest by a few degrees) at the ambient temperature
    background = float(np.percentile(image, 5))
    assert abs(background - AMBIENT_C) < 2.0, background
    peak = np.unravel_index(int(np.argmax(image)), image.shape)
    assert image[peak] > AMBIENT_C + 0.5 * FIRE_K, image[peak]  # over the fire: tens of degrees hotter
    # the fire is under the vehicle: near the image's centre (20 m up: 14 cm a pixel)
    assert abs(peak[0] - 60) < 15 and abs(peak[1] - 80) < 15, peak
    assert geotag.lat_deg == pytest.approx(captured.lat * 1e-7, abs=1e-6)


def test_cam1_type_6_drives_the_thermal_camera_from_the_autopilot(autopilot_factory):
    """As ArduCopter's AP_Camera with CAM1_TYPE 6: the autopilot's own picture command goes to the
    camera; the autopilot reports CAMERA_FEEDBACK and the camera its CAMERA_IMAGE_CAPTURED."""
    ap = autopilot_factory(extra=("--thermal-camera", "--param", "CAM1_TYPE=6"))
    gcs = Gcs(ap.pymavlink_url, timeout=15)
    try:
        assert gcs.conn.target_component == 1
        assert gcs.command(mav.MAV_CMD_DO_DIGICAM_CONTROL, 0, 0, 0, 0, 1) == mav.MAV_RESULT_ACCEPTED
        got: dict = {}
        while len(got) < 2:  # both, in whichever order they come
            msg = gcs.recv(["CAMERA_FEEDBACK", "CAMERA_IMAGE_CAPTURED"], 5)
            assert msg is not None, f"only {sorted(got)}"
            got.setdefault(msg.get_type(), msg)
        feedback, captured = got["CAMERA_FEEDBACK"], got["CAMERA_IMAGE_CAPTURED"]
        assert feedback is not None and feedback.img_idx == 1 and feedback.get_srcComponent() == 1
        assert captured is not None and captured.get_srcComponent() == CAMERA and captured.image_index == 0
    finally:
        gcs.close()

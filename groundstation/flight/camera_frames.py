"""The camera search's frames, flown: the vehicle's thermal camera (MAVLink component 100, camera
protocol v2; docs/thermal_camera.md) takes a still at each observation point, and its radiometric
TIFF reaches the search controller as the decision-level episodes' frames do.

One still at a time: after each new observation the companion sends IMAGE_START_CAPTURE (one still)
to component 100, waits for the CAMERA_IMAGE_CAPTURED of a new image index, downloads the file its
file_url names by MAVLink FTP from the camera itself (MAVSDK's Ftp plugin, burst reads), reads it
(sim/thermal_still.py, tifffile) and hands the frame to the controller (camera_view.frame_from_image,
as the episodes do). The footprint is the geotag's: CAMERA_IMAGE_CAPTURED's position (the
autopilot's estimate at the capture instant, as a real camera's) and its quaternion, the camera's
axes to north-east-down. A still whose capture is slower than the next observation makes that
observation go without one: frames never queue up behind the vehicle.

The vehicle holds its heading while the camera flies (WP_YAW_BEHAVIOR 0, its old value put back
after the flight): ArduCopter's default turns the nose, and with it a fixed camera's frame, along
each leg, and a frame turned 45 degrees keeps only some 40 % of its ground for the search (frame.py
judges the axis-aligned rectangle inside it). Held at the take-off heading (north in Firefly's
scenarios), every frame is whole but for the lean of its flight.

The link's cost is measured per frame: wall time from the request to the frame in the belief, and
vehicle time from the capture to the same moment (how far the vehicle flew meanwhile).
"""
from __future__ import annotations

import asyncio
import json
import math
import tempfile
import time
from pathlib import Path

import numpy as np
from mavsdk.asyncio.plugins.ftp import FtpAsync
from mavsdk.asyncio.plugins.mavlink_direct import MavlinkMessage
from mavsdk.asyncio.plugins.param import ParamAsync

from firefly.sim.thermal_camera import CameraPose, ThermalCameraSpec
from firefly.sim.thermal_still import load_radiometric

from ..camera_view import frame_from_image
from .vehicle_link import LinkError

CAMERA_COMPONENT = 100  # MAV_COMP_ID_CAMERA
IMAGE_START_CAPTURE = 2000
CAPTURE_WAIT_S = 5.0   # wall seconds for a still's CAMERA_IMAGE_CAPTURED
DOWNLOAD_WAIT_S = 15.0  # ... and for its download
HOLD_HEADING = ("WP_YAW_BEHAVIOR", 0)  # ArduCopter's "never change yaw" in AUTO/GUIDED/RTL


def rotation_of(q) -> np.ndarray:
    """The rotation matrix of a unit quaternion (w, x, y, z)."""
    w, x, y, z = (float(v) for v in q)
    norm = math.sqrt(w * w + x * x + y * y + z * z)
    if not norm > 0:
        raise ValueError(f"not a quaternion: {q!r}")
    w, x, y, z = w / norm, x / norm, y / norm, z / norm
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


class FlightCamera:
    """Takes, fetches and reads the stills; `frames` the footprints used (n_lo, n_hi, e_lo, e_hi)."""

    def __init__(self, link, direct, survey, spec: ThermalCameraSpec = ThermalCameraSpec()):
        self.link, self.direct, self.survey, self.spec = link, direct, survey, spec
        self.ftp = FtpAsync(link.system)
        self.captured: asyncio.Queue = asyncio.Queue()
        self.observed = asyncio.Event()  # set by the survey at each new observation
        self.frames: list[tuple] = []
        self.wall_ms: list[float] = []     # request to frame in the belief
        self.vehicle_ms: list[float] = []  # capture to frame in the belief, vehicle time
        self.think_ms: list[float] = []    # the frame's reduction and likelihood
        self.download_ms: list[float] = []  # of which the MAVLink FTP download, wall time
        self.missed = 0  # observations that went without a still (one was still on its way)
        self._last_index = -1
        self._dir = tempfile.TemporaryDirectory(prefix="firefly-stills-")

    async def hold_heading(self) -> int:
        """Set WP_YAW_BEHAVIOR to hold the heading; its old value, for restore_heading."""
        param = ParamAsync(self.link.system)
        name, value = HOLD_HEADING
        old = await param.get_param_int(name)
        await param.set_param_int(name, value)
        return old

    async def restore_heading(self, old: int) -> None:
        await ParamAsync(self.link.system).set_param_int(HOLD_HEADING[0], old)

    def on_captured(self, fields: dict) -> None:
        """A CAMERA_IMAGE_CAPTURED from the camera (the Feed's handler)."""
        self.captured.put_nowait(fields)

    def on_observation(self) -> None:
        if self.observed.is_set():
            self.missed += 1
        self.observed.set()

    async def run(self) -> None:
        await self.ftp.set_target_compid(CAMERA_COMPONENT)
        self.system_id = await self.link.system.get_system_id()
        try:
            while True:
                await self.observed.wait()
                self.observed.clear()
                if not self.survey.active:
                    continue
                await self.one_frame()
        finally:
            self._dir.cleanup()

    async def one_frame(self) -> None:
        wall0 = time.monotonic()
        fields = {"target_system": self.system_id, "target_component": CAMERA_COMPONENT,
                  "command": IMAGE_START_CAPTURE, "confirmation": 0, "param1": 0.0, "param2": 0.0,
                  "param3": 1.0, "param4": 0.0, "param5": 0.0, "param6": 0.0, "param7": 0.0}
        try:
            ack = await asyncio.wait_for(self.direct.send_command(MavlinkMessage(
                "COMMAND_LONG", 0, 0, self.system_id, CAMERA_COMPONENT, json.dumps(fields))), CAPTURE_WAIT_S)
        except Exception as exc:  # noqa: BLE001 - a timeout, or MAVSDK's own error for an unanswered command
            raise LinkError(f"no answer from the camera (component {CAMERA_COMPONENT}) to IMAGE_START_CAPTURE "
                            f"({type(exc).__name__}): is the vehicle fitted with one?") from None
        result = json.loads(ack.fields_json).get("result") if ack.fields_json else None
        if result != 0:
            raise LinkError(f"the camera refused IMAGE_START_CAPTURE: result {result}")
        capture = await self._next_capture()
        if int(capture["capture_result"]) != 1:
            raise LinkError(f"the camera's still {capture['image_index']} failed")
        name = str(capture["file_url"]).rstrip("\0").removeprefix("mftp://")
        fetch0 = time.monotonic()
        try:
            await asyncio.wait_for(self._download(name), DOWNLOAD_WAIT_S)
        except asyncio.TimeoutError:
            raise LinkError(f"no download of {name} within {DOWNLOAD_WAIT_S:g} s") from None
        self.download_ms.append(1000.0 * (time.monotonic() - fetch0))
        image, _ = load_radiometric(Path(self._dir.name) / name.split("/")[-1])
        if image.shape != (self.spec.height_px, self.spec.width_px):
            raise LinkError(f"a still of {image.shape[1]} x {image.shape[0]} pixels, "
                            f"not the {self.spec.width_px} x {self.spec.height_px} the search expects")
        n, e = self.link.north_east_of(capture["lat"] * 1e-7, capture["lon"] * 1e-7)
        pose = CameraPose(n, e, capture["relative_alt"] / 1000.0, rotation_of(capture["q"]))
        controller = self.survey.controller
        if not self.survey.active:
            return
        t0 = time.perf_counter()
        frame = frame_from_image(image, self.spec, pose)
        controller.observe_frame(frame)
        self.think_ms.append(1000.0 * (time.perf_counter() - t0))
        self.frames.append((frame.n_lo, frame.n_hi, frame.e_lo, frame.e_hi))
        self.wall_ms.append(1000.0 * (time.monotonic() - wall0))
        self.vehicle_ms.append(float(self.survey.vehicle_t_ms - int(capture["time_boot_ms"])))

    async def _next_capture(self) -> dict:
        """The CAMERA_IMAGE_CAPTURED of a still newer than the last one used."""
        while True:
            try:
                capture = await asyncio.wait_for(self.captured.get(), CAPTURE_WAIT_S)
            except asyncio.TimeoutError:
                raise LinkError(f"no CAMERA_IMAGE_CAPTURED within {CAPTURE_WAIT_S:g} s of a capture") from None
            if int(capture["image_index"]) > self._last_index:
                self._last_index = int(capture["image_index"])
                return capture

    async def _download(self, name: str) -> None:
        async for _ in self.ftp.download(name, self._dir.name, True):
            pass

    def summary(self) -> dict:
        """Frames read, observation points without one, and what a frame cost (ms)."""
        def mean(xs):
            return float(np.mean(xs)) if xs else math.nan
        return {"frames": len(self.frames), "frames_missed": self.missed,
                "frame_wall_ms_mean": mean(self.wall_ms), "frame_wall_ms_max": max(self.wall_ms, default=math.nan),
                "frame_download_ms_mean": mean(self.download_ms),
                "frame_vehicle_ms_mean": mean(self.vehicle_ms),
                "frame_vehicle_ms_max": max(self.vehicle_ms, default=math.nan),
                "frame_ms_mean": mean(self.think_ms), "frame_ms_max": max(self.think_ms, default=math.nan)}

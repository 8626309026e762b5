"""The thermal camera's live video, sans-IO: which frames to make and when, and making them. The I/O
edge (io/thermal_video.py) encodes each frame it is handed (H.264 in MPEG-TS) and sends it by UDP.

Time is vehicle time only: frame k belongs to the instant k / fps of the vehicle's clock (fps the
sensor's frame rate), and its timestamp in the stream is that instant. The loop asks at each tick;
when it runs faster than real time, or flat out, frames come as fast as the machine renders and
encodes them, still one per 1/fps of vehicle time. A frame whose instant has passed unrendered (the
clock jumped past it) is skipped and counted, never made late.

Each frame is rendered from the vehicle's true pose (as the stills are) with readout noise from its
own random stream, so the stills a user takes are the same with the video on or off.
"""
from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from firefly.sim.thermal_camera import render

from .thermal_palette import colour

EPS_S = 1e-9
STREAM_ID = 1  # the camera's one stream
NAME = "thermal"
BIT_RATE = 300_000  # what the encoder aims at [bit/s]: 160x120 at 8.7 Hz looks clean well below it


class FrameSchedule:
    """Frame k at k * period of vehicle time (exact multiples: no drift from adding periods)."""

    def __init__(self, fps: float, start_s: float = 0.0):
        if not (math.isfinite(fps) and fps > 0):
            raise ValueError(f"fps must be positive, got {fps!r}")
        self.fps = fps
        self.next_index = max(0, math.ceil(start_s * fps - EPS_S))
        self.skipped = 0

    @property
    def next_s(self) -> float:
        return self.next_index / self.fps

    def take(self, now_s: float) -> int | None:
        """The frame due at now_s (its index), or None; a later frame due at once skips those before it."""
        if now_s + EPS_S < self.next_s:
            return None
        index = math.floor(now_s * self.fps + EPS_S)
        self.skipped += index - self.next_index
        self.next_index = index + 1
        return index


class ThermalVideo:
    """The stream of a ThermalCamera (payload/thermal_camera.py): running from the start, stopped
    and started again by MAV_CMD_VIDEO_STOP/START_STREAMING. `on_frame(rgb, index)` is the I/O
    edge's encoder; without one nothing is rendered."""

    def __init__(self, camera, uri: str, seed: int = 0):
        self.camera = camera
        self.uri = uri
        self.spec = camera.spec
        self.bit_rate = BIT_RATE
        self.rng = np.random.default_rng([seed, 0x71D])  # not the stills' stream
        self.running = True
        self.schedule = FrameSchedule(self.spec.frame_rate_hz, camera.now())
        self.on_frame: Callable[[np.ndarray, int], None] | None = None
        self.edge_counters: dict = {}  # the encoder's and the socket's (frames sent, errors)
        self.frames = 0

    def restart(self) -> None:
        """The vehicle's clock starts again (a reboot of the autopilot): frames from its new now."""
        self.schedule = FrameSchedule(self.spec.frame_rate_hz, self.camera.now())

    def start(self) -> None:
        if not self.running:
            self.running = True
            self.restart()

    def stop(self) -> None:
        self.running = False

    def due(self, now_s: float) -> bool:
        return self.running and self.on_frame is not None and now_s + EPS_S >= self.schedule.next_s

    def tick(self) -> None:
        """Make the frame due now, if one is, and hand it to the encoder."""
        if not self.running or self.on_frame is None:
            return
        now = self.camera.now()
        index = self.schedule.take(now)
        if index is None:
            return
        image = render(self.camera.world, self.spec, self.camera.look().truth, self.rng, now)
        self.frames += 1
        self.on_frame(colour(image), index)

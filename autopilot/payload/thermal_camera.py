"""The thermal camera as a device on the vehicle: it takes radiometric stills (sim/thermal_camera.py
renders them, sim/thermal_still.py writes them as TIFFs) at sim instants, singly or at an interval,
and keeps them on its card with their geotag. No MAVLink here: mavlink/camera_component.py speaks
for it, and the I/O edge may copy each still to disk (io/thermal_stills.py).

Where a still is taken from: the world renders the truth (the simulated vehicle's position and
attitude), while the geotag is what the camera would be told by the autopilot, its estimate (as
GLOBAL_POSITION_INT and ATTITUDE say it), the way a real camera geotags from the flight controller.
The camera looks where the autopilot's mount points it when a mount is fitted (MNT1_TYPE), and
straight down otherwise (a camera fixed under the frame).

Time is sim time only: an interval capture takes its first still at once, then one each interval
after; when the loop runs flat out, stills come as fast as the machine renders them.
"""
from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from firefly.sim.rigid_body import euler_from_quaternion
from firefly.sim.thermal_camera import CameraPose, ThermalCameraSpec, pose_from_attitude, render
from firefly.sim.thermal_still import Geotag, radiometric_bytes

CARD_BYTES = 32 * 1024 * 1024  # the card: some 400 stills of 160x120 (77 kB each)
MIB = 1024 * 1024
DOWN_DEG = -90.0  # a fixed camera's pitch: straight down


@dataclass(frozen=True)
class Look:
    """What a capture needs at its instant: the true pose the world renders from, and what the
    autopilot says (the geotag): position in 1e-7 degrees and millimetres, and the camera's attitude
    as a quaternion (w, x, y, z) from its axes (optical axis, image right, image down) to NED."""
    truth: CameraPose
    geotag: Geotag
    lat_e7: int
    lon_e7: int
    alt_mm: int  # AMSL
    relative_alt_mm: int  # above home
    q: tuple
    time_boot_ms: int
    time_utc_us: int


@dataclass(frozen=True)
class Still:
    index: int  # 0-based, as CAMERA_IMAGE_CAPTURED's image_index
    name: str  # on the card
    data: bytes  # the radiometric TIFF
    look: Look
    ok: bool = True  # False: the capture failed (the card was full); no file


def quaternion_of(rotation: np.ndarray) -> tuple:
    """(w, x, y, z) of a rotation matrix (Shepperd's method: the largest of the four first)."""
    m = rotation
    trace = m[0, 0] + m[1, 1] + m[2, 2]
    if trace > 0:
        s = 2.0 * math.sqrt(1.0 + trace)
        q = (0.25 * s, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s)
    elif m[0, 0] > m[1, 1] and m[0, 0] > m[2, 2]:
        s = 2.0 * math.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2])
        q = ((m[2, 1] - m[1, 2]) / s, 0.25 * s, (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s)
    elif m[1, 1] > m[2, 2]:
        s = 2.0 * math.sqrt(1.0 + m[1, 1] - m[0, 0] - m[2, 2])
        q = ((m[0, 2] - m[2, 0]) / s, (m[0, 1] + m[1, 0]) / s, 0.25 * s, (m[1, 2] + m[2, 1]) / s)
    else:
        s = 2.0 * math.sqrt(1.0 + m[2, 2] - m[0, 0] - m[1, 1])
        q = ((m[1, 0] - m[0, 1]) / s, (m[0, 2] + m[2, 0]) / s, (m[1, 2] + m[2, 1]) / s, 0.25 * s)
    sign = -1.0 if q[0] < 0 else 1.0  # w >= 0: one of the two equal quaternions, always the same
    return tuple(float(sign * c) for c in q)


def look_of(vehicle) -> Look:
    """The vehicle's pose for a capture now: the sim's truth and the autopilot's estimate."""
    sim = vehicle.sim
    b = sim.state.body
    roll, pitch, yaw = euler_from_quaternion(b.qw, b.qx, b.qy, b.qz)
    mount = vehicle.mount
    if mount.fitted:  # body-frame angles the mount puts out
        _, g_pitch, g_yaw = (math.degrees(a) for a in mount.output)
    else:
        g_pitch, g_yaw = DOWN_DEG, 0.0
    ground_d = vehicle.height_ref_d
    truth = pose_from_attitude(b.n_m, b.e_m, ground_d - b.d_m, math.degrees(roll), math.degrees(pitch),
                               math.degrees(yaw), g_pitch, g_yaw)
    e_roll, e_pitch, e_yaw = (math.degrees(a) for a in vehicle.attitude)
    told = pose_from_attitude(0.0, 0.0, 1.0, e_roll, e_pitch, e_yaw, g_pitch, g_yaw)
    pos = vehicle.position_global()
    home = vehicle.home
    home_alt = home.alt_m if home else vehicle.origin.alt_m
    utc_us = vehicle.unix_time_us()
    geotag = Geotag(pos.lat_deg, pos.lon_deg, pos.alt_m, e_roll, e_pitch, e_yaw % 360.0, g_pitch, g_yaw,
                    utc_us * 1e-6)
    return Look(truth, geotag, round(pos.lat_deg * 1e7), round(pos.lon_deg * 1e7), round(pos.alt_m * 1000),
                round((pos.alt_m - home_alt) * 1000), quaternion_of(told.rotation),
                int(vehicle.time_s * 1000) & 0xFFFFFFFF, utc_us)


class ThermalCamera:
    """Stills on a card of CARD_BYTES, numbered from 0 since the card was last formatted."""

    def __init__(self, spec: ThermalCameraSpec, world, look: Callable[[], Look], now: Callable[[], float],
                 seed: int = 0, card_bytes: int = CARD_BYTES):
        self.spec = spec
        self.world = world
        self.look = look
        self.now = now  # sim time [s]
        self.rng = np.random.default_rng([seed, 0x7E])  # its own readout noise, not the sensors'
        self.card_bytes = card_bytes
        self.stills: list[Still] = []  # what the card holds, by index
        self.used_bytes = 0
        self.interval_s = 0.0  # of the interval capture running; 0: none
        self.left = 0  # stills the interval capture still takes; -1: until stopped
        self.next_s = math.inf  # sim time of its next still
        self.fresh: list[Still] = []  # taken since the last take_fresh (to announce)
        self.on_still: Callable[[Still], None] | None = None  # the I/O edge's copy to disk
        self.on_format: Callable[[], None] | None = None

    @property
    def interval_running(self) -> bool:
        return self.left != 0

    @property
    def still_bytes(self) -> int:
        """What one still takes on the card: the pixels as float32 and the TIFF's few hundred bytes."""
        return self.spec.width_px * self.spec.height_px * 4 + 1024

    @property
    def full(self) -> bool:
        return self.used_bytes + self.still_bytes > self.card_bytes

    def capture(self) -> Still:
        """One still now (a failed one, with no file, when the card is full)."""
        look = self.look()
        index = len(self.stills)
        name = f"IR_{index:04d}.tif"
        if self.full:
            still = Still(index, name, b"", look, ok=False)
        else:
            image = render(self.world, self.spec, look.truth, self.rng, self.now())
            still = Still(index, name, radiometric_bytes(image, look.geotag), look)
            self.used_bytes += len(still.data)
            if self.on_still is not None:
                self.on_still(still)
        self.stills.append(still)
        self.fresh.append(still)
        return still

    def start(self, interval_s: float, count: int) -> None:
        """count 1: one still now; else one now and then every interval_s, count in all (0: until
        stopped). A capture running is replaced."""
        self.stop()
        if count == 1:
            self.capture()
            return
        self.interval_s, self.left = interval_s, (count if count > 0 else -1)
        self.next_s = self.now()
        self.tick()

    def stop(self) -> None:
        self.interval_s, self.left, self.next_s = 0.0, 0, math.inf

    def tick(self) -> None:
        """Take the interval's stills that are due by now (sim time)."""
        now = self.now()
        while self.left != 0 and self.next_s <= now + 1e-9:
            try:
                still = self.capture()
            except Exception:  # a bug ends the series, or every poll would meet it again
                self.stop()
                raise
            if self.left > 0:
                self.left -= 1
            self.next_s += self.interval_s
            if not still.ok:
                self.stop()  # a full card ends the series
        if self.left == 0:
            self.stop()

    def format(self) -> None:
        self.stop()
        self.stills, self.used_bytes, self.fresh = [], 0, []
        if self.on_format is not None:
            self.on_format()

    def take_fresh(self) -> list[Still]:
        fresh, self.fresh = self.fresh, []
        return fresh

    def still(self, index: int) -> Still | None:
        return self.stills[index] if 0 <= index < len(self.stills) else None

    def file(self, name: str) -> Still | None:
        for still in self.stills:
            if still.ok and still.name == name:
                return still
        return None

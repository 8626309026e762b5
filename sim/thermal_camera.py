"""The radiometric thermal camera: an imager that sees a footprint of many cells at once.

A pure function of the fire world and the camera's pose (docs/thermal_camera.md): for each pixel the
ray through its centre (pinhole model, square pixels) meets the flat ground, or the sky if it points
at or above the horizon. What the camera sees there:
- ground: fire.py's temperature field (temperature_field, the point sensor's model) evaluated at the
  pixel's ground point for a layer `emission_height_m` above the ground — the flames and the base of
  the plume. So the hot spot has the kernel's shape at that height and leans downwind by
  wind_tilt * emission_height_m, as fire.py's model says of a plume at that height. (The ray's
  parallax inside that thin layer, at most emission_height_m * tan(off-nadir angle), is neglected:
  each pixel's reading belongs to its ground point, which the footprint helper gives.)
- sky: one documented brightness temperature, sky_c.
Then the optics blur it (a Gaussian point spread function) and the readout adds per-pixel Gaussian
noise of sigma NETD. Vectorised numpy; no MAVLink, no autopilot: the caller gives the pose.

Frames: world north/east/down (NED) metres, altitude up from the flat ground. The camera's own axes
are x along the optical axis, y toward the image's right, z toward the image's bottom; its attitude is
the rotation from those axes to NED. Pixel (row, col) = (0, 0) is the image's top-left.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .fire import FireWorld, temperature_field

LENS_ABOVE_GROUND_M = 0.05  # a pose at or below the ground is taken as resting on it, the lens this high


# The largest side a frame may have: past the thermal cores sold today (1280 x 1024) with room,
# and a frame that still renders in memory (MAVLink's uint16 resolution fields would take more).
MAX_SIDE_PX = 4096


@dataclass(frozen=True)
class ThermalCameraSpec:
    """A small radiometric long-wave infrared core. The defaults are a FLIR Lepton 3.5-class sensor,
    from FLIR's public Lepton engineering datasheet: a 160 x 120 pixel array, the 57 deg horizontal
    field of view configuration, the export-compliant frame rate (under 9 Hz: a new frame every
    third of its 26 Hz readout, 8.7 Hz) and a thermal sensitivity (NETD) under 50 mK. The others
    are this model's choices, not datasheet figures (see each)."""
    width_px: int = 160
    height_px: int = 120
    hfov_deg: float = 57.0
    frame_rate_hz: float = 8.7  # how often a caller may render; render() itself draws one frame
    netd_k: float = 0.05  # readout noise, one sigma per pixel per frame
    # Optical blur, sigma in pixels: about the diffraction spot of an f/1.1 lens at 10 um on a 12 um
    # pixel (Airy first-dark radius 1.22 * lambda * N = 13 um), rounded to one pixel. 0 = none.
    psf_sigma_px: float = 1.0
    # What a ray at or above the horizon reads: a clear sky's brightness temperature in the 8-14 um
    # band is tens of degrees below the air's; -20 C is a typical mid-latitude figure.
    sky_c: float = -20.0
    # The burning layer the camera sees (flames, the plume's base): fire.py's field at this height.
    # Flame lengths of grass and shrub fires are of this order (1-3 m).
    emission_height_m: float = 2.0

    def __post_init__(self) -> None:
        for name in ("width_px", "height_px"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not 0 < value <= MAX_SIDE_PX:
                raise ValueError(f"{name} must be a whole number of pixels in 1..{MAX_SIDE_PX}, got {value!r}")
        if not (math.isfinite(self.hfov_deg) and 0.0 < self.hfov_deg < 180.0):
            raise ValueError(f"hfov_deg must be within (0, 180) degrees, got {self.hfov_deg!r}")
        for name in ("frame_rate_hz",):
            if not (math.isfinite(getattr(self, name)) and getattr(self, name) > 0):
                raise ValueError(f"{name} must be positive, got {getattr(self, name)!r}")
        for name in ("netd_k", "psf_sigma_px", "emission_height_m"):
            if not (math.isfinite(getattr(self, name)) and getattr(self, name) >= 0):
                raise ValueError(f"{name} must be zero or positive, got {getattr(self, name)!r}")
        if not math.isfinite(self.sky_c):
            raise ValueError(f"sky_c must be a finite temperature, got {self.sky_c!r}")

    @property
    def focal_px(self) -> float:
        """The pinhole's focal length in pixels: half the width over tan(half the horizontal fov)."""
        return 0.5 * self.width_px / math.tan(math.radians(self.hfov_deg) / 2.0)

    @property
    def vfov_deg(self) -> float:
        return math.degrees(2.0 * math.atan(0.5 * self.height_px / self.focal_px))


@dataclass(frozen=True, eq=False)  # an array inside: compared by identity
class CameraPose:
    """Where the camera is (north, east metres; altitude above the flat ground) and its attitude:
    `rotation` takes camera axes (optical axis, image right, image down) to north/east/down."""
    n_m: float
    e_m: float
    alt_m: float
    rotation: np.ndarray

    def __post_init__(self) -> None:
        for name in ("n_m", "e_m", "alt_m"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"{name} must be finite, got {getattr(self, name)!r}")
        r = np.asarray(self.rotation, dtype=float)
        if r.shape != (3, 3) or not np.all(np.isfinite(r)):
            raise ValueError("rotation must be a finite 3x3 matrix")
        object.__setattr__(self, "rotation", r)


def _rotation_zyx(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """Body (forward, right, down) to NED for aerospace Euler angles, radians: yaw, then pitch, then roll."""
    cr, sr, cp, sp, cy, sy = math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch), math.cos(yaw), math.sin(yaw)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def pose_from_attitude(n_m: float, e_m: float, alt_m: float, roll_deg: float = 0.0, pitch_deg: float = 0.0,
                       yaw_deg: float = 0.0, gimbal_pitch_deg: float = -90.0, gimbal_yaw_deg: float = 0.0,
                       stabilised: bool = False) -> CameraPose:
    """The camera's pose from the vehicle's attitude (roll, pitch, yaw, degrees, body to NED) and the
    gimbal's angles relative to the body (yaw, then pitch; pitch -90 = straight down, 0 = along the
    nose). The default is a camera fixed looking down: at level flight and yaw 0 the image's top is
    north and its right east. `stabilised`: the gimbal cancels the vehicle's roll and pitch (as a
    stabilised mount does), so only the vehicle's yaw carries over."""
    body = (_rotation_zyx(0.0, 0.0, math.radians(yaw_deg)) if stabilised else
            _rotation_zyx(math.radians(roll_deg), math.radians(pitch_deg), math.radians(yaw_deg)))
    gimbal = _rotation_zyx(0.0, math.radians(gimbal_pitch_deg), math.radians(gimbal_yaw_deg))
    return CameraPose(n_m, e_m, alt_m, body @ gimbal)


@lru_cache(maxsize=8)
def _camera_rays(spec: ThermalCameraSpec) -> tuple[float, np.ndarray, np.ndarray]:
    """Each pixel centre's ray in camera axes, unnormalised: (focal length, image-right offsets as a
    (1, width) row, image-down offsets as a (height, 1) column), to broadcast into the image."""
    cols = (np.arange(spec.width_px) + 0.5 - spec.width_px / 2.0)[np.newaxis, :]
    rows = (np.arange(spec.height_px) + 0.5 - spec.height_px / 2.0)[:, np.newaxis]
    cols.setflags(write=False)
    rows.setflags(write=False)
    return spec.focal_px, cols, rows


def _ground_hits(x, y, z, pose: CameraPose) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Where rays (camera-axes components x, y, z, broadcast together) meet the ground: north, east
    (NaN for the sky) and the ground mask (the ray points below the horizon). Written out per
    component: numpy's matmul over many 3-vectors costs several times more."""
    r = pose.rotation
    north = r[0, 0] * x + r[0, 1] * y + r[0, 2] * z
    east = r[1, 0] * x + r[1, 1] * y + r[1, 2] * z
    down = r[2, 0] * x + r[2, 1] * y + r[2, 2] * z
    ground = down > 0.0
    height = max(pose.alt_m, LENS_ABOVE_GROUND_M)
    with np.errstate(divide="ignore", invalid="ignore"):
        reach = np.where(ground, height / down, np.nan)
    return pose.n_m + reach * north, pose.e_m + reach * east, ground


def footprint(spec: ThermalCameraSpec, pose: CameraPose) -> tuple[np.ndarray, np.ndarray]:
    """The ground north and east [m] of each pixel centre, each (height, width); NaN where the pixel
    sees sky. What the decision layer updates its belief at, pixel by pixel."""
    n, e, _ = _ground_hits(*_camera_rays(spec), pose)
    return n, e


def footprint_corners(spec: ThermalCameraSpec, pose: CameraPose) -> np.ndarray:
    """The ground north/east of the image's outer corners (the pixels' outer edges), (4, 2), in the
    order top-left, top-right, bottom-right, bottom-left; NaN for a corner that sees sky."""
    w, h = spec.width_px / 2.0, spec.height_px / 2.0
    n, e, _ = _ground_hits(spec.focal_px, np.array([-w, w, w, -w]), np.array([-h, -h, h, h]), pose)
    return np.stack([n, e], axis=-1)


def _gaussian_blur(image: np.ndarray, sigma_px: float) -> np.ndarray:
    """A separable Gaussian blur, mirrored at the edges, kernel cut at 4 sigma (scipy.ndimage's
    gaussian_filter defaults, without scipy: sim/ needs only numpy)."""
    radius = int(4.0 * sigma_px + 0.5)
    if sigma_px <= 0 or radius == 0:
        return image
    x = np.arange(-radius, radius + 1)
    weights = np.exp(-0.5 * (x / sigma_px) ** 2)
    weights /= weights.sum()
    out = image
    for axis in (0, 1):
        pad = [(0, 0), (0, 0)]
        pad[axis] = (radius, radius)
        padded = np.pad(out, pad, mode="symmetric")
        size = out.shape[axis]
        acc = np.zeros_like(out)
        for k, w in enumerate(weights):
            acc += w * (padded[k:k + size, :] if axis == 0 else padded[:, k:k + size])
        out = acc
    return out


def render(world: FireWorld, spec: ThermalCameraSpec, camera_pose: CameraPose,
           rng: np.random.Generator | None, t_s: float = 0.0) -> np.ndarray:
    """One frame: a float32 image (height_px, width_px) of temperatures [deg C] as the camera reads
    them at time t_s (fires that grow are hotter later). rng draws the readout noise (sigma netd_k);
    None renders the noise-free frame. The same rng state gives the same frame."""
    n, e, ground = _ground_hits(*_camera_rays(spec), camera_pose)
    if ground.all():  # the usual downward view: no sky, no masked copies
        scene = temperature_field(world, n, e, spec.emission_height_m, t_s)
    else:
        scene = np.full(ground.shape, spec.sky_c, dtype=float)
        scene[ground] = temperature_field(world, n[ground], e[ground], spec.emission_height_m, t_s)
    image = _gaussian_blur(scene, spec.psf_sigma_px).astype(np.float32)
    if rng is not None and spec.netd_k > 0:
        image += np.float32(spec.netd_k) * rng.standard_normal(image.shape, dtype=np.float32)
    return image

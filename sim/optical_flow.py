"""A downward optical flow camera over the flat ground, as ArduPilot SITL simulates one (its SITL
flow driver, FLOW_TYPE 10).

The camera sees the ground slide past: the angular rate of the image about the body's x and y axes
is the velocity across the line of sight over the range to the ground, plus the body's own rotation
(the camera turns with the body). With v the velocity in the body frame (FRD), h the range along
the beam and (p, q) the roll and pitch rates:
    flow_x = -v_y / h + p          flow_y = v_x / h + q
and the body rates the sensor's own gyro gives are (p, q). A camera mounted off the centre of mass
(SIM_FLOW_POS_*) also moves by the rotation (omega x offset) and sees the ground from its own height.
Looking at or above the horizon, or from under the ground, it sees no ground: the range is SITL's
1e38 and the flow only the rotation.

SensorSettings are SITL's SIM_FLOW_* (noise, rate, delay, offset): the rate gates when a new sample
is made, the noise is uniform within +-SIM_FLOW_RND on each flow axis, and the delay hands out the
sample made that many samples ago. The flow's scale factors and yaw alignment are the autopilot
driver's (FLOW_FXSCALER, FLOW_ORIENT_YAW) and applied there.
"""
from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass
from typing import NamedTuple

from .rigid_body import BodyState
from .sensors import sensor_rng

NO_GROUND_M = 1e38  # SITL's range when the beam misses the ground
MIN_COS_TILT = 0.05  # SITL's: flatter than this the beam never meets the ground
SURFACE_QUALITY = 51  # what SITL's simulated camera always reports
MAX_DELAY_SAMPLES = 20  # SITL keeps this many samples for SIM_FLOW_DELAY


class FlowSample(NamedTuple):
    flow_x: float  # image rate about the body x axis [rad/s], body rotation included
    flow_y: float
    body_x: float  # the body rates the sensor reports alongside [rad/s]
    body_y: float
    quality: int


def _rotation(b: BodyState) -> tuple:
    """The body-to-NED rotation matrix's rows from the attitude quaternion."""
    w, x, y, z = b.qw, b.qx, b.qy, b.qz
    return ((1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)),
            (2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)),
            (2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)))


def true_flow(b: BodyState, ground_d_m: float, offset_m: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> FlowSample:
    """The flow a perfect camera at body offset `offset_m` (FRD) sees over ground at down coordinate
    ground_d_m: a pure function of the true state."""
    r = _rotation(b)
    p, q, rr = b.p_rad_s, b.q_rad_s, b.r_rad_s
    height = ground_d_m - b.d_m
    cos_tilt = r[2][2]
    if cos_tilt > MIN_COS_TILT and height > 0.0:
        offset_down = r[2][0] * offset_m[0] + r[2][1] * offset_m[1] + r[2][2] * offset_m[2]
        range_m = (height - offset_down) / cos_tilt
    else:
        range_m = NO_GROUND_M
    vn, ve, vd = b.vn_m_s, b.ve_m_s, b.vd_m_s
    # the body frame's velocity: R transposed times the NED velocity, then omega x offset
    vx = r[0][0] * vn + r[1][0] * ve + r[2][0] * vd + (q * offset_m[2] - rr * offset_m[1])
    vy = r[0][1] * vn + r[1][1] * ve + r[2][1] * vd + (rr * offset_m[0] - p * offset_m[2])
    return FlowSample(_over(-vy, range_m) + p, _over(vx, range_m) + q, p, q, SURFACE_QUALITY)


def _over(x: float, y: float) -> float:
    """x / y as SITL's float division gives it: over a range of exactly 0 (a lens offset
    SIM_FLOW_POS_Z at the ground) an infinite flow, or NaN for no motion, where Python would raise."""
    if y:
        return x / y
    if x != x or x == 0.0:
        return math.nan
    return math.copysign(math.inf, x) * math.copysign(1.0, y)


@dataclass
class SensorSettings:
    """SITL's SIM_FLOW_* as plain numbers, set from outside as the other sensors' faults are."""
    enabled: bool = False           # SIM_FLOW_ENABLE
    rate_hz: float = 10.0           # SIM_FLOW_RATE
    delay_samples: int = 0          # SIM_FLOW_DELAY
    noise_rad_s: float = 0.05       # SIM_FLOW_RND
    offset_m: tuple[float, float, float] = (0.0, 0.0, 0.0)  # SIM_FLOW_POS_X/Y/Z


class FlowCamera:
    """The simulated camera: makes a sample at SIM_FLOW_RATE when read, noisy and delayed."""

    def __init__(self, seed: int):
        self._rng = sensor_rng(seed, "optical_flow")
        self.settings = SensorSettings()
        self._last_s: float | None = None
        self._queue: deque[FlowSample] = deque()

    def read(self, time_s: float, body: BodyState, ground_d_m: float = 0.0) -> FlowSample | None:
        """A new sample if one is due at time_s (SIM_FLOW_RATE), else None; None while disabled."""
        s = self.settings
        if not s.enabled or s.rate_hz <= 0.0:
            return None
        if self._last_s is not None and time_s - self._last_s < 1.0 / s.rate_hz - 1e-9:
            return None
        self._last_s = time_s
        flow = true_flow(body, ground_d_m, s.offset_m)
        if s.noise_rad_s:
            nx, ny = self._rng.uniform(-1.0, 1.0, 2)
            flow = flow._replace(flow_x=flow.flow_x + s.noise_rad_s * float(nx),
                                 flow_y=flow.flow_y + s.noise_rad_s * float(ny))
        delay = min(max(int(s.delay_samples), 0), MAX_DELAY_SAMPLES)
        self._queue.append(flow)
        while len(self._queue) > delay + 1:
            self._queue.popleft()
        return self._queue[0]

"""A downward rangefinder's beam over the flat ground, as ArduPilot SITL simulates its sonar.

The range is the height above the ground along the beam: height / cos(tilt), the beam being the
body's down axis. A beam at or above the horizon never meets the ground: the range is infinite
(SITL's "no data"). Noise, when set (SIM_SONAR_RND), is uniform within +-noise_m, and a range is
never negative. No limit is applied here: the autopilot's driver judges a range too short or too
long against its own RNGFND1_MIN and RNGFND1_MAX.
"""
from __future__ import annotations

import math

from .rigid_body import BodyState
from .sensors import sensor_rng

FARTHEST_M = 100_000.0  # SITL's sanity bound: farther than this is no reading


class SonarBeam:
    def __init__(self, seed: int):
        self._rng = sensor_rng(seed, "sonar")
        self.noise_m = 0.0  # SIM_SONAR_RND, set from outside as the other sensors' faults are

    def range_m(self, body: BodyState, ground_d_m: float = 0.0) -> float:
        """The range [m] from the body to the ground at down coordinate ground_d_m, along the body's
        down axis; inf when that axis does not point below the horizon."""
        cos_tilt = 1.0 - 2.0 * (body.qx * body.qx + body.qy * body.qy)  # the body z axis' down component
        if cos_tilt <= 0.0:
            return math.inf
        distance = (ground_d_m - body.d_m) / cos_tilt
        if distance > FARTHEST_M:
            return math.inf
        if self.noise_m:
            distance += self.noise_m * float(self._rng.uniform(-1.0, 1.0))
        return max(distance, 0.0)

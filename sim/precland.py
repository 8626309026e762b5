"""ArduPilot SITL's precision-landing beacon (SIM_PLD_*): where the vehicle is, seen from it.

The beacon lies at SIM_PLD_LAT / SIM_PLD_LON, SIM_PLD_HEIGHT above the origin, facing up (SITL's
default SIM_PLD_ORIENT, the only one modelled). It sees the vehicle while the vehicle is above it,
no higher than SIM_PLD_ALT_LMT, and within SIM_PLD_DIST_LMT: sideways for SIM_PLD_TYPE 0 (a
cylinder), within the cone that widens to that at ALT_LMT for 1, in all directions for 2. What it
reports is the vehicle's true position relative to it (north, east, down), as SITL's does.

SITL reads the beacon's position through float32s (the parameter, and the parameter times 1e7),
which moves it by up to about a metre from where it was asked for: `quantised_e7` does the same,
so a landing comes down where ArduCopter's comes down.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

CYLINDER, CONE, SPHERE = 0, 1, 2


def quantised_e7(degrees: float) -> int:
    """SIM_Precland's int32(float(param) * 1.0e7f): the beacon's latitude or longitude [1e-7 deg]."""
    return int(np.float32(np.float32(degrees) * np.float32(1e7)))


class Beacon(NamedTuple):
    n_m: float  # in the sim's frame
    e_m: float
    d_m: float
    alt_limit_m: float
    dist_limit_m: float
    kind: int

    def sees(self, n_m: float, e_m: float, d_m: float) -> tuple[float, float, float] | None:
        """The vehicle's position relative to the beacon, or None when the beacon cannot see it."""
        if self.alt_limit_m == 0 or self.dist_limit_m < 1.0:
            return None
        rn, re, rd = n_m - self.n_m, e_m - self.e_m, d_m - self.d_m
        height = -rd
        if height <= 0 or height > self.alt_limit_m:
            return None
        lateral = math.hypot(rn, re)
        if self.kind == CONE:
            seen = lateral <= height * self.dist_limit_m / self.alt_limit_m
        elif self.kind == SPHERE:
            seen = math.sqrt(rn * rn + re * re + rd * rd) <= self.dist_limit_m
        else:
            seen = lateral <= self.dist_limit_m
        return (rn, re, rd) if seen else None

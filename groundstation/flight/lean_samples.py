"""The flight's steady lean samples for the wind estimate (strategy/wind_estimate.py), sans-IO.

ATTITUDE gives the lean, LOCAL_POSITION_NED the velocity. Only steady flight says what the wind
does: while the vehicle speeds up, slows down or turns, its lean also drives that change, and the
lean comes first (the vehicle tilts, then its velocity follows). So an instant is judged once
LOOKAHEAD_S has passed: it is steady when the velocity changed by at most STEADY_M_S from STEADY_S
before it to LOOKAHEAD_S after it. Its sample pairs the velocity with the attitude nearest in time
(within PAIR_MS), at most one per SAMPLE_S: consecutive attitudes are not independent evidence.
Nothing below MIN_HEIGHT_SHARE of the survey height (taking off) is taken.
"""
from __future__ import annotations

import math
from collections import deque

from ..strategy.wind_estimate import lean_of_attitude
from .survey import MIN_HEIGHT_SHARE  # the same rule as the readings': nothing from taking off

STEADY_S = 1.0
LOOKAHEAD_S = 0.5
STEADY_M_S = 0.2
SAMPLE_S = 0.5
PAIR_MS = 60  # an attitude this close in time to the velocity is the same instant
KEPT_MS = 3000  # the history a judgement needs, and some


class LeanSamples:
    def __init__(self, survey_alt_m: float):
        self.min_height_m = survey_alt_m * MIN_HEIGHT_SHARE
        self.velocities: deque = deque()  # (t_ms, vn, ve): a steady stretch at the survey height
        self.attitudes: deque = deque()   # (t_ms, roll, pitch, yaw)
        self.samples: list[tuple] = []  # ((vn, ve), (lean_n, lean_e)) taken so far
        self._last_ms = -math.inf

    def add_attitude(self, t_ms: int, roll: float, pitch: float, yaw: float) -> None:
        if all(math.isfinite(x) for x in (roll, pitch, yaw)):
            self.attitudes.append((t_ms, roll, pitch, yaw))
            while self.attitudes and self.attitudes[0][0] < t_ms - KEPT_MS:
                self.attitudes.popleft()

    def add_velocity(self, t_ms: int, vn: float, ve: float, height_m: float) -> tuple | None:
        """A velocity report; returns the sample it completes, if any (also kept in samples)."""
        if not all(math.isfinite(x) for x in (vn, ve, height_m)) or height_m < self.min_height_m:
            self.velocities.clear()
            return None
        self.velocities.append((t_ms, vn, ve))
        while self.velocities and self.velocities[0][0] < t_ms - KEPT_MS:
            self.velocities.popleft()
        when = t_ms - 1000 * LOOKAHEAD_S
        if self.velocities[0][0] > when - 1000 * STEADY_S or when - self._last_ms < 1000 * SAMPLE_S:
            return None  # not yet the whole window, or a sample taken too lately
        window = [v for v in self.velocities if v[0] >= when - 1000 * STEADY_S]
        at = min(window, key=lambda v: abs(v[0] - when))
        if max(math.hypot(v[1] - at[1], v[2] - at[2]) for v in window) > STEADY_M_S:
            return None
        attitude = min(self.attitudes, key=lambda a: abs(a[0] - at[0]), default=None)
        if attitude is None or abs(attitude[0] - at[0]) > PAIR_MS:
            return None
        self._last_ms = at[0]
        sample = ((at[1], at[2]), lean_of_attitude(*attitude[1:]))
        self.samples.append(sample)
        return sample

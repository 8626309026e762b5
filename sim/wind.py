"""Wind: a steady vector from the scenario (meteorological convention: the direction it blows
from), and the wind the vehicle actually flies in, which may change while it flies.

`Wind` keeps a mean that moves toward its set value with a first-order lag (a changed wind takes
effect over `change_tc_s`, as ArduPilot's SIM_WIND_TC) plus turbulence: on each axis a seeded
first-order Gauss-Markov process with standard deviation `turbulence_m_s` and correlation time
TURBULENCE_TC_S, stepped exactly (x' = a x + sigma sqrt(1 - a^2) n, a = exp(-dt/tau)).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .sensors import NoisySource, sensor_rng

TURBULENCE_TC_S = 0.5  # how long a gust lasts, roughly; ArduPilot's is a per-physics-step IIR


@dataclass(frozen=True)
class SteadyWind:
    speed_m_s: float = 0.0
    from_direction_deg: float = 0.0

    def velocity_ned(self) -> tuple:
        to = math.radians(self.from_direction_deg + 180.0)
        return (self.speed_m_s * math.cos(to), self.speed_m_s * math.sin(to), 0.0)


class Wind:
    """The wind now: a lagged mean plus turbulence from the vehicle's own "wind" random stream."""

    def __init__(self, steady: SteadyWind, seed: int):
        self._mean = self._target = steady.velocity_ned()
        self._gust: tuple[float, ...] = (0.0, 0.0, 0.0)
        self._src = NoisySource(sensor_rng(seed, "wind"))
        self.turbulence_m_s = 0.0
        self.change_tc_s = 0.0
        self.velocity_ned = self._mean

    def set_mean(self, steady: SteadyWind, immediately: bool = False) -> None:
        """The wind to blow from now on; it is reached over change_tc_s unless `immediately`."""
        self._target = steady.velocity_ned()
        if immediately or self.change_tc_s <= 0.0:
            self._mean = self._target

    @property
    def changing(self) -> bool:
        """Whether advance() would change anything (a steady wind costs nothing per step)."""
        return self.turbulence_m_s > 0.0 or self._mean != self._target or self.velocity_ned != self._mean

    def advance(self, dt: float) -> tuple:
        """The wind dt seconds later (NED, m/s)."""
        if self._mean != self._target:
            k = 1.0 - math.exp(-dt / self.change_tc_s) if self.change_tc_s > 0.0 else 1.0
            mean = tuple(m + (t - m) * k for m, t in zip(self._mean, self._target))
            settled = all(abs(t - m) < 1e-3 for m, t in zip(mean, self._target))  # within 1 mm/s
            self._mean = self._target if settled else mean
        a = math.exp(-dt / TURBULENCE_TC_S)
        spread = self.turbulence_m_s * math.sqrt(1.0 - a * a)
        nz = self._src.normal
        self._gust = tuple(a * g + spread * nz() for g in self._gust) if self.turbulence_m_s > 0.0 \
            else (0.0, 0.0, 0.0)
        self.velocity_ned = tuple(m + g for m, g in zip(self._mean, self._gust))
        return self.velocity_ned

"""Wind: a steady vector from the scenario (meteorological convention: the direction it blows
from), and the wind the vehicle actually flies in, which may change while it flies.

`Wind` keeps a mean that moves toward its set value with a first-order lag (a changed wind takes
effect over `change_tc_s`, as ArduPilot's SIM_WIND_TC) plus turbulence: on each axis a seeded
first-order Gauss-Markov process with standard deviation `turbulence_m_s` and correlation time
TURBULENCE_TC_S, stepped exactly (x' = a x + sigma sqrt(1 - a^2) n, a = exp(-dt/tau)).

Near the ground the mean blows weaker, as ArduPilot SITL's SIM_WIND_T profile makes it (its
default: the speed times the square root of the height's share of SIM_WIND_T_ALT, 60 m, below
it); the turbulence does not weaken. A Wind made without a profile blows the same at any height.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .sensors import NoisySource, sensor_rng

TURBULENCE_TC_S = 0.5  # how long a gust lasts, roughly; ArduPilot's is a per-physics-step IIR


# SIM_WIND_T's values
SQUARE_ROOT, NO_LIMIT, LINEAR = 0, 1, 2
# A profile's parameters take any value, as ArduPilot's do; the wind they make is held to the
# highest SIM_WIND_SPD takes, so that absurd settings make a storm, not an overflowing physics step.
MAX_SPEED_M_S = 100.0


@dataclass(frozen=True)
class WindProfile:
    """How the mean wind's speed depends on the height above the ground (SIM_WIND_T, _ALT, _COEF)."""
    kind: int = NO_LIMIT
    alt_m: float = 60.0
    coef: float = 0.01

    def speed_at(self, speed_m_s: float, height_m: float) -> float:
        """As SITL works it out (an altitude of 0: no wind below it; a negative one: stronger below
        it), at most MAX_SPEED_M_S and never blowing backwards."""
        if self.kind == SQUARE_ROOT:
            if height_m < self.alt_m:
                share = height_m / self.alt_m if self.alt_m != 0.0 else -math.inf
                speed_m_s *= math.sqrt(max(share, 0.0))
        elif self.kind == LINEAR:
            speed_m_s += (height_m - self.alt_m) * self.coef
        return min(max(speed_m_s, 0.0), MAX_SPEED_M_S)


FLAT = WindProfile()


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
        self._turbulence_m_s = 0.0
        self.change_tc_s = 0.0
        self._profile = FLAT
        self._calm: tuple | None = self._mean  # the mean as it blew at the last height asked (None: anew)
        self.velocity_ned = self._mean
        # Whether the wind may change at all, by time or by height: a plain attribute, read at
        # every battery step (a calm or steady wind at one height costs nothing there)
        self.live = False

    def _review(self) -> None:
        self.live = self.changing or self.with_height

    @property
    def turbulence_m_s(self) -> float:
        return self._turbulence_m_s

    @turbulence_m_s.setter
    def turbulence_m_s(self, std_m_s: float) -> None:
        self._turbulence_m_s = std_m_s
        self._review()

    def set_mean(self, steady: SteadyWind, immediately: bool = False) -> None:
        """The wind to blow from now on; it is reached over change_tc_s unless `immediately`."""
        self._target = steady.velocity_ned()
        if immediately or self.change_tc_s <= 0.0:
            self._mean = self._target
        self._review()

    @property
    def profile(self) -> WindProfile:
        return self._profile

    @profile.setter
    def profile(self, profile: WindProfile) -> None:
        if profile != self._profile:
            self._profile, self._calm = profile, None  # blowing anew at the next advance
            self._review()

    @property
    def changing(self) -> bool:
        """Whether advance() would change anything at the same height (a steady wind costs nothing
        per step)."""
        return self.turbulence_m_s > 0.0 or self._mean != self._target or self.velocity_ned != self._calm

    @property
    def with_height(self) -> bool:
        """Whether the wind changes with the height (a profile, and a mean to weaken)."""
        return self._profile.kind != NO_LIMIT and self._mean != (0.0, 0.0, 0.0)

    def advance(self, dt: float, height_m: float = math.inf) -> tuple:
        """The wind dt seconds later (NED, m/s), `height_m` above the ground."""
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
        calm = self._calm = self._at_height(height_m)
        self.velocity_ned = tuple(m + g for m, g in zip(calm, self._gust))
        self._review()
        return self.velocity_ned

    def _at_height(self, height_m: float) -> tuple:
        mean = self._mean
        if self._profile.kind == NO_LIMIT:
            return mean
        speed = math.hypot(mean[0], mean[1])
        if speed == 0.0:
            return mean
        k = self._profile.speed_at(speed, height_m) / speed  # (SITL scales the vertical part alike)
        return (mean[0] * k, mean[1] * k, mean[2] * k)

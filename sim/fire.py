"""The fire world: fires, the temperature field they make, and the downward radiometric sensor.

Reading model (docs/strategy.md): z = b + sum_f A_f * g(r_f) + noise, r_f the horizontal distance
from the sensor to fire f. Kernels:
  R (radiant point source, default): g = h^2 / (h^2 + r^2), h the sensor's height above ground —
    the inverse-square fall-off of radiant flux q = chi*Q / (4 pi R^2) with R^2 = h^2 + r^2;
  G (plume-like): g = exp(-r^2 / (2 s^2)).
A wind tilt shifts the hot spot downwind by tilt * h (the plume leans with the wind): either given
as it is (wind_tilt, wind_to_deg: a lean nothing else in the world explains) or made by the
scenario's wind, tilt = wind speed / plume_rise_m_s toward where the wind blows. Fires may spread: their strength grows linearly in time.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .sensors import sensor_rng

KERNELS = ("R", "G")


@dataclass(frozen=True)
class Fire:
    n_m: float
    e_m: float
    strength_k: float = 50.0
    growth_k_per_s: float = 0.0  # slow spread: strength grows with time

    def strength_at(self, t_s: float) -> float:
        return self.strength_k + self.growth_k_per_s * t_s


@dataclass(frozen=True)
class FireWorld:
    """The area searched and what burns in it. Local metres, origin = home, area = [0, size]^2."""
    fires: tuple = (Fire(290.0, 250.0),)
    area_m: float = 400.0
    cell_m: float = 10.0
    survey_alt_m: float = 30.0
    ambient_c: float = 22.0
    kernel: str = "R"
    plume_sigma_m: float = 25.0
    noise_k: float = 1.0
    outlier_rate: float = 0.0
    outlier_k: float = 15.0
    wind_tilt: float = 0.0  # metres downwind per metre of height
    wind_to_deg: float = 90.0  # direction the plume leans toward
    # The speed the hot gases rise at: with it the plume leans with the scenario's [wind], by
    # wind speed / rise speed metres per metre of height (sim/scenario.py sets wind_tilt from it).
    plume_rise_m_s: float = 0.0

    def validate(self) -> None:
        if self.kernel not in KERNELS:
            raise ValueError(f"kernel must be one of {', '.join(KERNELS)}, got {self.kernel!r}")
        for name in ("area_m", "cell_m", "survey_alt_m", "plume_sigma_m"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be positive")
        if self.cell_m > self.area_m:
            raise ValueError("cell_m must not exceed area_m")
        for name in ("noise_k", "outlier_k", "wind_tilt", "plume_rise_m_s"):
            if not getattr(self, name) >= 0:
                raise ValueError(f"{name} must be zero or positive")
        if not 0 <= self.outlier_rate <= 1:
            raise ValueError("outlier_rate must be within 0..1")
        for k, fire in enumerate(self.fires):
            if not (0 <= fire.n_m <= self.area_m and 0 <= fire.e_m <= self.area_m):
                raise ValueError(f"fire {k} at ({fire.n_m}, {fire.e_m}) is outside the area 0..{self.area_m:g} m")
            if not fire.strength_k > 0:
                raise ValueError(f"fire {k} strength must be positive")


def kernel_value(kernel: str, r2, h: float, sigma: float):
    """g(r) for squared horizontal distance(s) r2 (float or numpy array)."""
    if kernel == "R":
        h2 = np.maximum(h, 0.5) ** 2  # (h may be an array too, one height per r2)
        return h2 / (h2 + r2)
    return np.exp(-r2 / (2.0 * sigma * sigma)) if isinstance(r2, np.ndarray) else math.exp(-r2 / (2.0 * sigma * sigma))


def true_temperature(world: FireWorld, n: float, e: float, height_m: float, t_s: float) -> float:
    """Noise-free reading of the sensor at (n, e) and height above ground."""
    shift = world.wind_tilt * max(height_m, 0.0)
    to = math.radians(world.wind_to_deg)
    total = world.ambient_c
    for fire in world.fires:
        fn, fe = fire.n_m + shift * math.cos(to), fire.e_m + shift * math.sin(to)
        r2 = (n - fn) ** 2 + (e - fe) ** 2
        total += fire.strength_at(t_s) * kernel_value(world.kernel, r2, height_m, world.plume_sigma_m)
    return total


def temperature_field(world: FireWorld, n: np.ndarray, e: np.ndarray, height_m: float, t_s: float) -> np.ndarray:
    """true_temperature at many points (n, e) at once, all at one height above ground: what an imager
    sees (sim/thermal_camera.py). The same model, vectorised; height_m is one figure for all points."""
    h = max(height_m, 0.0)
    to = math.radians(world.wind_to_deg)
    total = np.full(np.broadcast_shapes(np.shape(n), np.shape(e)), world.ambient_c, dtype=float)
    for fire in world.fires:
        fn, fe = fire.n_m + world.wind_tilt * h * math.cos(to), fire.e_m + world.wind_tilt * h * math.sin(to)
        r2 = (n - fn) ** 2 + (e - fe) ** 2
        total += fire.strength_at(t_s) * kernel_value(world.kernel, r2, height_m, world.plume_sigma_m)
    return total


@dataclass
class TemperatureSensor:
    """Noisy readings with occasional outliers, from its own seeded stream."""
    world: FireWorld
    seed: int = 0
    _rng: np.random.Generator = field(init=False, repr=False)

    def __post_init__(self):
        self._rng = sensor_rng(self.seed, "temperature")

    def read(self, n: float, e: float, height_m: float, t_s: float) -> float:
        z = true_temperature(self.world, n, e, height_m, t_s) + self.world.noise_k * self._rng.standard_normal()
        if self.world.outlier_rate and self._rng.random() < self.world.outlier_rate:
            z += self.world.outlier_k * (1.0 if self._rng.random() < 0.5 else -1.0)
        return float(z)


WORLD_KEYS = {"area_m", "cell_m", "survey_alt_m", "ambient_c", "kernel", "plume_sigma_m", "noise_k",
              "outlier_rate", "outlier_k", "wind_tilt", "wind_to_deg", "plume_rise_m_s"}
FIRE_KEYS = {"n_m", "e_m", "strength_k", "growth_k_per_s"}


def world_from_tables(world: dict, fires: list | None, where: str) -> FireWorld:
    """Build a FireWorld from a scenario's [world] table and [[fire]] array of tables.

    Raises ValueError with one line naming the table and key at fault."""
    if not isinstance(world, dict):
        raise ValueError(f"{where}: [world] must be a table")
    values = {}
    for key, value in world.items():
        if key not in WORLD_KEYS:
            raise ValueError(f"{where}: [world] unknown key '{key}' (known: {', '.join(sorted(WORLD_KEYS))})")
        if key == "kernel":
            if value not in KERNELS:
                raise ValueError(f"{where}: [world].kernel must be \"R\" or \"G\", got {value!r}")
        elif isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise ValueError(f"{where}: [world].{key}: expected a finite number, got {value!r}")
        values[key] = value
    fire_objs = []
    for k, table in enumerate(fires if fires is not None else []):
        if not isinstance(table, dict):
            raise ValueError(f"{where}: [[fire]] {k + 1} must be a table")
        for key, value in table.items():
            if key not in FIRE_KEYS:
                raise ValueError(f"{where}: [[fire]] {k + 1} unknown key '{key}' (known: {', '.join(sorted(FIRE_KEYS))})")
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise ValueError(f"{where}: [[fire]] {k + 1}.{key}: expected a finite number, got {value!r}")
        missing = {"n_m", "e_m"} - set(table)
        if missing:
            raise ValueError(f"{where}: [[fire]] {k + 1} missing '{sorted(missing)[0]}'")
        fire_objs.append(Fire(**{key: float(v) for key, v in table.items()}))
    if fires is not None:
        values["fires"] = tuple(fire_objs)
    built = FireWorld(**values)
    try:
        built.validate()
    except ValueError as exc:
        raise ValueError(f"{where}: [world] {exc}") from None
    return built

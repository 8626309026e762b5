"""Sensors that measure the true state with seeded noise.

Each sensor owns its own numpy Generator (seeded from the vehicle seed and the sensor's name) so
adding a sensor never changes another's noise. Noise draws happen at each sensor's own rate.
"""
from __future__ import annotations

import zlib
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np


@dataclass(frozen=True)
class NoiseConfig:
    gps_horizontal_m: float = 0.3
    gps_vertical_m: float = 0.5
    gps_velocity_m_s: float = 0.05
    baro_m: float = 0.1
    gyro_rad_s: float = 0.002
    attitude_rad: float = 0.002
    battery_v: float = 0.01


def sensor_rng(seed: int, name: str) -> np.random.Generator:
    return np.random.default_rng([seed & 0xFFFFFFFF, zlib.crc32(name.encode())])


class GpsReading(NamedTuple):
    n_m: float
    e_m: float
    d_m: float
    vn_m_s: float
    ve_m_s: float
    vd_m_s: float
    satellites: int
    fix_type: int  # 3 = 3D fix


class NoisySource:
    """Standard-normal draws in blocks, so the per-sample cost stays small."""

    def __init__(self, rng: np.random.Generator, block: int = 4096):
        self._rng = rng
        self._block = block
        self._buf: list[float] = []

    def normal(self) -> float:
        if not self._buf:
            self._buf = self._rng.standard_normal(self._block).tolist()
        return self._buf.pop()


class Gps:
    def __init__(self, seed: int, noise: NoiseConfig):
        self._src = NoisySource(sensor_rng(seed, "gps"))
        self._noise = noise

    def read(self, body) -> GpsReading:
        nz, h, v, vel = self._src.normal, self._noise.gps_horizontal_m, self._noise.gps_vertical_m, \
            self._noise.gps_velocity_m_s
        return GpsReading(body.n_m + h * nz(), body.e_m + h * nz(), body.d_m + v * nz(),
                          body.vn_m_s + vel * nz(), body.ve_m_s + vel * nz(),
                          body.vd_m_s + vel * nz(), 16, 3)


class Barometer:
    def __init__(self, seed: int, noise: NoiseConfig):
        self._src = NoisySource(sensor_rng(seed, "baro"))
        self._noise = noise

    def altitude_m(self, body) -> float:
        return -body.d_m + self._noise.baro_m * self._src.normal()


class Gyro:
    def __init__(self, seed: int, noise: NoiseConfig):
        self._src = NoisySource(sensor_rng(seed, "gyro"))
        self._noise = noise

    def rates(self, body) -> tuple:
        s, nz = self._noise.gyro_rad_s, self._src.normal
        return body.p_rad_s + s * nz(), body.q_rad_s + s * nz(), body.r_rad_s + s * nz()

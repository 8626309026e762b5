"""Sensors that measure the true state with seeded noise.

Each sensor owns its own numpy Generator (seeded from the vehicle seed and the sensor's name) so
adding a sensor never changes another's noise. Noise draws happen at each sensor's own rate.

Faults are plain attributes set from outside (autopilot/faults/world.py): the GPS can be switched
off, jammed (gps_jamming.py), glitched by a fixed offset or report few satellites; the barometer
can drift; the RC receiver can stop sending frames or send its failsafe throttle.
"""
from __future__ import annotations

import zlib
from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

if TYPE_CHECKING:
    from .gps_jamming import GpsJamming


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


NO_FIX, FIX_2D, FIX_3D = 1, 2, 3  # MAVLink GPS_FIX_TYPE


class Gps:
    def __init__(self, seed: int, noise: NoiseConfig):
        self._src = NoisySource(sensor_rng(seed, "gps"))
        self._noise = noise
        self.enabled = True
        # What the receiver reports in view (ArduPilot SITL's SIM_GPS1_NUMSATS default); as in SITL
        # only the count reported, the fix is the switch's: measured on ArduCopter SITL, 3
        # satellites in flight change nothing.
        self.satellites = 10
        self.glitch_ned = (0.0, 0.0, 0.0)  # metres added to every position reading
        self._seed = seed
        self.jamming: GpsJamming | None = None  # while SIM_GPS1_JAM is on

    def jam(self, on: bool) -> None:
        """SIM_GPS1_JAM: the receiver jammed from now on, or no longer. Its draws come from a
        generator of their own, so the other readings' noise is the same whether or not it was."""
        if on and self.jamming is None:
            from .gps_jamming import GpsJamming as Jamming  # (it reads this module's GpsReading)
            self.jamming = Jamming(sensor_rng(self._seed, "gps_jamming"))
        elif not on:
            self.jamming = None

    def read(self, body, now_s: float = 0.0) -> GpsReading:
        nz, h, v, vel = self._src.normal, self._noise.gps_horizontal_m, self._noise.gps_vertical_m, \
            self._noise.gps_velocity_m_s
        gn, ge, gd = self.glitch_ned
        sats, fix = (self.satellites, FIX_3D) if self.enabled else (0, NO_FIX)
        reading = GpsReading(body.n_m + gn + h * nz(), body.e_m + ge + h * nz(), body.d_m + gd + v * nz(),
                             body.vn_m_s + vel * nz(), body.ve_m_s + vel * nz(),
                             body.vd_m_s + vel * nz(), sats, fix)
        return reading if self.jamming is None else self.jamming.read(reading, now_s)


class RcReceiver:
    """The pilot's radio as ArduPilot SITL simulates one with no transmitter attached
    (AP_RCProtocol_UDP): 8 channels at 50 Hz, sticks centred, throttle at the bottom, channels 5
    and 8 at 1800 us. `fail` is SIM_RC_FAIL: 1 no frames at all; 2 every channel at 1500 us and
    the throttle at 950 us (a receiver's failsafe values). As SITL's, the values 2 writes stay
    after SIM_RC_FAIL goes back to 0: nothing sends the old ones again."""

    REST_US = (1500, 1500, 1000, 1500, 1800, 1000, 1000, 1800)
    FAILSAFE_US = (1500, 1500, 950, 1500, 1500, 1500, 1500, 1500)
    REST_THROTTLE_US = 1000
    FAILSAFE_THROTTLE_US = 950
    NO_PULSES, THROTTLE_950 = 1, 2

    def __init__(self) -> None:
        self._fail = 0
        self.pwm_us: tuple[int, ...] = self.REST_US

    @property
    def fail(self) -> int:
        return self._fail

    @fail.setter
    def fail(self, value: int) -> None:
        self._fail = value
        if value == self.THROTTLE_950:
            self.pwm_us = self.FAILSAFE_US

    def channels_us(self) -> tuple[int, ...] | None:
        """The latest frame's channels [us]; None while no frames come."""
        if self._fail == self.NO_PULSES:
            return None
        return self.pwm_us

    def throttle_us(self) -> int | None:
        """The throttle channel of the latest frame; None while no frames come."""
        chans = self.channels_us()
        return None if chans is None else chans[2]


class Barometer:
    """Altitude above the origin from pressure, with noise and an error that grows at
    drift_m_s from the moment the drift is set (setting 0 makes the sensor good again)."""

    def __init__(self, seed: int, noise: NoiseConfig):
        self._src = NoisySource(sensor_rng(seed, "baro"))
        self._noise = noise
        self.drift_m_s = 0.0
        self._drift_since = (0.0, 0.0)  # (sim time, error at that time)

    def set_drift(self, rate_m_s: float, t_s: float) -> None:
        self._drift_since = (t_s, self.error_m(t_s) if rate_m_s else 0.0)
        self.drift_m_s = rate_m_s

    def error_m(self, t_s: float) -> float:
        """How much higher than the truth the sensor reads, leaving noise aside."""
        t0, error0 = self._drift_since
        return error0 + self.drift_m_s * (t_s - t0)

    def altitude_m(self, body, t_s: float) -> float:
        return -body.d_m + self.error_m(t_s) + self._noise.baro_m * self._src.normal()


class Gyro:
    def __init__(self, seed: int, noise: NoiseConfig):
        self._src = NoisySource(sensor_rng(seed, "gyro"))
        self._noise = noise

    def rates(self, body) -> tuple:
        s, nz = self._noise.gyro_rad_s, self._src.normal
        return body.p_rad_s + s * nz(), body.q_rad_s + s * nz(), body.r_rad_s + s * nz()

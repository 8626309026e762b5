"""Other air traffic, as ArduPilot SITL's simulated ADS-B aircraft fly (SIM_ADSB_COUNT and friends).

Each aircraft is spawned around the vehicle, a normal spread of SIM_ADSB_RADIUS metres on each
axis, at SIM_ADSB_ALT metres (its altitude counted from the sim's origin, and reported above sea
level as SITL reports it); ArduPilot's spawn crosses the vehicle's own north and east offsets, and
so does this one (at the origin it makes no difference). Its emitter type is drawn from MAVLink's
twenty; a point obstacle (19) stands still and is spawned again after an hour; every other type
flies a straight line at a speed drawn per axis from N(15, 60) m/s (N(5, 20) within 500 m of the
origin) and, below the surface types (17), climbs at N(3, 3) m/s. An aircraft that reaches the
ground, or strays farther than SIM_ADSB_RADIUS from the vehicle, is replaced by a new one with a
new ICAO address (0-9999) and callsign ("SIM" and the address).

The draws come from the scenario's seed (ArduPilot's from an unseeded C rand(): the same
distributions, not the same aircraft). Aircraft move in steps of the caller's choosing (the
autopilot's 10 Hz); they fly straight, so only a respawn's moment depends on the step.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .sensors import sensor_rng

EMITTER_TYPES = 20  # ADSB_EMITTER_TYPE 0..19
POINT_OBSTACLE = 19
SURFACE = 17  # EMERGENCY_SURFACE: this type and above do not climb
STATIONARY_S = 3600.0
COUNT_MAX = 200  # SITL's num_vehicles_MAX: a larger count is taken as 0


@dataclass
class Aircraft:
    icao: int
    callsign: str
    emitter_type: int
    n_m: float  # from the sim's origin
    e_m: float
    up_m: float
    vn_m_s: float
    ve_m_s: float
    vd_m_s: float
    spawned_s: float
    alive: bool = True  # False: spawned again (a new aircraft) at the next step


class TrafficSim:
    def __init__(self, seed: int):
        self._rng = sensor_rng(seed, "adsb traffic")
        self.aircraft: list[Aircraft | None] = []  # None: never spawned yet

    def _normal(self, mean: float, sd: float) -> float:
        return mean + sd * float(self._rng.standard_normal())

    def _spawn(self, old: Aircraft | None, vehicle_ne: tuple[float, float], radius_m: float, alt_m: float,
               now_s: float) -> Aircraft:
        rng = self._rng
        icao = int(rng.integers(10000))
        n = vehicle_ne[1] + self._normal(0.0, radius_m)  # crossed, as ArduPilot's spawn
        e = vehicle_ne[0] + self._normal(0.0, radius_m)
        up = abs(alt_m)
        slow, fast = (15.0, 60.0) if math.sqrt(n * n + e * e + up * up) > 500 else (5.0, 20.0)
        emitter = int(rng.integers(EMITTER_TYPES))
        vn = ve = 0.0
        vd = old.vd_m_s if old is not None else 0.0  # a surface type keeps its last life's climb
        if emitter == POINT_OBSTACLE:
            vd = 0.0
        else:
            vn, ve = self._normal(slow, fast), self._normal(slow, fast)
            if emitter < SURFACE:
                vd = self._normal(-3.0, 3.0)
        return Aircraft(icao, f"SIM{icao}", emitter, n, e, up, vn, ve, vd, now_s)

    def step(self, dt_s: float, now_s: float, count: int, vehicle_ne: tuple[float, float], radius_m: float,
             alt_m: float) -> None:
        """Move every aircraft dt_s on; spawn those due. A new count spawns them all again."""
        count = 0 if count >= COUNT_MAX else max(count, 0)
        if count != len(self.aircraft):
            self.aircraft = [None] * count
        for i, a in enumerate(self.aircraft):
            if a is None or not a.alive or (a.emitter_type == POINT_OBSTACLE and now_s - a.spawned_s > STATIONARY_S):
                a = self.aircraft[i] = self._spawn(a, vehicle_ne, radius_m, alt_m, now_s)
            a.n_m += a.vn_m_s * dt_s
            a.e_m += a.ve_m_s * dt_s
            a.up_m -= a.vd_m_s * dt_s
            if a.up_m < 0 or math.hypot(a.n_m - vehicle_ne[0], a.e_m - vehicle_ne[1]) > radius_m:
                a.alive = False  # crashed, or too far: not reported, and spawned afresh next step

    def flying(self) -> list[Aircraft]:
        return [a for a in self.aircraft if a is not None and a.alive]

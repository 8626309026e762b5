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

A scenario may also fly aircraft of its own (`[[traffic]]` tables, Firefly's addition: ArduPilot
SITL has only the random ones): each from a place given off home, on a fixed course, speed and
climb, forever, with the ICAO address and callsign it is given. Their altitude is a true one
(home's plus their height), where SITL's random aircraft report their height above the origin as
their altitude.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .tables import each_table
from .sensors import sensor_rng

EMITTER_TYPES = 20  # ADSB_EMITTER_TYPE 0..19
POINT_OBSTACLE = 19
SURFACE = 17  # EMERGENCY_SURFACE: this type and above do not climb
STATIONARY_S = 3600.0
COUNT_MAX = 200  # SITL's num_vehicles_MAX: a larger count is taken as 0


TRACK_KEYS = {"icao": "the ICAO address, 1-16777215", "callsign": "up to 8 characters",
              "north_m": "start, north of home [m]", "east_m": "start, east of home [m]",
              "up_m": "start, above home [m]", "course_deg": "the way it flies, from north [deg]",
              "speed_m_s": "ground speed [m/s]", "climb_m_s": "climb rate [m/s]",
              "emitter_type": "ADSB_EMITTER_TYPE, 0-19 (1 light)"}


@dataclass(frozen=True)
class Track:
    """One of a scenario's own aircraft ([[traffic]])."""
    icao: int
    callsign: str = ""
    north_m: float = 0.0
    east_m: float = 0.0
    up_m: float = 0.0
    course_deg: float = 0.0
    speed_m_s: float = 0.0
    climb_m_s: float = 0.0
    emitter_type: int = 1

    def validate(self) -> None:
        if not 1 <= self.icao <= 0xFFFFFF:
            raise ValueError(f"icao: {self.icao} is not a 24-bit address (1-16777215)")
        if len(self.callsign) > 8 or not self.callsign.isascii():
            raise ValueError(f"callsign: {self.callsign!r} is not up to 8 ASCII characters")
        if not 0 <= self.emitter_type < EMITTER_TYPES:
            raise ValueError(f"emitter_type: {self.emitter_type} is not 0-19")
        if self.speed_m_s < 0:
            raise ValueError(f"speed_m_s: {self.speed_m_s:g} is negative (give course_deg the other way)")


def tracks_from_tables(tables, where: str) -> tuple[Track, ...]:
    """A scenario's [[traffic]] tables; ValueError with one line naming the table and key at fault."""
    tracks: list[Track] = []
    for name, table in each_table(tables, where, "traffic", TRACK_KEYS):
        for key, value in table.items():
            if key == "callsign":
                if not isinstance(value, str):
                    raise ValueError(f"{name}.callsign: expected a string, got {value!r}")
            elif isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) \
                    or (key in ("icao", "emitter_type") and not isinstance(value, int)):
                raise ValueError(f"{name}.{key}: expected a finite {'integer' if key in ('icao', 'emitter_type') else 'number'}, "
                                 f"got {value!r}")
        if "icao" not in table:
            raise ValueError(f"{name} missing 'icao'")
        track = Track(**table)
        try:
            track.validate()
        except ValueError as exc:
            raise ValueError(f"{name}.{exc}") from None
        same = next((j for j, t in enumerate(tracks, start=1) if t.icao == track.icao), None)
        if same is not None:
            raise ValueError(f"{name}.icao: {track.icao} is [[traffic]] {same}'s too")
        tracks.append(track)
    return tuple(tracks)


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
    scripted: bool = False  # a scenario's own: its altitude is home's plus its height, not its height


def _flying(track: Track) -> Aircraft:
    course = math.radians(track.course_deg)
    return Aircraft(track.icao, track.callsign, track.emitter_type, track.north_m, track.east_m, track.up_m,
                    track.speed_m_s * math.cos(course), track.speed_m_s * math.sin(course), -track.climb_m_s, 0.0,
                    scripted=True)


class TrafficSim:
    def __init__(self, seed: int, tracks: tuple[Track, ...] = ()):
        self._rng = sensor_rng(seed, "adsb traffic")
        self.aircraft: list[Aircraft | None] = []  # SITL's random ones; None: never spawned yet
        self.tracked = [_flying(t) for t in tracks]  # the scenario's own

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

        for a in self.tracked:
            a.n_m += a.vn_m_s * dt_s
            a.e_m += a.ve_m_s * dt_s
            a.up_m -= a.vd_m_s * dt_s

    def flying(self) -> list[Aircraft]:
        return [a for a in self.aircraft if a is not None and a.alive] + self.tracked

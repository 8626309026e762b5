"""The ground's shape: smooth hills standing on the flat field, from a scenario's [[terrain]] tables.

Each hill is a raised-cosine bump, height * (1 + cos(pi * r / radius)) / 2 within `radius` of its
centre (north, east of home, metres) and nothing beyond: smooth where it meets the field, so a
vehicle holding a height above it never sees a step. Hills add where they overlap. Heights are
above home's ground (the scenario's home altitude). The vehicle boots and rests at home, so no hill
may reach home: its centre must be farther from home than its radius.

A pure height function (metres up at north, east): the rangefinder's and the optical flow
camera's beams, and a ground station serving terrain tiles, read the same ground.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, fields

from .tables import each_table

HILL_KEYS = ("north_m", "east_m", "height_m", "radius_m")


@dataclass(frozen=True)
class Hill:
    north_m: float
    east_m: float
    height_m: float
    radius_m: float

    def validate(self) -> None:
        if not self.radius_m > 0.0:
            raise ValueError(f"radius_m: must be above 0, got {self.radius_m}")
        if not 0.0 < self.height_m <= 9000.0:
            raise ValueError(f"height_m: must be above 0 and at most 9000, got {self.height_m}")
        if math.hypot(self.north_m, self.east_m) <= self.radius_m:
            raise ValueError(f"radius_m: the hill reaches home ({math.hypot(self.north_m, self.east_m):.1f} m "
                             f"from its centre); the vehicle starts on flat ground there")

    def height_at(self, n_m: float, e_m: float) -> float:
        r = math.hypot(n_m - self.north_m, e_m - self.east_m)
        if r >= self.radius_m:
            return 0.0
        return self.height_m * 0.5 * (1.0 + math.cos(math.pi * r / self.radius_m))


@dataclass(frozen=True)
class Terrain:
    hills: tuple[Hill, ...] = ()

    def height_m(self, n_m: float, e_m: float) -> float:
        """The ground's height above home's ground [m] at north, east of home."""
        return sum(h.height_at(n_m, e_m) for h in self.hills)

    def ground_d_m(self, n_m: float, e_m: float) -> float:
        """The ground's down coordinate (NED from home's ground) at north, east."""
        return -self.height_m(n_m, e_m) if self.hills else 0.0


FLAT = Terrain()


def terrain_from_tables(tables, where: str) -> Terrain:
    """A scenario's [[terrain]] tables; ValueError with one line naming the table and key at fault."""
    hills: list[Hill] = []
    for name, table in each_table(tables, where, "terrain", HILL_KEYS):
        for key, value in table.items():
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise ValueError(f"{name}.{key}: expected a finite number, got {value!r}")
        missing = [f.name for f in fields(Hill) if f.name not in table]
        if missing:
            raise ValueError(f"{name} missing '{missing[0]}'")
        hill = Hill(**{key: float(value) for key, value in table.items()})
        try:
            hill.validate()
        except ValueError as exc:
            raise ValueError(f"{name}.{exc}") from None
        hills.append(hill)
    return Terrain(tuple(hills))

"""Positions as ArduPilot's Location keeps them: latitude and longitude in 1e-7 degrees, altitude in
centimetres above mean sea level, and its flat-earth distances between two of them. Whatever must
round as ArduPilot rounds (ADS-B traffic, terrain grids, mission rewinds) measures with these."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, NamedTuple

if TYPE_CHECKING:
    from firefly.sim.geo import GeoPoint

M_PER_E7 = 0.011131884502145034  # ArduPilot's LOCATION_SCALING_FACTOR: metres per 1e-7 degree


def longitude_scale(lat_e7: float) -> float:
    """East metres per 1e-7 degree of longitude, as a share of north's (kept off zero at the poles)."""
    return max(math.cos(math.radians(lat_e7 * 1e-7)), 0.01)


class Loc(NamedTuple):
    lat_e7: int
    lon_e7: int
    alt_cm: int  # above mean sea level

    def is_zero(self) -> bool:
        return self.lat_e7 == 0 and self.lon_e7 == 0 and self.alt_cm == 0

    def ne_to(self, other: Loc) -> tuple[float, float]:
        """Metres north and east from this location to `other` (Location::get_distance_NE)."""
        scale = longitude_scale((self.lat_e7 + other.lat_e7) * 0.5)
        d_lon = other.lon_e7 - self.lon_e7
        if d_lon > 1800000000:  # across the antimeridian, the short way
            d_lon -= 3600000000
        elif d_lon < -1800000000:
            d_lon += 3600000000
        return (other.lat_e7 - self.lat_e7) * M_PER_E7, d_lon * M_PER_E7 * scale

    def offset(self, north_m: float, east_m: float) -> Loc:
        """This location moved north and east (Location::offset)."""
        d_lat = int(north_m / M_PER_E7)
        lat = self.lat_e7 + d_lat
        lon = self.lon_e7 + int(east_m / M_PER_E7 / longitude_scale(self.lat_e7 + d_lat / 2))
        lon = (lon + 1800000000) % 3600000000 - 1800000000
        return Loc(max(-900000000, min(900000000, lat)), lon, self.alt_cm)

    def distance_to(self, other: Loc) -> float:
        """Horizontal metres to `other` (Location::get_distance)."""
        n, e = self.ne_to(other)
        return math.hypot(n, e)


ZERO = Loc(0, 0, 0)


def loc_of(point: GeoPoint) -> Loc:
    """A float position in ArduPilot's integer units (altitude truncated to the centimetre)."""
    return Loc(round(point.lat_deg * 1e7), round(point.lon_deg * 1e7), int(point.alt_m * 100.0))

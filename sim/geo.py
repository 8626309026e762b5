"""Home and the local tangent plane: latitude/longitude/altitude <-> north/east/down metres.

A flat-earth (equirectangular) projection around home is accurate to centimetres over the few
kilometres a SITL flight covers.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

EARTH_RADIUS_M = 6378137.0  # WGS84 equatorial radius


@dataclass(frozen=True)
class GeoPoint:
    lat_deg: float
    lon_deg: float
    alt_m: float  # AMSL

    def validate(self) -> None:
        for name, value, bound in (("latitude", self.lat_deg, 90.0), ("longitude", self.lon_deg, 180.0)):
            if not (math.isfinite(value) and -bound <= value <= bound):
                raise ValueError(f"{name} {value!r} is outside -{bound:g}..{bound:g}")
        if not (math.isfinite(self.alt_m) and -500.0 <= self.alt_m <= 10000.0):
            raise ValueError(f"altitude {self.alt_m!r} m is outside -500..10000")


def ned_from_global(origin: GeoPoint, lat_deg: float, lon_deg: float, alt_m: float) -> tuple[float, float, float]:
    n = math.radians(lat_deg - origin.lat_deg) * EARTH_RADIUS_M
    e = math.radians(lon_deg - origin.lon_deg) * EARTH_RADIUS_M * math.cos(math.radians(origin.lat_deg))
    return n, e, origin.alt_m - alt_m


def global_from_ned(origin: GeoPoint, n_m: float, e_m: float, d_m: float) -> GeoPoint:
    lat = origin.lat_deg + math.degrees(n_m / EARTH_RADIUS_M)
    lon = origin.lon_deg + math.degrees(e_m / (EARTH_RADIUS_M * math.cos(math.radians(origin.lat_deg))))
    return GeoPoint(lat, lon, origin.alt_m - d_m)

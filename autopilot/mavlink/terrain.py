"""TERRAIN_REQUEST and TERRAIN_REPORT as ArduCopter sends them with no terrain data on board.

Firefly's ground is flat at the origin's altitude and it keeps no terrain database, so, like an
ArduCopter whose ground station never answers, it asks every 2 s for the grid block it is in
(TERRAIN_DATA answers are not stored) and reports nothing loaded. The block is found as AP_Terrain
finds it: blocks of 28 x 32 points at TERRAIN_SPACING, 24 x 28 spacings apart (a one-point
overlap), anchored on whole degrees of latitude and longitude, with ArduPilot's flat-earth
distances in 1e-7 degree units.
"""
from __future__ import annotations

import math

from ..location import M_PER_E7, longitude_scale
from ..views import TelemetryView
from .dialect import mavlink as mav
from .encoding import deg_e7

BLOCK_STEP_N, BLOCK_STEP_E = 24, 28  # grid spacings between block corners (AP_Terrain)
ALL_BLOCKS_MASK = (1 << 56) - 1  # 7 x 8 sub-blocks of 4 x 4 points, none loaded
PENDING_UNLOADED = 504  # ArduCopter SITL's TERRAIN_REPORT with nothing loaded: 9 blocks x 56
REQUEST_MIN_INTERVAL_S = 2.0  # AP_Terrain asks again no sooner than this


def _whole_degrees_e7(x_e7: int) -> int:
    """The whole degree at or below x (AP_Terrain rounds negatives away from zero)."""
    return math.floor(x_e7 / 10_000_000) * 10_000_000


def grid_block_corner(lat_e7: int, lon_e7: int, spacing_m: float) -> tuple[int, int]:
    """South-west corner (1e-7 degrees) of the terrain grid block holding the point."""
    ref_lat, ref_lon = _whole_degrees_e7(lat_e7), _whole_degrees_e7(lon_e7)
    north = (lat_e7 - ref_lat) * M_PER_E7
    east = (lon_e7 - ref_lon) * M_PER_E7 * longitude_scale((lat_e7 + ref_lat) / 2)
    block_n = int(north / spacing_m) // BLOCK_STEP_N
    block_e = int(east / spacing_m) // BLOCK_STEP_E
    d_lat = int(block_n * BLOCK_STEP_N * spacing_m / M_PER_E7)
    d_lon = int(block_e * BLOCK_STEP_E * spacing_m / M_PER_E7 / longitude_scale(ref_lat + d_lat / 2))
    return ref_lat + d_lat, ref_lon + d_lon


def terrain_request(v: TelemetryView, codec):
    if not v.params["TERRAIN_ENABLE"]:
        return None
    pos = v.position_global()
    spacing = int(v.params["TERRAIN_SPACING"])
    lat, lon = grid_block_corner(deg_e7(pos.lat_deg), deg_e7(pos.lon_deg), spacing)
    return codec.terrain_request_encode(lat, lon, spacing, ALL_BLOCKS_MASK)


def terrain_report(v: TelemetryView, codec):
    """Nothing loaded: spacing 0, terrain height 0 and the height above it the altitude AMSL."""
    if not v.params["TERRAIN_ENABLE"]:
        return None
    pos = v.position_global()
    return codec.terrain_report_encode(deg_e7(pos.lat_deg), deg_e7(pos.lon_deg), 0, 0.0, pos.alt_m,
                                       PENDING_UNLOADED, 0)


BUILDERS = {mav.MAVLINK_MSG_ID_TERRAIN_REQUEST: terrain_request,
            mav.MAVLINK_MSG_ID_TERRAIN_REPORT: terrain_report}

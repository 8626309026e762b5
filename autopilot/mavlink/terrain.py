"""TERRAIN_REQUEST, TERRAIN_REPORT, TERRAIN_DATA and TERRAIN_CHECK as ArduCopter handles them.

The vehicle asks, no more often than every 2 s, for the missing 4 x 4 sub-grids of one block: its
own if that lacks any, else the first held block that does (the blocks are autopilot/terrain_grid.py's,
found as AP_Terrain finds them). A ground station's TERRAIN_DATA fills a held block; TERRAIN_CHECK
is answered with a TERRAIN_REPORT for its location (no extrapolation); the streamed TERRAIN_REPORT
is for the vehicle's own, extrapolated from the last height known while the data under it has not
come. Nothing at all with TERRAIN_ENABLE 0.
"""
from __future__ import annotations

from ..location import ZERO, Loc
from .dialect import mavlink as mav
from ..terrain import missing_mask

REQUEST_MIN_INTERVAL_S = 2.0  # AP_Terrain asks again no sooner than this


def terrain_request(v, codec):
    if not v.params["TERRAIN_ENABLE"]:
        return None
    v.terrain_update()
    block = v.terrain.request(v.params, v.terrain_here())
    if block is None:
        return None
    return codec.terrain_request_encode(block.lat_e7, block.lon_e7, block.spacing_m, missing_mask(block))


def _report(v, codec, loc: Loc, here: Loc | None, extrapolate: bool):
    r = v.terrain.report(v.params, loc, here, extrapolate)
    return codec.terrain_report_encode(loc.lat_e7, loc.lon_e7, r.spacing, r.terrain_height_m, r.current_height_m,
                                       r.pending, r.loaded)


def terrain_report(v, codec):
    """For where the vehicle is (0, 0 before it knows)."""
    if not v.params["TERRAIN_ENABLE"]:
        return None
    v.terrain_update()
    here = v.terrain_here()
    return _report(v, codec, ZERO if here is None else here, here, True)


def on_terrain_data(v, msg) -> None:
    v.terrain.store(v.params, msg.lat, msg.lon, msg.grid_spacing, msg.gridbit, msg.data)


def terrain_check_reply(v, codec, msg):
    """TERRAIN_CHECK's answer: a TERRAIN_REPORT for its location, the heights there only if held."""
    if not v.params["TERRAIN_ENABLE"]:
        return None
    return _report(v, codec, Loc(msg.lat, msg.lon, 0), v.terrain_here(), False)


BUILDERS = {mav.MAVLINK_MSG_ID_TERRAIN_REQUEST: terrain_request,
            mav.MAVLINK_MSG_ID_TERRAIN_REPORT: terrain_report}

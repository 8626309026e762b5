"""A ground station's terrain server: answers a vehicle's TERRAIN_REQUEST from a scenario's hills,
as MAVProxy's terrain module answers from SRTM.

For every sub-grid bit the request's mask sets, one TERRAIN_DATA: the 16 heights (whole metres
AMSL, north rows of 4 east points) of that 4 x 4 sub-grid of the block whose south-west corner the
request names, the points found by ArduPilot's flat-earth offsets from that corner. The heights are
the scenario's home altitude plus its [[terrain]] hills (sim/terrain.py), so a vehicle flying in that
scenario holds the same ground in its database as its rangefinder sees.

    autopilot --scenario S.toml --out udp:127.0.0.1:14551 ...
    python -m groundstation.terrain_tiles --scenario S.toml --url udpin:127.0.0.1:14551

Like MAVProxy it asks the vehicle for its EXTRA3 stream (where TERRAIN_REQUEST goes out) on the
first HEARTBEAT it hears, and says it is there with a HEARTBEAT of its own each second.
"""
from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Iterator

from firefly.sim.geo import GeoPoint, global_from_ned, ned_from_global
from firefly.sim.terrain import Terrain

SUBGRIDS_E = 8  # sub-grids across a block's east side (AP_Terrain's TERRAIN_GRID_BLOCK_MUL_Y)
MAV_TYPE_GCS, MAV_AUTOPILOT_INVALID = 6, 8
EXTRA3_STREAM, EXTRA3_HZ = 12, 2  # MAV_DATA_STREAM_EXTRA3; TERRAIN_REQUEST comes at most every 2 s anyway


def hills_amsl(home: GeoPoint, terrain: Terrain) -> Callable[[float, float], float]:
    """The ground's height AMSL [m] at (lat_deg, lon_deg): home's altitude plus the hills there."""
    def height(lat_deg: float, lon_deg: float) -> float:
        n, e, _ = ned_from_global(home, lat_deg, lon_deg, home.alt_m)
        return home.alt_m + terrain.height_m(n, e)
    return height


def tiles(lat_e7: int, lon_e7: int, spacing_m: int, mask: int,
          height_amsl: Callable[[float, float], float]) -> Iterator[tuple[int, list[int]]]:
    """(gridbit, 16 heights) for each sub-grid the mask asks for, lowest bit first."""
    corner = GeoPoint(lat_e7 * 1e-7, lon_e7 * 1e-7, 0.0)
    for bit in range(56):
        if not mask >> bit & 1:
            continue
        n0, e0 = bit // SUBGRIDS_E * 4, bit % SUBGRIDS_E * 4
        data = []
        for i in range(4):
            for j in range(4):
                p = global_from_ned(corner, (n0 + i) * float(spacing_m), (e0 + j) * float(spacing_m), 0.0)
                data.append(max(-32768, min(32767, round(height_amsl(p.lat_deg, p.lon_deg)))))
        yield bit, data


def answer(request, height_amsl: Callable[[float, float], float], codec) -> list:
    """The TERRAIN_DATA messages answering one TERRAIN_REQUEST (pymavlink's encoders, `codec`)."""
    return [codec.terrain_data_encode(request.lat, request.lon, request.grid_spacing, bit, data)
            for bit, data in tiles(request.lat, request.lon, request.grid_spacing, request.mask, height_amsl)]


def main(argv: list[str] | None = None) -> int:
    from pymavlink import mavutil

    from firefly.sim.scenario import ScenarioError, load_scenario
    parser = argparse.ArgumentParser(prog="terrain_tiles", description=__doc__.split("\n\n")[0])
    parser.add_argument("--scenario", required=True, help="scenario TOML whose [home] and [[terrain]] to serve")
    parser.add_argument("--url", default="udpin:127.0.0.1:14551",
                        help="the link to the vehicle (default: listening where an --out sends)")
    args = parser.parse_args(argv)
    try:
        sc = load_scenario(args.scenario)
    except ScenarioError as exc:
        print(exc, file=sys.stderr)
        return 2
    height = hills_amsl(sc.home, sc.sim.terrain)
    link = mavutil.mavlink_connection(args.url, source_system=255, source_component=190)
    asked = False
    while True:
        msg = link.recv_match(type=["TERRAIN_REQUEST", "HEARTBEAT"], blocking=True, timeout=1.0)
        if msg is None or msg.get_type() == "HEARTBEAT":
            link.mav.heartbeat_send(MAV_TYPE_GCS, MAV_AUTOPILOT_INVALID, 0, 0, 0)
            if msg is not None and not asked:  # the vehicle's EXTRA3 stream, where TERRAIN_REQUEST goes
                link.mav.request_data_stream_send(msg.get_srcSystem(), msg.get_srcComponent(), EXTRA3_STREAM,
                                                  EXTRA3_HZ, 1)
                asked = True
            continue
        for out in answer(msg, height, link.mav):
            link.mav.send(out)


if __name__ == "__main__":
    sys.exit(main())

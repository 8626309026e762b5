"""The terrain tile server against the real autopilot process: the autopilot boots in a scenario
with a hill and sends to two links, a ground station (pymavlink) and the tile server
(groundstation/terrain_tiles.py, its own process); the server's TERRAIN_DATA fill the vehicle's
terrain database until its TERRAIN_REPORT has nothing pending, and a TERRAIN_CHECK on the hill's top
is answered with the hill's height."""
from __future__ import annotations

import subprocess
import sys

import pytest

from firefly.groundstation.flight.autopilot_process import stop_process

from .conftest import REPO, free_udp_port, wait_for
from .pymav import Gcs, mav

pytestmark = pytest.mark.sitl
HOME_ALT_M = 584.0  # the autopilot's default home (ArduPilot SITL's CMAC field)
HILL_TOP_N_M, HILL_M = 400.0, 30.0
M_PER_DEG = 1.0e7 * 0.011131884502145034


def test_served_tiles_fill_the_database_and_a_check_finds_the_hill(autopilot_factory, tmp_path):
    scenario = tmp_path / "hill.toml"
    scenario.write_text(f"[[terrain]]\nnorth_m = {HILL_TOP_N_M}\neast_m = 0.0\nheight_m = {HILL_M}\nradius_m = 300.0\n")
    tiles_port = free_udp_port()
    ap = autopilot_factory(extra=("--scenario", str(scenario), "--out", f"udp:127.0.0.1:{tiles_port}"))
    server = subprocess.Popen([sys.executable, "-m", "firefly.groundstation.terrain_tiles", "--scenario", str(scenario),
                               "--url", f"udpin:127.0.0.1:{tiles_port}"], cwd=REPO)
    gcs = Gcs(ap.pymavlink_url)
    try:
        gcs.mav.request_data_stream_send(gcs.conn.target_system, gcs.conn.target_component,
                                         mav.MAV_DATA_STREAM_ALL, 4, 1)
        last: dict = {}

        def loaded() -> bool:
            msg = gcs.recv("TERRAIN_REPORT", 1.0)
            if msg is not None:
                last["report"] = msg
            r = last.get("report")
            return r is not None and r.spacing > 0 and r.pending == 0 and r.loaded > 0
        wait_for(loaded, 60.0, "the terrain database filled by the tile server")
        report = last["report"]
        assert report.terrain_height == pytest.approx(HOME_ALT_M, abs=1.0)
        lat = report.lat + round(HILL_TOP_N_M / M_PER_DEG * 1e7)
        gcs.mav.terrain_check_send(lat, report.lon)
        check = gcs.recv("TERRAIN_REPORT", 5.0, lambda m: m.lat == lat and m.lon == report.lon)
        assert check is not None, "no TERRAIN_REPORT answering the TERRAIN_CHECK"
        assert check.spacing == 100
        # the 100 m grid round the top, interpolated: its points up to 71 m off the top stand >= 26 m high
        assert check.terrain_height == pytest.approx(HOME_ALT_M + HILL_M, abs=4.5)
    finally:
        gcs.close()
        stop_process(server)

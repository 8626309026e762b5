"""`groundstation explore` against the real autopilot on a small world: the fire it declares is
the scenario's, within one cell, and the vehicle ends on the ground at home, disarmed."""
from __future__ import annotations

import json
import re
import subprocess
import sys

import pytest

from .conftest import REPO, free_udp_port
from .pymav import Gcs

pytestmark = pytest.mark.sitl
SMALL_WORLD = REPO / "tests" / "sitl" / "data" / "small_world.toml"


def test_explore_finds_the_fire_and_lands(autopilot_factory, tmp_path):
    ap = autopilot_factory(speedup="20", extra=("--scenario", str(SMALL_WORLD)))
    plot = tmp_path / "explore.png"
    result = subprocess.run([sys.executable, "-m", "groundstation", "explore", "--url", ap.mavsdk_url,
                             "--scenario", str(SMALL_WORLD), "--plot", str(plot)],
                            cwd=REPO, capture_output=True, text=True, timeout=240)
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    declared = re.search(r"fire declared at N ([\d.]+) m E ([\d.]+) m", result.stdout)
    assert declared, result.stdout
    n, e = float(declared.group(1)), float(declared.group(2))
    # Judge against the scenario file's fire directly, not against the companion's own verdict.
    assert abs(n - 135.0) <= 15.0 and abs(e - 72.0) <= 15.0, (n, e)
    assert "within one 10 m cell" in result.stdout
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # An independent look at the vehicle: on the ground at home, disarmed.
    gcs = Gcs(f"udpin:127.0.0.1:{ap.port}")
    hb = gcs.recv("HEARTBEAT", 5)
    pos = gcs.recv("GLOBAL_POSITION_INT", 5)
    home = gcs.recv("HOME_POSITION", 5)
    gcs.close()
    assert not hb.base_mode & 128
    assert abs(pos.relative_alt) < 300
    assert abs(pos.lat - home.latitude) < 30 and abs(pos.lon - home.longitude) < 40  # within ~3 m


def test_explore_says_so_and_exits_nonzero_when_no_vehicle_answers(tmp_path):
    result = subprocess.run([sys.executable, "-m", "groundstation", "explore", "--url", f"udpin://127.0.0.1:{free_udp_port()}",
                             "--plot", str(tmp_path / "x.png")], cwd=REPO, capture_output=True, text=True,
                            timeout=60)
    assert result.returncode != 0
    assert "no autopilot answered" in result.stderr and "Traceback" not in result.stderr


def test_evaluate_flight_flies_an_episode_and_lands_it_at_home(tmp_path):
    out = tmp_path / "flight.json"
    result = subprocess.run([sys.executable, "-m", "groundstation", "evaluate", "--scenario", str(SMALL_WORLD),
                             "--episodes", "1", "--policies", "gig", "--flight", "1", "--json", str(out)],
                            cwd=REPO, capture_output=True, text=True, timeout=240)
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    flight = json.loads(out.read_text())["flights"]["episodes"][0]
    assert flight["flown"], flight
    # The episode's own fire (not the scenario file's): the flight must find it and come home.
    (fire_n, fire_e, _), = flight["fire"]
    assert (fire_n, fire_e) != (135.0, 72.0)
    n, e = flight["declared"]
    assert abs(n - fire_n) <= 15.0 and abs(e - fire_e) <= 15.0, (flight["declared"], flight["fire"])
    assert flight["landed_from_home_m"] < 5.0
    assert "flown: success 1.00" in result.stdout

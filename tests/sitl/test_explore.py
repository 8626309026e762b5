"""`groundstation explore` against the real autopilot on a small world: the fire it declares is
the scenario's, within one cell, and the vehicle ends on the ground at home, disarmed. The flown
episodes of `evaluate --flight` keep the search's settings, and a companion whose own autopilot
process exits says so at once."""
from __future__ import annotations

import asyncio
import json
import math
import re
import subprocess
import sys

import pytest

from firefly.groundstation.flight.autopilot_process import AutopilotExited, start_autopilot
from firefly.groundstation.flight.vehicle_link import VehicleLink

from .conftest import REPO, free_udp_port
from .pymav import Gcs

pytestmark = pytest.mark.sitl
SMALL_WORLD = REPO / "tests" / "sitl" / "data" / "small_world.toml"


@pytest.fixture
def refused_scenario(tmp_path):
    """The small world with a [faults] table the autopilot refuses (the companion reads only the world)."""
    path = tmp_path / "refused.toml"
    path.write_text(SMALL_WORLD.read_text() + "\n[faults]\nSIM_NOT_A_FAULT = 1\n")
    return path


def test_explore_finds_the_fire_and_lands(autopilot_factory, tmp_path):
    ap = autopilot_factory(speedup="20", extra=("--scenario", str(SMALL_WORLD)))
    plot = tmp_path / "explore.png"
    result = subprocess.run([sys.executable, "-m", "firefly.groundstation", "explore", "--url", ap.mavsdk_url,
                             "--scenario", str(SMALL_WORLD), "--plot", str(plot)],
                            cwd=REPO, capture_output=True, text=True, timeout=240)
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    declared = re.search(r"fire declared at N ([\d.]+) m E ([\d.]+) m", result.stdout)
    assert declared, result.stdout
    n, e = float(declared.group(1)), float(declared.group(2))
    # Judge against the scenario file's fire directly, not against the companion's own verdict.
    assert abs(n - 135.0) <= 15.0 and abs(e - 72.0) <= 15.0, (n, e)
    assert "within one 10 m cell" in result.stdout
    # not told how many fires: after the find it looked on (a climb over it, here) until sure of no other
    assert "1 fire(s): the first found after" in result.stdout and "confident there is no other fire" in result.stdout
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
    result = subprocess.run([sys.executable, "-m", "firefly.groundstation", "explore", "--url", f"udpin://127.0.0.1:{free_udp_port()}",
                             "--plot", str(tmp_path / "x.png")], cwd=REPO, capture_output=True, text=True,
                            timeout=60)
    assert result.returncode != 0
    assert "no autopilot answered" in result.stderr and "Traceback" not in result.stderr


def test_evaluate_flight_flies_an_episode_and_lands_it_at_home(tmp_path):
    out = tmp_path / "flight.json"
    result = subprocess.run([sys.executable, "-m", "firefly.groundstation", "evaluate", "--scenario", str(SMALL_WORLD),
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


def test_evaluate_flight_flies_with_the_budget_and_speed_it_is_given(tmp_path):
    out = tmp_path / "flight.json"
    # Threshold 1: nothing but the 60 m budget can end the search; 2 m/s: slower than the 5 m/s default.
    result = subprocess.run([sys.executable, "-m", "firefly.groundstation", "evaluate", "--scenario", str(SMALL_WORLD),
                             "--episodes", "2", "--policies", "gig", "--flight", "2", "--budget", "60",
                             "--speed", "2", "--no-confirm", "--threshold", "1", "--json", str(out)],
                            cwd=REPO, capture_output=True, text=True, timeout=240)
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    flights = json.loads(out.read_text())["flights"]["episodes"]
    assert all(f["flown"] and f["forced"] for f in flights), flights
    # The search stops at the budget (6,000 m by default), within one observation (2 m at 2 m/s)...
    assert all(60.0 <= f["path_m"] <= 60.0 + 2.0 + 1.0 for f in flights), flights
    # ...and never flies faster than it was told (the default would average about 4 m/s here).
    assert sum(f["path_m"] for f in flights) / sum(f["survey_vehicle_s"] for f in flights) <= 2.1, flights


def test_a_scenario_its_autopilot_refuses_ends_explore_at_once_with_one_line(refused_scenario, tmp_path):
    result = subprocess.run([sys.executable, "-m", "firefly.groundstation", "explore", "--scenario", str(refused_scenario),
                             "--plot", str(tmp_path / "x.png")], cwd=REPO, capture_output=True, text=True, timeout=60)
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    # The autopilot's own words, asked before any vehicle starts; not a connection timeout.
    assert lines[0].startswith(f"groundstation: error: {refused_scenario}: [faults].SIM_NOT_A_FAULT")


def test_evaluate_flight_refuses_a_scenario_its_autopilot_refuses_before_any_episode(refused_scenario):
    result = subprocess.run([sys.executable, "-m", "firefly.groundstation", "evaluate", "--scenario", str(refused_scenario),
                             "--episodes", "1", "--policies", "gig", "--flight", "1"],
                            cwd=REPO, capture_output=True, text=True, timeout=60)
    assert result.returncode == 2 and result.stdout == ""
    assert result.stderr.strip().splitlines() == [result.stderr.strip()]
    assert result.stderr.startswith("groundstation: error: ") and "SIM_NOT_A_FAULT" in result.stderr


async def test_guard_cancels_the_flight_when_its_autopilot_exits(refused_scenario, tmp_path):
    ap = start_autopilot(tmp_path / "state", extra=("--scenario", str(refused_scenario)), cwd=REPO,
                         capture_stderr=True)
    cleaned_up = []

    async def flight_waiting_for_a_vehicle():
        try:
            await asyncio.Event().wait()  # nothing will ever answer
        finally:
            cleaned_up.append(True)
    try:
        with pytest.raises(AutopilotExited, match=r"status 2 \(autopilot: error: .*SIM_NOT_A_FAULT"):
            await ap.guard(flight_waiting_for_a_vehicle())
    finally:
        assert ap.stop() == 2
    assert cleaned_up == [True]


async def test_guard_passes_the_flight_result_while_its_autopilot_runs(autopilot):
    async def home_of_the_vehicle():
        link = await VehicleLink.connect(autopilot.mavsdk_url)
        try:
            await link.wait_armable()
            return link.home
        finally:
            link.close()
    home = await autopilot.guard(home_of_the_vehicle())
    assert math.isclose(home.latitude_deg, -35.363261, abs_tol=1e-6)
    assert autopilot.process.poll() is None


WINDY = "[wind]\nspeed_m_s = 4.0\nfrom_direction_deg = 270.0\n\n"
DRAG_FUSION = "[params]\nEK3_DRAG_BCOEF_X = 9.5\nEK3_DRAG_BCOEF_Y = 9.5\nEK3_DRAG_MCOEF = 0.082\n\n"


def fly_windy(autopilot_factory, tmp_path, tables: str, *flags: str) -> str:
    """explore on the small world with the plume leaning 20 m east at the survey height (4 m/s from
    the west, gases rising at 5 m/s); the companion's output, after checking it declared the fire
    (at N 135, E 72), not its hot spot (at E 92)."""
    scenario = tmp_path / "windy.toml"
    scenario.write_text(SMALL_WORLD.read_text().replace("[world]", tables + "[world]\nplume_rise_m_s = 5.0"))
    ap = autopilot_factory(speedup="20", extra=("--scenario", str(scenario)))
    result = subprocess.run([sys.executable, "-m", "firefly.groundstation", "explore", "--url", ap.mavsdk_url,
                             "--scenario", str(scenario), "--plot", str(tmp_path / "windy.png"), *flags],
                            cwd=REPO, capture_output=True, text=True, timeout=240)
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    declared = re.search(r"fire declared at N ([\d.]+) m E ([\d.]+) m", result.stdout)
    assert declared, result.stdout
    n, e = float(declared.group(1)), float(declared.group(2))
    assert abs(n - 135.0) <= 15.0 and abs(e - 72.0) <= 15.0, (n, e)
    return result.stdout


def test_explore_estimates_the_wind_from_the_lean_when_the_vehicle_reports_none(autopilot_factory, tmp_path):
    """No drag fusion: the vehicle's WIND says zero, as ArduCopter's does. The companion estimates
    the wind from ATTITUDE and velocity in steady flight, says what it found, and declares the fire."""
    out = fly_windy(autopilot_factory, tmp_path, WINDY)
    assert "wind: estimated from how the vehicle leans" in out
    wind = re.search(r"wind estimated from (\d+) lean samples: ([\d.]+) m/s from (\d+) deg", out)
    assert wind, out
    assert int(wind.group(1)) >= 20
    assert abs(float(wind.group(2)) - 4.0) < 0.5 and abs(int(wind.group(3)) - 270) <= 10


def test_explore_told_the_wind_reads_the_vehicles_wind_report(autopilot_factory, tmp_path):
    """--told-wind with drag fusion on (EK3_DRAG_*, as ArduCopter needs it to estimate wind): the
    companion asks for WIND, says what it read, and the search takes that."""
    out = fly_windy(autopilot_factory, tmp_path, WINDY + DRAG_FUSION, "--told-wind")
    wind = re.search(r"wind ([\d.]+) m/s from (\d+) deg \(WIND\)", out)
    assert wind, out
    assert abs(float(wind.group(1)) - 4.0) < 0.5 and abs(int(wind.group(2)) - 270) <= 5


def test_explore_looks_for_two_fires_and_declares_both(autopilot_factory, tmp_path):
    """Not told how many fires, on a world with two: after the first find the search explains it
    away and goes on; both are declared, each within a cell of its own fire, the search ends
    confident there is no third, and the vehicle lands."""
    scenario = tmp_path / "two_fires.toml"
    scenario.write_text(SMALL_WORLD.read_text() + "\n[[fire]]\nn_m = 45.0\ne_m = 150.0\nstrength_k = 40.0\n")
    ap = autopilot_factory(speedup="20", extra=("--scenario", str(scenario)))
    result = subprocess.run([sys.executable, "-m", "firefly.groundstation", "explore", "--url", ap.mavsdk_url,
                             "--scenario", str(scenario), "--plot", str(tmp_path / "two.png")],
                            cwd=REPO, capture_output=True, text=True, timeout=240)
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    declared = [(float(n), float(e)) for n, e in re.findall(r"fire declared at N ([\d.]+) m E ([\d.]+) m", result.stdout)]
    assert len(declared) == 2, result.stdout
    fires = [(135.0, 72.0), (45.0, 150.0)]
    for fire in fires:  # each fire has its own declaration within a cell and a half
        assert any(abs(n - fire[0]) <= 15.0 and abs(e - fire[1]) <= 15.0 for n, e in declared), (fire, declared)
    assert "2 of 2 fires found" in result.stdout
    assert "confident there is no other fire" in result.stdout
    assert (tmp_path / "two.png").stat().st_size > 0

"""The cooperative search flown end to end: two real vehicles of one autopilot process, one
companion, one belief. They declare the small world's fire within a cell and both land at their
own homes; and when one vehicle's motor fails mid-search, the companion drops it and the other
finishes the search and lands."""
from __future__ import annotations

import asyncio
import json
import re
import subprocess
import sys
import threading

import pytest

from firefly.groundstation.flight.autopilot_process import free_udp_port
from firefly.groundstation.flight.team_explore import explore_team
from firefly.sim.scenario import load_scenario

from .conftest import REPO
from .pymav import Gcs

pytestmark = pytest.mark.sitl
SMALL_WORLD = REPO / "tests" / "sitl" / "data" / "small_world.toml"
FIRE_N, FIRE_E = 135.0, 72.0  # the small world's fire
CELL_M = 10.0


def test_two_vehicles_find_the_fire_together_and_land_at_their_homes(tmp_path):
    plot = tmp_path / "team.png"
    result = subprocess.run([sys.executable, "-m", "firefly.groundstation", "explore", "--vehicles", "2", "--speedup", "50",
                             "--scenario", str(SMALL_WORLD), "--plot", str(plot)],
                            cwd=REPO, capture_output=True, text=True, timeout=300)
    out = result.stdout
    assert result.returncode == 0, out[-2000:] + result.stderr[-2000:]
    assert "surveying 200 m x 200 m at heights 25, 30 m with team policy joint" in out, out
    n, e = (float(g) for g in re.search(r"fire declared at N ([-\d.]+) m E ([-\d.]+) m", out).groups())
    assert abs(n - FIRE_N) <= 1.5 * CELL_M and abs(e - FIRE_E) <= 1.5 * CELL_M, (n, e)
    paths = [float(p) for p in re.findall(r"vehicle \d: path (\d+) m", out)]
    assert len(paths) == 2 and all(p > 20 for p in paths), f"both vehicles searched: {paths}"
    landed = [float(d) for d in re.findall(r"vehicle \d landed and disarmed ([\d.]+) m from its home", out)]
    assert len(landed) == 2 and all(d < 3.0 for d in landed), out[-1000:]
    assert plot.stat().st_size > 10_000


def fail_a_motor(url: str, system_id: int, after_s: float, started: threading.Event, done: list) -> None:
    """Once the search has started, let `after_s` of the vehicle's own time pass, then stop its
    front motor (SIM_ENGINE_FAIL 4: output 3, at SIM_ENGINE_MUL's default 0)."""
    gcs = Gcs(url)
    try:
        assert started.wait(120), "the search never started"
        while gcs.conn.recv_match(blocking=False) is not None:  # what queued up before the start
            pass
        first = gcs.recv("GLOBAL_POSITION_INT", 5)
        assert first is not None
        gcs.recv("GLOBAL_POSITION_INT", 60, lambda m: m.time_boot_ms >= first.time_boot_ms + 1000 * after_s)
        gcs.mav.param_set_send(system_id, 1, b"SIM_ENGINE_FAIL", 4.0, 9)
        echo = gcs.recv("PARAM_VALUE", 5, lambda m: m.param_id == "SIM_ENGINE_FAIL" and m.param_value == 4.0)
        assert echo is not None, "the vehicle did not take the motor fault"
        done.append(first.time_boot_ms / 1000.0 + after_s)
    finally:
        gcs.close()


def test_a_vehicle_whose_motor_fails_drops_out_and_the_other_finishes(autopilot_factory):
    side = free_udp_port(2)  # a pymavlink link to each vehicle besides the companion's: vehicle 2's is side + 10
    ap = autopilot_factory(speedup="50", extra=("--scenario", str(SMALL_WORLD), "--count", "2",
                                                "--out", f"udp:127.0.0.1:{side}"))
    world = load_scenario(SMALL_WORLD).world
    lines: list[str] = []
    started = threading.Event()

    def say(line: str) -> None:
        lines.append(line)
        if line.startswith("wind"):
            started.set()
    failed_at: list[float] = []
    injector = threading.Thread(target=fail_a_motor, args=(f"udpin:127.0.0.1:{side + 10}", 2, 8.0, started, failed_at))
    injector.start()
    try:
        result = asyncio.run(asyncio.wait_for(explore_team(ap.mavsdk_urls(2), world, "joint", None, True, say=say), 240))
    finally:
        started.set()
        injector.join(90)
    text = "\n".join(lines)
    assert failed_at, "the motor fault was not injected"
    assert result["dropped"] == [1], text
    assert re.search(r"vehicle 2 is out of the search: (it fell|it disarmed|it left GUIDED)", text), text
    assert result["within_one_cell"], text
    assert result["paths_m"][1] > 20, "the failed vehicle had searched before its motor failed"
    assert result["paths_m"][0] > result["paths_m"][1] + 50, "the survivor flew on after the other fell"
    assert result["landed_from_home_m"][0] < 3.0 and result["landed_from_home_m"][1] is None, result


def test_evaluate_flies_team_episodes_beside_the_decided_ones(tmp_path):
    out = tmp_path / "team.json"
    result = subprocess.run([sys.executable, "-m", "firefly.groundstation", "evaluate", "--scenario", str(SMALL_WORLD),
                             "--vehicles", "2", "--policies", "joint", "--episodes", "2", "--flight", "1",
                             "--flight-speedup", "50", "--json", str(out)],
                            cwd=REPO, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    assert "flying episodes 0..0 with joint (2 vehicles)" in result.stdout
    flight = json.loads(out.read_text())["flights"]["episodes"][0]
    assert flight["flown"] and flight["success"], flight
    assert len(flight["paths_m"]) == 2 and len(flight["landed_each_m"]) == 2
    assert flight["landed_from_home_m"] == max(flight["landed_each_m"]) < 3.0, flight
    assert "landed at home 1.00" in result.stdout, result.stdout[-1500:]

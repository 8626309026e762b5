"""The plugin as a user meets it: test files in a fresh directory, run by a separate pytest that
loads the plugin from the installed package's entry point (no conftest), serially and under
pytest-xdist, and nothing left running afterwards."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from .inner import autopilots_under, run_pytest

pytestmark = pytest.mark.sitl
REPO = Path(__file__).resolve().parents[2]


def readme_example() -> str:
    """The first Python block of the README's "Testing your own drone code" section."""
    text = (REPO / "README.md").read_text()
    section = text[text.index("## Testing your own drone code"):]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


def test_the_readme_example_runs_green_serially_and_under_xdist(tmp_path):
    files = {"test_my_drone_app.py": readme_example()}
    serial = run_pytest(tmp_path / "serial", files, "--firefly-evidence", str(tmp_path / "serial" / "evidence"))
    assert serial.returncode == 0, serial.output
    assert serial.outcomes() == {"passed": 3}, serial.output
    assert autopilots_under(tmp_path) == []
    parallel = run_pytest(tmp_path / "xdist", files, "-n", "2",
                          "--firefly-evidence", str(tmp_path / "xdist" / "evidence"))
    assert parallel.returncode == 0, parallel.output
    assert parallel.outcomes() == {"passed": 3}, parallel.output
    assert "2 workers" in parallel.output
    assert autopilots_under(tmp_path) == []
    # Passing tests leave no evidence behind.
    assert not any((tmp_path / "xdist" / "evidence").iterdir())


FAILING_AND_PASSING = '''
import pytest

@pytest.mark.firefly(speedup="inf")
def test_passes(firefly):
    firefly.sleep(1.0)

def test_leaves_the_vehicle_flying(firefly):
    firefly.take_off(10.0)
'''


def test_a_broken_example_reports_its_tlog_and_keeps_only_its_own_evidence(tmp_path):
    example = (REPO / "examples" / "tests" / "test_mavsdk_takeoff_goto_land.py").read_text()
    broken = example.replace("assert abs(landed.north_m - 30.0) < 2.0", "assert abs(landed.north_m - 30.0) < -1.0")
    assert broken != example, "the example's assertion this test breaks has changed"
    evidence = tmp_path / "evidence"
    run = run_pytest(tmp_path / "run", {"test_broken.py": broken, "test_others.py": FAILING_AND_PASSING},
                     "--firefly-evidence", str(evidence), "--firefly-speedup", "50")
    assert run.outcomes() == {"failed": 1, "passed": 2}, run.output
    section = run.output[run.output.index("firefly ---"):]
    tlog = Path(re.search(r"tlog (\S+\.tlog)", section).group(1))
    assert tlog.is_file() and tlog.stat().st_size > 10_000, "the failed flight's tlog is kept, with the flight in it"
    assert (tlog.parent / "state.csv").stat().st_size > 1000
    assert re.search(r"seed \d+, speedup 50", section)
    assert "reproduce: autopilot " in section
    # Only the failed test's directory is left; the passing one's (and the one left flying) are gone.
    assert [p.name.split("-")[0] for p in evidence.iterdir()] == ["test_takeoff_goto_north_and_land"]
    assert autopilots_under(tmp_path) == []
    kept = run_pytest(tmp_path / "keep", {"test_others.py": FAILING_AND_PASSING}, "--firefly-keep",
                      "--firefly-evidence", str(tmp_path / "kept"))
    assert kept.outcomes() == {"passed": 2}, kept.output
    assert len(list((tmp_path / "kept").glob("*/vehicle.tlog"))) == 2


BAD_INPUT = '''
import pytest

@pytest.mark.firefly(spedup=3)
def test_unknown_key(firefly): pass

@pytest.mark.firefly(speedup=-1)
def test_bad_speedup(firefly): pass

@pytest.mark.firefly(count=0)
def test_bad_count(firefly): pass

@pytest.mark.firefly(faults={"WPNAV_SPEED": 500})
def test_fault_not_sim(firefly): pass

@pytest.mark.firefly(3)
def test_positional(firefly): pass

@pytest.mark.firefly(scenario="missing.toml")
def test_missing_scenario(firefly): pass

@pytest.mark.firefly(scenario="broken.toml")
def test_scenario_the_autopilot_refuses(firefly): pass

@pytest.mark.firefly(params={"NO_SUCH_PARAM": 1})
def test_unknown_param(firefly): pass

@pytest.mark.firefly(params={"WPNAV_SPEED": 1e9})
def test_param_out_of_range(firefly): pass
'''
EXPECTED_ERRORS = {
    "test_unknown_key": "@pytest.mark.firefly: unknown key 'spedup'",
    "test_bad_speedup": "@pytest.mark.firefly(speedup=...): expected a positive number",
    "test_bad_count": "@pytest.mark.firefly(count=...): expected an integer in 1..50",
    "test_fault_not_sim": "WPNAV_SPEED is not a SIM_* parameter",
    "test_positional": "@pytest.mark.firefly: takes keywords only",
    "test_missing_scenario": "@pytest.mark.firefly(scenario=...): no scenario file",
    "test_scenario_the_autopilot_refuses": "unknown key 'speeed'",
    "test_unknown_param": "NO_SUCH_PARAM",
    "test_param_out_of_range": "WPNAV_SPEED = 1e+09 refused",
}


def test_bad_markers_and_refused_settings_fail_their_test_at_setup_in_one_line(tmp_path):
    run = run_pytest(tmp_path / "run", {"test_bad.py": BAD_INPUT, "broken.toml": "[wind]\nspeeed = 3\n"},
                     "--firefly-evidence", str(tmp_path / "evidence"))
    assert run.outcomes() == {"errors": len(EXPECTED_ERRORS)}, run.output
    assert "Traceback" not in run.output
    for test, expected in EXPECTED_ERRORS.items():
        block = run.output[run.output.index(f"ERROR at setup of {test} "):]
        first_line = block.splitlines()[1]
        assert expected in first_line, f"{test}: {first_line!r}"
    assert autopilots_under(tmp_path) == []
    usage = run_pytest(tmp_path / "usage", {"test_x.py": "def test_x(firefly): pass\n"}, "--firefly-speedup=fast")
    assert usage.returncode == 4 and "--firefly-speedup: expected a positive number or 'inf'" in usage.output
    assert "Traceback" not in usage.output


BEHAVIOUR = '''
import asyncio
import json
import os

import pytest

SEEDS = os.environ["SEEDS_FILE"]


def record(name, seed):
    with open(SEEDS, "a") as f:
        f.write(json.dumps([name, seed]) + "\\n")


@pytest.mark.firefly(speedup="inf")
def test_first(firefly):
    record("first", firefly.seed)


@pytest.mark.firefly(speedup="inf")
def test_second(firefly):
    record("second", firefly.seed)


@pytest.mark.firefly(seed=7, speedup="inf")
def test_seed_from_marker(firefly):
    assert firefly.seed == 7


@pytest.mark.firefly(speedup=1)
def test_sleep_is_vehicle_time(firefly):
    before = firefly.state().time_s
    after = firefly.sleep(0.5)
    assert after.time_s - before >= 0.5


@pytest.mark.firefly(speedup=50)
def test_a_wait_that_never_ends_times_out_in_vehicle_time(firefly):
    from autopilot.testing import FireflyError
    with pytest.raises(FireflyError, match="timed out after 3 s of vehicle time waiting for flight"):
        firefly.wait_until(lambda s: s.altitude_m > 5, timeout=3, what="flight")


@pytest.mark.firefly(count=3, speedup=50)
def test_fleet(firefly_fleet, firefly):
    assert firefly is firefly_fleet[0]
    assert [v.system_id for v in firefly_fleet] == [1, 2, 3]
    for v in firefly_fleet:
        hb = v.mavlink().recv_match(type="HEARTBEAT", blocking=True, timeout=5)
        assert hb.get_srcSystem() == v.system_id
        assert v.state().on_ground
    assert firefly_fleet[1].state().east_m == pytest.approx(5.0)


@pytest.mark.firefly(airborne=10, params={"WPNAV_SPEED": 750}, speedup=50)
def test_params_set_before_takeoff(firefly):
    conn = firefly.mavlink()
    conn.mav.param_request_read_send(firefly.system_id, 1, b"WPNAV_SPEED", -1)
    value = conn.recv_match(type="PARAM_VALUE", blocking=True, timeout=5,
                            condition="PARAM_VALUE.param_id == 'WPNAV_SPEED'")
    assert value.param_value == 750
    assert firefly.state().armed and abs(firefly.state().altitude_m - 10) < 0.5


@pytest.mark.firefly(airborne=10, faults={"SIM_GPS_DISABLE": 1}, speedup=50)
def test_faults_start_with_the_test(firefly):
    landed = firefly.wait_until(lambda s: s.landed, timeout=120, what="the failsafe's landing")
    assert landed.mode == "LAND"
'''


def test_seeds_waits_fleets_and_ready_states(tmp_path, monkeypatch):
    seeds = tmp_path / "seeds.jsonl"
    monkeypatch.setenv("SEEDS_FILE", str(seeds))
    runs = [run_pytest(tmp_path / "run", {"test_behaviour.py": BEHAVIOUR}, "--firefly-evidence",
                       str(tmp_path / "evidence")) for _ in range(2)]
    for run in runs:
        assert run.outcomes() == {"passed": 8}, run.output
    recorded = [tuple(__import__("json").loads(line)) for line in seeds.read_text().splitlines()]
    first_run, second_run = dict(recorded[:2]), dict(recorded[2:])
    assert first_run["first"] != first_run["second"], "two tests fly different noise"
    assert first_run == second_run, "the same test flies the same seed every run"
    assert autopilots_under(tmp_path) == []


STRICT = '''
import pytest


@pytest.mark.asyncio
async def test_async_in_strict_mode(firefly):
    system = await firefly.mavsdk()
    assert await system.has_autopilot()
    state = await firefly.sleep_async(1.0)
    assert state.on_ground


def test_sync_in_strict_mode(firefly):
    assert firefly.mavlink().recv_match(type="HEARTBEAT", blocking=True, timeout=5) is not None
'''


def test_pytest_asyncio_strict_mode(tmp_path):
    run = run_pytest(tmp_path / "run", {"test_strict.py": STRICT}, "--firefly-evidence", str(tmp_path / "evidence"),
                     asyncio_mode="strict")
    assert run.outcomes() == {"passed": 2}, run.output
    assert autopilots_under(tmp_path) == []

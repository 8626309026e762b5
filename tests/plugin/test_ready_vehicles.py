"""The vehicle a test gets is the one it asked for: its seed, its fleet, its parameters and faults
already in effect, and waits that count the vehicle's own time."""
from __future__ import annotations

import re

import pytest

from .inner import run_inner

pytest_plugins = ["pytester"]
pytestmark = pytest.mark.sitl

SEEDS = '''
from pathlib import Path

import pytest


def report_seed(request, firefly):
    """SEED <node id> <firefly.seed> <the --seed of the autopilot process writing this tlog>"""
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            words = (entry / "cmdline").read_bytes().decode(errors="replace").split("\\0")
        except OSError:
            continue
        if "firefly.autopilot" in words and str(firefly.tlog_path) in words:
            print(f"SEED {request.node.nodeid} {firefly.seed} {words[words.index('--seed') + 1]}")
            return
    raise AssertionError("no autopilot process found")


def test_first(request, firefly):
    report_seed(request, firefly)


def test_second(request, firefly):
    report_seed(request, firefly)


@pytest.mark.firefly(seed=7)
def test_seed_from_the_marker(request, firefly):
    report_seed(request, firefly)
'''


def seeds(result: pytest.RunResult) -> list[tuple[str, int]]:
    """(node id, seed) of each SEED line, after checking that the seed is the one the autopilot
    process was started with."""
    found = []
    for node_id, seed, given in re.findall(r"SEED (\S+) (\d+) (\d+)", result.stdout.str()):
        assert seed == given, f"{node_id}: firefly.seed is {seed} but the autopilot was started with --seed {given}"
        found.append((node_id, int(seed)))
    return found


def test_each_test_has_its_own_seed_and_the_same_one_every_run(pytester):
    """Two tests of one file fly different seeds (different sensor noise); the same file run again
    gets the same seeds, even invoked so that its node ids differ (another rootdir); `seed=7` in
    the marker gives 7. Each seed is also the one the autopilot process was started with, read
    from its command line."""
    pytester.makepyfile(test_seeds=SEEDS)
    tests = ["test_first", "test_second", "test_seed_from_the_marker"]
    first_run = run_inner(pytester, "-s", "--firefly-speedup=inf")
    first_run.assert_outcomes(passed=3)
    first = seeds(first_run)
    assert [node_id for node_id, _ in first] == [f"test_seeds.py::{test}" for test in tests]
    by_test = {node_id.split("::")[1]: seed for node_id, seed in first}
    assert by_test["test_first"] != by_test["test_second"]
    assert by_test["test_seed_from_the_marker"] == 7

    again_run = run_inner(pytester, "-s", "--firefly-speedup=inf", f"--rootdir={pytester.path.parent}",
                          str(pytester.path / "test_seeds.py"))
    again_run.assert_outcomes(passed=3)
    again = seeds(again_run)
    assert [node_id for node_id, _ in again] == [f"{pytester.path.name}/test_seeds.py::{test}" for test in tests]
    assert [seed for _, seed in again] == [seed for _, seed in first]


READY = '''
import time

import pytest


def read_param(firefly, name, timeout_s=10.0):
    """The vehicle's value of `name`, asked with PARAM_REQUEST_READ on the test's pymavlink link
    (asked again every 0.5 s until the PARAM_VALUE comes)."""
    conn = firefly.mavlink()
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        conn.mav.param_request_read_send(firefly.system_id, 1, name.encode(), -1)
        reply = conn.recv_match(type="PARAM_VALUE", blocking=True, timeout=0.5,
                                condition=f"PARAM_VALUE.param_id == {name!r}")
        if reply is not None:
            return reply.param_value
    raise AssertionError(f"no PARAM_VALUE for {name} within {timeout_s:g} s")


@pytest.mark.firefly(count=3, speedup=50)
def test_a_fleet_of_three(firefly_fleet, firefly):
    assert firefly is firefly_fleet[0]
    assert [vehicle.system_id for vehicle in firefly_fleet] == [1, 2, 3]
    for vehicle in firefly_fleet:
        heartbeat = vehicle.mavlink().recv_match(type="HEARTBEAT", blocking=True, timeout=5)
        assert heartbeat is not None and heartbeat.get_srcSystem() == vehicle.system_id
        state = vehicle.state()
        assert state.on_ground and not state.armed
    where = {(round(v.state().north_m), round(v.state().east_m)) for v in firefly_fleet}
    assert len(where) == 3, f"three airframes in three places, not one state read three times: {where}"
    before = firefly_fleet[2].state().time_s
    assert firefly_fleet[2].sleep(1.0).time_s >= before + 1.0


@pytest.mark.firefly(speedup=1)
def test_sleep_at_real_time(firefly):
    before = firefly.state().time_s
    firefly.sleep(0.5)
    assert firefly.state().time_s - before >= 0.5


@pytest.mark.firefly(speedup=50)
def test_sleep_counts_vehicle_time_not_wall_time(firefly):
    before, wall_before = firefly.state().time_s, time.monotonic()
    firefly.sleep(10.0)
    assert firefly.state().time_s - before >= 10.0
    assert time.monotonic() - wall_before < 5.0  # 10 s at 50x is 0.2 s of wall time


@pytest.mark.firefly(params={"WPNAV_SPEED": 750}, speedup=50)
def test_params_are_in_effect_when_the_test_starts(firefly):
    assert read_param(firefly, "WPNAV_SPEED") == 750  # the default is 1000


@pytest.mark.firefly(airborne=10, faults={"SIM_GPS_DISABLE": 1}, speedup=50)
def test_a_gps_fault_set_before_the_test_lands_the_flying_vehicle(firefly):
    assert not firefly.state().on_ground
    landed = firefly.wait_until(lambda s: s.landed, timeout=120, what="the GPS failsafe's landing")
    assert landed.mode == "LAND"


@pytest.mark.firefly(startup="realistic", airborne=5, speedup="inf")
def test_airborne_after_a_realistic_start_up(firefly):
    state = firefly.state()
    assert not state.on_ground and state.mode == "GUIDED"
    assert state.time_s > 40, "GUIDED is not armable before the realistic start-up's position is good"


@pytest.mark.firefly(home=(-33.8568, 151.2153, 10), speedup=50)
def test_a_home_south_of_the_equator(firefly):
    position = firefly.mavlink().recv_match(type="GLOBAL_POSITION_INT", blocking=True, timeout=5)
    assert position is not None
    assert abs(position.lat / 1e7 + 33.8568) < 1e-3 and abs(position.lon / 1e7 - 151.2153) < 1e-3
'''

MERGED = '''
import pytest

pytestmark = pytest.mark.firefly(speedup=50, seed=11)


@pytest.mark.firefly(seed=12)
def test_the_test_marker_wins_where_both_set_a_key(firefly):
    assert firefly.seed == 12 and firefly.run.settings.speedup == 50


def test_the_module_marker_alone(firefly):
    assert firefly.seed == 11 and firefly.run.settings.speedup == 50
'''


def test_fleets_waits_params_and_faults_are_ready_when_the_test_starts(pytester):
    """One inner run:
    - count=3: `firefly_fleet` holds system ids 1, 2, 3, each with its own pymavlink link (its
      HEARTBEAT comes from that system) and its own true state (three different places); `firefly`
      is the fleet's first vehicle; a wait on the third vehicle works;
    - at speedup 1, sleep(0.5) advances the true state's time by at least 0.5 s; at speedup 50
      sleep(10) advances it 10 s in much less than 10 s of wall time (vehicle time, not wall time);
    - params={"WPNAV_SPEED": 750} reads back 750 over the test's own pymavlink link;
    - faults={"SIM_GPS_DISABLE": 1} with airborne=10: the vehicle starts the test in the air and
      the failsafe lands it in LAND mode;
    - startup="realistic" with airborne=5: the takeoff waits for the vehicle to become armable
      in GUIDED (after 40 s of vehicle time) and the test starts in the air;
    - home=(-33.8568, 151.2153, 10): the vehicle reports its position there (a negative latitude
      must reach the autopilot as a value, not be read as an option);
    - a module's marker and a test's merge, key by key, the test's winning."""
    pytester.makepyfile(test_ready=READY, test_merged=MERGED)
    result = run_inner(pytester)
    result.assert_outcomes(passed=9)

"""A user's MAVSDK test file flies green with nothing but the installed plugin: serially, under
pytest-xdist with both workers flying vehicles, and in pytest-asyncio's strict mode."""
from __future__ import annotations

import re

import pytest

from .inner import run_inner

pytest_plugins = ["pytester"]
pytestmark = pytest.mark.sitl

HOPS = '''
import pytest
from mavsdk.asyncio.plugins.action import ActionAsync

pytestmark = pytest.mark.firefly(speedup=50)


@pytest.mark.parametrize("height_m", [3.0, 4.0, 5.0, 6.0])
async def test_hop_and_land_at_home(firefly, height_m):
    action = ActionAsync(await firefly.mavsdk())
    await action.arm()
    await action.set_takeoff_altitude(height_m)
    await action.takeoff()
    await firefly.wait_until_async(lambda s: s.altitude_m > height_m - 0.5, timeout=30, what=f"{height_m} m")
    await action.land()
    landed = await firefly.wait_until_async(lambda s: s.landed, timeout=60, what="the landing")
    assert landed.distance_from_home_m < 2
'''


@pytest.mark.serial  # its inner -n 2 keeps both cores busy
def test_a_mavsdk_flight_file_passes_serially_and_under_xdist(pytester):
    """Four MAVSDK flights (arm, take off, land, wait in vehicle time for the landing, assert on the
    true position) pass in one process, then with -n 2, where the verbose report shows each of
    the two workers passing flights of its own: the plugin's free ports, evidence directories and
    clean-up hold when two sessions start vehicles side by side."""
    pytester.makepyfile(test_hops=HOPS)
    serial = run_inner(pytester)
    serial.assert_outcomes(passed=4)
    assert serial.ret == pytest.ExitCode.OK

    parallel = run_inner(pytester, "-n", "2", "-v")
    parallel.assert_outcomes(passed=4)
    workers = set(re.findall(r"\[(gw\d)\] .*PASSED", parallel.stdout.str()))
    assert workers == {"gw0", "gw1"}, parallel.stdout.str()


STRICT = '''
import pytest
from mavsdk.asyncio.plugins.action import ActionAsync


@pytest.mark.asyncio
@pytest.mark.firefly(speedup=50)
async def test_mavsdk_arms_in_strict_mode(firefly):
    await ActionAsync(await firefly.mavsdk()).arm()
    armed = await firefly.wait_until_async(lambda s: s.armed, timeout=5, what="armed")
    assert armed.on_ground


@pytest.mark.firefly(speedup=50)
def test_pymavlink_in_strict_mode(firefly):
    heartbeat = firefly.mavlink().recv_match(type="HEARTBEAT", blocking=True, timeout=5)
    assert heartbeat is not None and heartbeat.get_srcSystem() == firefly.system_id
'''


def test_the_fixtures_work_in_pytest_asyncio_strict_mode(pytester):
    """In strict mode pytest-asyncio only runs coroutines marked @pytest.mark.asyncio and only
    treats marked fixtures as async. `firefly` is a plain fixture, so a marked async test can await
    MAVSDK through it and an unmarked synchronous test can use pymavlink: both pass."""
    pytester.makepyfile(test_strict=STRICT)
    result = run_inner(pytester, asyncio_mode="strict")
    result.stdout.fnmatch_lines(["asyncio: mode=*STRICT*"])  # the inner run really was strict
    result.assert_outcomes(passed=2)

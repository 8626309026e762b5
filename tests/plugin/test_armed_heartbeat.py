"""The short version of armed_heartbeat_stress.py: tests that each wait flat out in vehicle time,
then arm and wait over `firefly.mavlink()` for the armed HEARTBEAT, under pytest-xdist -n 2, all
pass. Before the connection read its socket from a thread of its own, about one in four failed:
the socket had overflowed during the wait, and the vehicle's 10 s armed on the ground (20 ms of
wall time) were dropped while the client read the stale backlog."""
from __future__ import annotations

import pytest

from .armed_heartbeat_stress import TEST_FILE
from .inner import run_inner

pytest_plugins = ["pytester"]
pytestmark = [pytest.mark.sitl, pytest.mark.serial]  # its inner -n 2 keeps both cores busy

TESTS = 10


def test_every_armed_heartbeat_arrives_under_xdist(pytester):
    pytester.makepyfile(test_arming=TEST_FILE.format(tests=TESTS, busy_s=300.0))
    result = run_inner(pytester, "-n", "2")
    result.assert_outcomes(passed=TESTS)

"""The loop's clock: a run of S sim seconds is exactly S / tick ticks, however long it is."""
from __future__ import annotations

import math

import pytest

from autopilot.io.runner import Runner


@pytest.mark.parametrize("duration_s", [0.3, 5.0, 60.0, 3600.0])
def test_a_run_of_s_seconds_is_exactly_s_over_tick_ticks(duration_s):
    runner = Runner([], math.inf)
    runner.run(duration_s)
    assert runner.ticks == round(duration_s / 0.01)
    assert runner.sim_time_s == pytest.approx(duration_s, abs=1e-9)

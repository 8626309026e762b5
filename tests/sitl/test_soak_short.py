"""A short soak in every CI run (`make soak` runs a simulated hour): the real process, a pilot and
three noisy clients; the exit report must show every tick ran and nothing raised."""
from __future__ import annotations

import pytest

from ..fuzz.soak import soak, verdict

pytestmark = pytest.mark.sitl


def test_two_simulated_minutes_under_hostile_traffic_run_every_tick():
    result = soak(sim_hours=120 / 3600, speedup=40, noisy_clients=3, rate=300, seed=2, progress=lambda _: None)
    assert verdict(result) == []
    stats = result["stats"]
    assert stats["ticks"] == 12_000 and stats["exception"] is None
    (vehicle,) = stats["vehicles"]
    assert vehicle["physics_steps"] == 48_000
    counters = vehicle["counters"]
    assert counters["bad_data"] > 0 and counters["received"] > 1000
    assert counters["param_sets_refused"] > 0 and counters["mission_uploads_refused"] > 0
    assert result["pilot_flights"] >= 1

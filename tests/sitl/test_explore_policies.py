"""Every search policy flies end to end against the real autopilot on the small world: the
companion declares the scenario's fire within one cell and lands at home. And a reading handler
that raises ends the flight with that error (vehicle made safe), instead of dying unseen while the
vehicle flies on without readings."""
from __future__ import annotations

import asyncio
import re
import subprocess
import sys

import pytest

from firefly.groundstation.flight.explore import explore
from firefly.groundstation.flight.vehicle_link import LinkError
from firefly.groundstation.strategy import policies
from firefly.groundstation.strategy.policies import POLICIES, Lawnmower
from firefly.sim.scenario import load_scenario

from .conftest import REPO
from .pymav import Gcs

pytestmark = pytest.mark.sitl
SMALL_WORLD = REPO / "tests" / "sitl" / "data" / "small_world.toml"
FIRE_N, FIRE_E = 135.0, 72.0  # the small world's fire


@pytest.mark.parametrize("policy", sorted(POLICIES))
def test_every_policy_flies_to_a_declaration_and_lands(policy, autopilot_factory):
    ap = autopilot_factory(speedup="50", extra=("--scenario", str(SMALL_WORLD)))
    result = subprocess.run([sys.executable, "-m", "firefly.groundstation", "explore", "--url", ap.mavsdk_url,
                             "--scenario", str(SMALL_WORLD), "--policy", policy],
                            cwd=REPO, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    declared = re.search(r"fire declared at N ([-\d.]+) m E ([-\d.]+) m.* after (\d+) m", result.stdout)
    assert declared, result.stdout
    n, e, path_m = (float(g) for g in declared.groups())
    assert path_m > 0, "a search that flew nowhere"
    assert abs(n - FIRE_N) <= 15.0 and abs(e - FIRE_E) <= 15.0, (policy, n, e)
    landed = re.search(r"landed and disarmed ([\d.]+) m from home", result.stdout)
    assert landed and float(landed.group(1)) < 3.0, result.stdout[-1000:]


class BrokenLawnmower(Lawnmower):
    """A lawnmower whose reading handling fails once the survey has readings."""
    name = "broken"

    def observe(self, n, e, z):
        raise ValueError("cannot use this reading")


def test_a_failing_reading_handler_ends_the_flight_with_its_error(autopilot_factory, monkeypatch):
    monkeypatch.setitem(policies.POLICIES, "broken", BrokenLawnmower)
    ap = autopilot_factory(speedup="50", extra=("--scenario", str(SMALL_WORLD)))
    world = load_scenario(SMALL_WORLD).world
    lines: list[str] = []
    # The survey hands readings on from either stream (a reading waits for the position that
    # places it, or the other way round), so either handler is the one that fails.
    with pytest.raises(LinkError, match="(NAMED_VALUE_FLOAT|LOCAL_POSITION_NED) handling failed: "
                                        "ValueError: cannot use this reading"):
        asyncio.run(asyncio.wait_for(explore(ap.mavsdk_url, world, "broken", None, True, say=lines.append), 120))
    # The companion left the vehicle returning home rather than flying on blind.
    gcs = Gcs(f"udpin:127.0.0.1:{ap.port}")
    try:
        hb = gcs.recv("HEARTBEAT", 5, lambda m: m.type != 6)
        assert hb is not None and hb.custom_mode == 6, hb  # RTL
    finally:
        gcs.close()

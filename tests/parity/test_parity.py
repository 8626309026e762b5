"""The recorded-reference comparison in `make test`: every probe against Firefly; a mismatch not
listed in differences.toml (with its reason) fails, and so does a listed difference that is gone."""
from __future__ import annotations

import pytest

from .compare_run import run_area
from .probes import AREAS

pytestmark = pytest.mark.sitl


@pytest.mark.parametrize("area", list(AREAS))
def test_firefly_behaves_as_the_recorded_arducopter(area):
    result = run_area(area)
    assert len(result.checks) > 0
    unexplained = [f"{c.name}: ArduCopter {c.want!r}, Firefly {c.got!r}" for c in result.unexplained]
    assert not unexplained, f"{len(unexplained)} unexplained differences:\n" + "\n".join(unexplained[:40])
    assert not result.stale, f"listed differences that no longer differ (remove them): {result.stale}"

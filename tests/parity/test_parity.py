"""The recorded-reference comparison in `make test`: every probe against Firefly; a mismatch not
listed in differences.toml (with its reason), nor in surface/not_yet.toml (an entry of ArduCopter's
surface not reproduced yet), fails; so does a listed difference that is gone. An area that differs
is run once more, and only what differs in both runs fails (compare_run.run_area_confirmed)."""
from __future__ import annotations

import warnings

import pytest

from .compare_run import run_area_confirmed
from .probes import AREAS
from .surface.score import entry_of, kind_of, not_yet

pytestmark = pytest.mark.sitl


@pytest.mark.parametrize("area", list(AREAS))
def test_firefly_behaves_as_the_recorded_arducopter(area):
    result = run_area_confirmed(area)
    assert len(result.checks) > 0
    unexplained = [f"{c.name}: ArduCopter {c.want!r}, Firefly {c.got!r}" for c in result.unexplained]
    assert not unexplained, f"{len(unexplained)} unexplained differences:\n" + "\n".join(unexplained[:40])
    assert not result.stale, f"listed differences that no longer differ (remove them): {result.stale}"
    listed = not_yet().get(kind_of(area) or "", set())
    failing = {entry_of(area, c.name) for c in result.checks if not c.ok}
    closed = sorted(listed & {entry_of(area, c.name) for c in result.checks} - failing)
    if closed:  # progress, not a failure: `make parity` with --write-not-yet takes them off the list
        warnings.warn(f"{area}: now reproduced, still listed in surface/not_yet.toml: {closed}")

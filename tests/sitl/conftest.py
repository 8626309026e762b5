"""Fixtures that start the real `autopilot` process on free ports.

Each test gets its own process, its own state directory and its own UDP port; the client listens
on that port (udpin), exactly as a user's MAVSDK or pymavlink script listens on 14540/14550.
"""
from __future__ import annotations

import json
import time
from pathlib import Path

import pytest

from firefly.groundstation.flight import autopilot_process
from firefly.groundstation.flight.autopilot_process import AutopilotProcess, free_udp_port  # noqa: F401 - the tests' names

REPO = Path(__file__).resolve().parents[2]


def start_autopilot(tmp_path: Path, speedup: str = "10", extra: tuple = (), port: int | None = None,
                    wipe: bool = True) -> AutopilotProcess:
    """The autopilot with its state in tmp_path/state, run from the repository."""
    return autopilot_process.start_autopilot(tmp_path / "state", speedup, extra, port, wipe, cwd=REPO)


@pytest.fixture
def autopilot_factory(tmp_path):
    """Starts autopilots; each is stopped after the test, and the test fails if any vehicle of
    one had an internal error or a handler error (its --stats exit report says)."""
    started = []

    def factory(speedup: str = "10", extra: tuple = (), **kw) -> AutopilotProcess:
        stats = None
        if "--stats" not in extra:
            stats = tmp_path / f"exit-report-{len(started)}.json"
            extra = (*extra, "--stats", str(stats))
        ap = start_autopilot(tmp_path, speedup, extra, **kw)
        started.append((ap, stats))
        return ap

    yield factory
    problems = []
    for ap, stats in started:
        ap.stop()
        problems.extend(exit_report_problems(stats))
    assert not problems, "\n".join(problems)


def exit_report_problems(stats: Path | None) -> list[str]:
    """Internal and handler errors in an exit report (none when there is no report to read)."""
    if stats is None or not stats.exists():
        return []
    problems = []
    for v in json.loads(stats.read_text())["vehicles"]:
        if v.get("internal_errors"):
            problems.append(f"system {v['system_id']}: {v['internal_errors']} internal errors, "
                            f"last: {v['last_internal_error']}")
        if v["counters"].get("handler_errors"):
            problems.append(f"system {v['system_id']}: handler errors, last: {v['last_handler_error']}")
    return problems


@pytest.fixture
def autopilot(autopilot_factory) -> AutopilotProcess:
    return autopilot_factory()


def wait_for(predicate, timeout: float, what: str, poll=None):
    """Poll `predicate` (after `poll()` if given) until true or fail naming `what`."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if poll is not None:
            poll()
        value = predicate()
        if value:
            return value
    raise AssertionError(f"timed out after {timeout:g} s waiting for {what}")

"""Fixtures that start the real `autopilot` process on free ports.

Each test gets its own process, its own state directory and its own UDP port; the client listens
on that port (udpin), exactly as a user's MAVSDK or pymavlink script listens on 14540/14550.
"""
from __future__ import annotations

import time
from pathlib import Path

import pytest

from groundstation.flight import autopilot_process
from groundstation.flight.autopilot_process import AutopilotProcess, free_udp_port  # noqa: F401 - the tests' names

REPO = Path(__file__).resolve().parents[2]


def start_autopilot(tmp_path: Path, speedup: str = "10", extra: tuple = (), port: int | None = None,
                    wipe: bool = True) -> AutopilotProcess:
    """The autopilot with its state in tmp_path/state, run from the repository."""
    return autopilot_process.start_autopilot(tmp_path / "state", speedup, extra, port, wipe, cwd=REPO)


@pytest.fixture
def autopilot_factory(tmp_path):
    started = []

    def factory(speedup: str = "10", extra: tuple = (), **kw) -> AutopilotProcess:
        ap = start_autopilot(tmp_path, speedup, extra, **kw)
        started.append(ap)
        return ap

    yield factory
    for ap in started:
        ap.stop()


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

"""Fixtures that start the real `autopilot` process on free ports.

Each test gets its own process, its own state directory and its own UDP port; the client listens
on that port (udpin), exactly as a user's MAVSDK or pymavlink script listens on 14540/14550.
"""
from __future__ import annotations

import os
import socket
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


def free_udp_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@dataclass
class AutopilotProcess:
    process: subprocess.Popen
    port: int  # where the client listens (the autopilot's --out)
    state_dir: Path
    speedup: str

    @property
    def mavsdk_url(self) -> str:
        return f"udpin://127.0.0.1:{self.port}"

    @property
    def pymavlink_url(self) -> str:
        return f"udpin:127.0.0.1:{self.port}"

    def stop(self) -> int:
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        return self.process.returncode


def start_autopilot(tmp_path: Path, speedup: str = "10", extra: tuple = (), port: int | None = None,
                    wipe: bool = True) -> AutopilotProcess:
    port = port or free_udp_port()
    state = tmp_path / "state"
    cmd = [sys.executable, "-m", "autopilot", "--listen", "udp:127.0.0.1:0",
           "--out", f"udp:127.0.0.1:{port}", "--speedup", speedup, "--state-dir", str(state),
           "--quiet", *extra]
    if wipe:
        cmd.append("--wipe")
    proc = subprocess.Popen(cmd, cwd=REPO, env={**os.environ, "PYTHONUNBUFFERED": "1"})
    return AutopilotProcess(proc, port, state, speedup)


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

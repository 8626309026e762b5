"""Autopilots forked warm (groundstation/flight/warm_start.py) answer as cold ones do: the exit
status and one line for a bad flag, on the stream the caller gave; a signal's ending; and each
start is its own process. The trajectory's bit-identity with a cold start is test_determinism's."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import tempfile

import pytest
from pymavlink import mavutil

from firefly.groundstation.flight.warm_start import WarmProcess, popen_autopilot

from .conftest import REPO, free_udp_port

pytestmark = pytest.mark.sitl


def said(log) -> str:
    log.seek(0)
    return log.read().decode()


def test_a_bad_flag_ends_warm_as_cold_with_its_one_line_on_the_callers_stderr():
    answers = []
    for warm in (True, False):
        with tempfile.TemporaryFile() as log:
            if warm:
                proc = popen_autopilot(["--speedup", "fast"], cwd=REPO, stderr=log)
                assert isinstance(proc, WarmProcess)
            else:
                proc = subprocess.Popen([sys.executable, "-m", "firefly.autopilot", "--speedup", "fast"],
                                        cwd=REPO, stderr=log)
            answers.append((proc.wait(timeout=60), said(log).strip().splitlines()[-1]))
    assert answers[0] == answers[1]
    assert answers[0][0] == 2 and "--speedup" in answers[0][1]


def test_each_start_is_its_own_process_that_a_signal_ends_as_it_ends_a_cold_one(tmp_path):
    procs = []
    for k in range(2):
        port = free_udp_port()
        procs.append(popen_autopilot(["--listen", "udp:127.0.0.1:0", "--out", f"udp:127.0.0.1:{port}",
                                      "--quiet", "--wipe", "--state-dir", str(tmp_path / str(k)),
                                      f"--exit-with-parent={os.getpid()}"], cwd=REPO))
        link = mavutil.mavlink_connection(f"udpin:127.0.0.1:{port}")
        assert link.wait_heartbeat(timeout=30) is not None  # up: its own signal handling in place
        link.close()
    assert procs[0].pid != procs[1].pid and all(p.poll() is None for p in procs)
    procs[0].send_signal(signal.SIGINT)  # Ctrl-C: a clean stop, status 0
    assert procs[0].wait(timeout=30) == 0
    assert procs[1].poll() is None  # the other runs on
    procs[1].kill()
    assert procs[1].wait(timeout=30) == -signal.SIGKILL

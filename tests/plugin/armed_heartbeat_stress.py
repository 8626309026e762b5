"""Stress: many tests, each arming a vehicle flat out and waiting over `firefly.mavlink()` for the
HEARTBEAT that says it is armed, run with pytest-xdist -n 2; prints how many tests ran and failed.

    python -m tests.plugin.armed_heartbeat_stress --tests 100 --rounds 5

Each round is one `pytest -n 2` session over a file of `--tests` parametrized tests, in a fresh
directory with no pytest configuration (as a user's project). At speedup inf an armed vehicle left
on the ground disarms itself after 10 s of vehicle time, about 20 ms of wall time: the client has
that long in vehicle time but must not lose the HEARTBEATs sent meanwhile, however far behind it
reads. tests/plugin/test_armed_heartbeat.py runs a short version in `make test`.

Measured on 2 cores, --tests 100: with a plain pymavlink connection, 46 of 200 tests failed with
--busy 300 (0 of 200 with --busy 0: arming at once, the socket has not overflowed yet); with
the connection's reader thread (mavlink_client.py), 0 of 300 with --busy 300.
"""
from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROUND_WALL_S = 900

TEST_FILE = '''
import time

import pytest

ARMED = 128  # MAV_MODE_FLAG_SAFETY_ARMED


@pytest.mark.firefly(speedup="inf")
@pytest.mark.parametrize("repetition", range({tests}))
def test_armed_heartbeat_arrives(firefly, repetition):
    conn = firefly.mavlink()
    if {busy_s}:  # the test does something else first, in vehicle time, while telemetry arrives
        firefly.sleep({busy_s})
    conn.mav.command_long_send(firefly.system_id, 1, 400, 0, 1, 0, 0, 0, 0, 0, 0)  # COMPONENT_ARM_DISARM
    ack = armed = None
    deadline = time.monotonic() + 20
    while armed is None and time.monotonic() < deadline:
        msg = conn.recv_match(type=["COMMAND_ACK", "HEARTBEAT"], blocking=True, timeout=1)
        if msg is None or msg.get_srcSystem() != firefly.system_id:
            continue
        if msg.get_type() == "COMMAND_ACK" and msg.command == 400:
            ack = msg.result
        elif msg.get_type() == "HEARTBEAT" and msg.base_mode & ARMED:
            armed = msg
    assert ack == 0, f"arm ACK: {{ack}}"
    assert armed is not None, "no armed HEARTBEAT seen"
'''


def one_round(directory: Path, tests: int, workers: int, busy_s: float) -> tuple[int, int, str]:
    """(tests run, tests failed, pytest's summary line) of one session."""
    (directory / "test_arming.py").write_text(TEST_FILE.format(tests=tests, busy_s=busy_s))
    result = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-n", str(workers),
                             "test_arming.py"], cwd=directory, capture_output=True, text=True,
                            timeout=ROUND_WALL_S, env={**os.environ, "PYTHONDONTWRITEBYTECODE": "1"})
    summary = result.stdout.strip().splitlines()[-1] if result.stdout.strip() else result.stderr[-500:]
    counts = {word: int(n) for n, word in re.findall(r"(\d+) (passed|failed|error)", summary)}
    failed = counts.get("failed", 0) + counts.get("error", 0)
    return counts.get("passed", 0) + failed, failed, summary


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--tests", type=int, default=100, help="tests per session")
    parser.add_argument("--rounds", type=int, default=5, help="sessions")
    parser.add_argument("--workers", type=int, default=2, help="pytest-xdist -n")
    parser.add_argument("--busy", type=float, default=300.0, metavar="S",
                        help="vehicle seconds each test lets pass between connecting and arming (0: none)")
    args = parser.parse_args()
    ran = failed = 0
    started = time.monotonic()
    for k in range(args.rounds):
        with tempfile.TemporaryDirectory(prefix="firefly-stress-") as directory:
            n, bad, summary = one_round(Path(directory), args.tests, args.workers, args.busy)
        ran, failed = ran + n, failed + bad
        print(f"round {k + 1}: {summary}", flush=True)
    print(f"{ran} tests run, {failed} failed, in {time.monotonic() - started:.0f} s "
          f"(-n {args.workers}, speedup inf, {args.busy:g} s of vehicle time before each arm)")
    sys.exit(1 if failed or ran < args.tests * args.rounds else 0)


if __name__ == "__main__":
    main()

"""`firefly.state()` is never older than an answer the test has already received: the vehicle
writes a state line for the moment of each answer before sending it, and state() reads the
newest line at each call. Flat out, arm and disarm over `firefly.mavlink()` again and again; on
each COMMAND_ACK, state() already says what the command did.
Without the line before each answer (autopilot/io/runner.py), 34 of 80 ACKs here came before a
state that showed them: the newest line can be up to 0.1 s of vehicle time older."""
from __future__ import annotations

import time

import pytest

pytestmark = pytest.mark.sitl

ARM = 400  # MAV_CMD_COMPONENT_ARM_DISARM
REPETITIONS = 40
ACK_WALL_S = 10.0


def ack(conn, system_id: int, command: int) -> int:
    """The MAV_RESULT of the next COMMAND_ACK for `command`."""
    deadline = time.monotonic() + ACK_WALL_S
    while time.monotonic() < deadline:
        msg = conn.recv_match(type="COMMAND_ACK", blocking=True, timeout=1.0)
        if msg is not None and msg.get_srcSystem() == system_id and msg.command == command:
            return msg.result
    raise AssertionError(f"no COMMAND_ACK for {command} within {ACK_WALL_S:g} s")


@pytest.mark.firefly(speedup="inf", params={"DISARM_DELAY": 0})  # armed stays armed until disarmed
def test_state_on_the_ack_already_shows_the_command_done(firefly):
    conn = firefly.mavlink()
    stale = []
    for repetition in range(REPETITIONS):
        for arm in (1, 0):
            conn.mav.command_long_send(firefly.system_id, 1, ARM, 0, arm, 0, 0, 0, 0, 0, 0)
            assert ack(conn, firefly.system_id, ARM) == 0
            state = firefly.state()
            if state.armed != bool(arm):
                stale.append(f"repetition {repetition}: {'arm' if arm else 'disarm'} ACKed, state() says {state}")
    assert stale == [], f"{len(stale)} of {2 * REPETITIONS} states older than their ACK:\n" + "\n".join(stale)

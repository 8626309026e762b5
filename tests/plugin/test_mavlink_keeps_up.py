"""`firefly.mavlink()` loses nothing while the test waits: over a 30 s vehicle-time sleep at 10x
(about 600 messages a second) and flat out (about 30,000 a second), and a 600 s one flat out
(a plain pymavlink connection's socket overflows in both of the longer ones), every frame the vehicle sent
arrives, in order: MAVLink sequence numbers without a gap, and both STATUSTEXTs of the window
(the arm's and the auto-disarm's 10 s later) among them."""
from __future__ import annotations

import time

import pytest

pytestmark = [pytest.mark.sitl, pytest.mark.serial]  # a reader thread keeping up with 30,000 messages a second

ARM = 400  # MAV_CMD_COMPONENT_ARM_DISARM
READ_WALL_S = 60.0  # to read what queued up during the sleep (flat out: about 2 s)


def read_until_vehicle_time(conn, system_id: int, end_s: float) -> list:
    """Every message from the vehicle, in arrival order, up to the first stamped at or after `end_s`."""
    messages = []
    deadline = time.monotonic() + READ_WALL_S
    while time.monotonic() < deadline:
        msg = conn.recv_match(blocking=True, timeout=1.0)
        if msg is None or msg.get_srcSystem() != system_id or msg.get_type() == "BAD_DATA":
            continue
        messages.append(msg)
        if msg.get_type() == "ATTITUDE" and msg.time_boot_ms >= end_s * 1000:
            return messages
    raise AssertionError(f"no ATTITUDE of t >= {end_s:g} s within {READ_WALL_S:g} s of reading")


def sequence_gaps(messages: list) -> list[str]:
    """Each break in a component's sequence numbers, as "COMPONENT: after SEQ came SEQ"."""
    last: dict[int, int] = {}
    gaps = []
    for msg in messages:
        component, seq = msg.get_srcComponent(), msg.get_seq()
        if component in last and seq != (last[component] + 1) % 256:
            gaps.append(f"{component}: after {last[component]} came {seq} ({msg.get_type()})")
        last[component] = seq
    return gaps


@pytest.mark.parametrize("speedup, seconds", [
    pytest.param(speedup, seconds, marks=pytest.mark.firefly(speedup=speedup))
    for speedup, seconds in ((10, 30.0), ("inf", 30.0), ("inf", 600.0))])  # 600 s flat out: 1.2 s of wall time
def test_nothing_is_lost_during_a_sleep(firefly, speedup, seconds):
    conn = firefly.mavlink()
    conn.mav.command_long_send(firefly.system_id, 1, ARM, 0, 1, 0, 0, 0, 0, 0, 0)
    slept = firefly.sleep(seconds)  # the armed vehicle, left on the ground, disarms itself at 10 s
    messages = read_until_vehicle_time(conn, firefly.system_id, slept.time_s)

    assert sequence_gaps(messages) == []
    texts = [m.text for m in messages if m.get_type() == "STATUSTEXT"]
    assert "Arming motors" in texts and "Disarming motors" in texts, texts
    assert conn.dropped_datagrams == 0
    print(f"speedup {speedup}, sleep {seconds:g} s: {len(messages)} messages up to t = {slept.time_s:.1f} s, none lost")


@pytest.mark.firefly(speedup="inf")
def test_it_is_a_pymavlink_connection_a_test_may_close(firefly):
    """What a pymavlink user does with it works: wait_heartbeat, recv_msg, sending a request and
    reading its answer, closing it (the fixture's own close after that is harmless)."""
    conn = firefly.mavlink()
    assert conn.wait_heartbeat(timeout=5).get_srcSystem() == firefly.system_id
    assert conn.recv_msg() is not None or conn.recv_match(blocking=True, timeout=5) is not None
    conn.mav.param_request_read_send(firefly.system_id, 1, b"DISARM_DELAY", -1)
    value = conn.recv_match(type="PARAM_VALUE", blocking=True, timeout=5)
    assert value is not None and value.param_id == "DISARM_DELAY" and value.param_value == 10
    conn.close()
    conn.close()

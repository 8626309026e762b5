"""FLOWHOLD against the real autopilot process, driven by pymavlink as a script would: SITL's optical
flow camera (FLOW_TYPE 10, SIM_FLOW_ENABLE 1) streamed as OPTICAL_FLOW, FLOWHOLD refused without it
and taken with it, holding its place over the ground in a wind with the sticks centred by
RC_CHANNELS_OVERRIDE, then moving under the pitch stick and braking when it is let go."""
from __future__ import annotations

import math

import pytest
from pymavlink import mavutil

from .pymav import Gcs, set_param, take_off

pytestmark = pytest.mark.sitl
mav = mavutil.mavlink
FLOWHOLD = 22
MID, FORWARD, LEAVE = 1500, 1300, 65535
BOOT = ("--param", "FLOW_TYPE=10", "--param", "SIM_FLOW_ENABLE=1")


def sticks(gcs: Gcs, pitch: int = MID) -> None:
    gcs.mav.rc_channels_override_send(1, 1, MID, pitch, MID, MID, LEAVE, LEAVE, LEAVE, LEAVE)


def position_at(gcs: Gcs, t_ms: int, timeout: float = 30.0):
    """The first LOCAL_POSITION_NED stamped at or after vehicle time t_ms."""
    p = gcs.recv("LOCAL_POSITION_NED", timeout, lambda m: m.time_boot_ms >= t_ms)
    assert p is not None, f"no LOCAL_POSITION_NED at {t_ms} ms"
    return p


def test_flowhold_without_a_flow_sensor_is_refused(autopilot_factory):
    gcs = Gcs(autopilot_factory().pymavlink_url)
    try:
        assert gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, FLOWHOLD) == mav.MAV_RESULT_FAILED
        text = gcs.recv("STATUSTEXT", 5, lambda m: "FLOWHOLD" in m.text)
        assert text is not None and text.text == "Mode change to FLOWHOLD failed: init failed"
    finally:
        gcs.close()


def test_flowhold_holds_over_the_ground_and_follows_the_stick(autopilot_factory):
    gcs = Gcs(autopilot_factory(extra=BOOT).pymavlink_url)
    try:
        gcs.mav.request_data_stream_send(1, 1, mav.MAV_DATA_STREAM_ALL, 10, 1)
        flow = gcs.recv("OPTICAL_FLOW", 10)
        assert flow is not None and flow.quality == 51 and abs(flow.flow_rate_x) < 0.1
        status = gcs.recv("SYS_STATUS", 5)
        assert status.onboard_control_sensors_health & mav.MAV_SYS_STATUS_SENSOR_OPTICAL_FLOW

        take_off(gcs, 4.0)
        set_param(gcs, "RC_OVERRIDE_TIME", -1)  # one override holds the sticks for good
        sticks(gcs)
        set_param(gcs, "SIM_WIND_SPD", 3.0)
        set_param(gcs, "SIM_WIND_DIR", 180.0)  # from the south: it would carry the vehicle north
        assert gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, FLOWHOLD) == mav.MAV_RESULT_ACCEPTED
        assert gcs.recv("HEARTBEAT", 5, lambda m: m.custom_mode == FLOWHOLD) is not None

        start = position_at(gcs, 0)
        settled = position_at(gcs, start.time_boot_ms + 3000)
        held = position_at(gcs, settled.time_boot_ms + 20_000)
        drift = math.hypot(held.x - settled.x, held.y - settled.y)
        assert drift < 3.0, f"drifted {drift:.1f} m in 20 s"
        assert abs(held.z - settled.z) < 0.5
        hest = gcs.recv("NAMED_VALUE_FLOAT", 5, lambda m: m.name == "HEST")
        assert hest is not None and 3.0 < hest.value < 5.0  # its height estimate, about the real 4 m

        set_param(gcs, "SIM_WIND_SPD", 0.0)
        sticks(gcs, FORWARD)
        pushed = position_at(gcs, held.time_boot_ms + 3000)
        assert pushed.x - held.x > 2.0 and pushed.vx > 1.0
        sticks(gcs)
        stopped = gcs.recv("LOCAL_POSITION_NED", 30, lambda m: math.hypot(m.vx, m.vy) < 0.3)
        assert stopped is not None and stopped.time_boot_ms - pushed.time_boot_ms < 5000
        assert stopped.x - pushed.x < 4.0
    finally:
        gcs.close()

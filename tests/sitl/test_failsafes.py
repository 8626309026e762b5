"""Failsafes on the real process: each breach triggers the configured action, is announced by
STATUSTEXT and shows in SYS_STATUS / HEARTBEAT."""
from __future__ import annotations

import pytest
from pymavlink import mavutil

from .pymav import Gcs, expect_failsafe, set_param, take_off

pytestmark = pytest.mark.sitl
mav = mavutil.mavlink
RTL = 6


def test_battery_drained_by_scenario_triggers_rtl(autopilot_factory, tmp_path):
    scenario = tmp_path / "small_battery.toml"
    scenario.write_text("[airframe]\nbattery_capacity_mah = 500.0\n")
    ap = autopilot_factory(speedup="20", extra=("--scenario", str(scenario)))
    gcs = Gcs(ap.pymavlink_url)
    for name, value in (("BATT_CAPACITY", 500), ("BATT_LOW_MAH", 350), ("BATT_FS_LOW_ACT", 2)):
        set_param(gcs, name, value)
    take_off(gcs)
    expect_failsafe(gcs, "Battery 1 is low", RTL, timeout=60)
    status = gcs.recv("SYS_STATUS", 5)
    assert not status.onboard_control_sensors_health & mav.MAV_SYS_STATUS_SENSOR_BATTERY
    gcs.close()


def test_ground_station_silence_triggers_rtl(autopilot):
    gcs = Gcs(autopilot.pymavlink_url)
    set_param(gcs, "FS_GCS_ENABLE", 1)
    set_param(gcs, "FS_GCS_TIMEOUT", 2)
    gcs.mav.heartbeat_send(mav.MAV_TYPE_GCS, mav.MAV_AUTOPILOT_INVALID, 0, 0, 0)  # we are a GCS
    take_off(gcs)
    # From here on this ground station sends no more heartbeats (it keeps listening).
    expect_failsafe(gcs, "GCS Failsafe", RTL, timeout=20)
    gcs.close()


def test_fence_breach_triggers_rtl(autopilot):
    gcs = Gcs(autopilot.pymavlink_url)
    for name, value in (("FENCE_ENABLE", 1), ("FENCE_TYPE", 2), ("FENCE_RADIUS", 40), ("FENCE_ACTION", 1)):
        set_param(gcs, name, value)
    status = gcs.recv("SYS_STATUS", 5)
    assert status.onboard_control_sensors_present & mav.MAV_SYS_STATUS_GEOFENCE
    set_param(gcs, "AVOID_ENABLE", 0)  # so that nothing holds the vehicle back at the fence
    take_off(gcs)
    # A position target beyond the fence is refused (as ArduCopter's GUIDED does): fly out on a
    # velocity target instead, sent again as a companion does (GUIDED stops one 3 s old)
    text = None
    for _ in range(60):
        gcs.mav.set_position_target_local_ned_send(0, 1, 1, mav.MAV_FRAME_LOCAL_NED, 0xDC7, 0, 0, 0,
                                                   5, 0, 0, 0, 0, 0, 0, 0)
        text = gcs.recv("STATUSTEXT", 0.5, lambda m: "fence breached" in m.text)
        if text is not None:
            break
    # As ArduCopter: the breach is told and answered, but it is not a failsafe the heartbeat shows
    assert text is not None and text.text == "Circle fence breached" and text.severity == mav.MAV_SEVERITY_NOTICE
    hb = gcs.recv("HEARTBEAT", 5, lambda m: m.custom_mode == RTL)
    assert hb is not None and hb.system_status == mav.MAV_STATE_ACTIVE
    status = gcs.recv("SYS_STATUS", 5)
    assert not status.onboard_control_sensors_health & mav.MAV_SYS_STATUS_GEOFENCE
    gcs.close()

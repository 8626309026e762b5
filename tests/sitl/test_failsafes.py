"""Failsafes on the real process: each breach triggers the configured action, is announced by
STATUSTEXT and shows in SYS_STATUS / HEARTBEAT."""
from __future__ import annotations

import pytest
from pymavlink import mavutil

from .pymav import Gcs

pytestmark = pytest.mark.sitl
mav = mavutil.mavlink
GUIDED, RTL = 4, 6


def set_param(gcs, name: str, value: float) -> None:
    gcs.mav.param_set_send(1, 1, name.encode(), value, mav.MAV_PARAM_TYPE_REAL32)
    echo = gcs.recv("PARAM_VALUE", 5, lambda m: m.param_id == name)
    assert echo is not None and echo.param_value == value, f"{name} not set"


def take_off(gcs, alt: float = 10.0) -> None:
    assert gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, GUIDED) == mav.MAV_RESULT_ACCEPTED
    assert gcs.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1) == mav.MAV_RESULT_ACCEPTED
    assert gcs.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, alt) == mav.MAV_RESULT_ACCEPTED
    assert gcs.recv("GLOBAL_POSITION_INT", 20, lambda m: m.relative_alt > (alt - 0.5) * 1000) is not None


def expect_rtl_with_text(gcs, words: str, timeout: float = 30.0):
    text = gcs.recv("STATUSTEXT", timeout, lambda m: words in m.text)
    assert text is not None, f"no STATUSTEXT containing {words!r}"
    hb = gcs.recv("HEARTBEAT", 5, lambda m: m.custom_mode == RTL)
    assert hb is not None, "vehicle did not switch to RTL"
    assert hb.system_status == mav.MAV_STATE_CRITICAL
    return text


def test_battery_drained_by_scenario_triggers_rtl(autopilot_factory, tmp_path):
    scenario = tmp_path / "small_battery.toml"
    scenario.write_text("[airframe]\nbattery_capacity_mah = 500.0\n")
    ap = autopilot_factory(speedup="20", extra=("--scenario", str(scenario)))
    gcs = Gcs(ap.pymavlink_url)
    for name, value in (("BATT_CAPACITY", 500), ("BATT_LOW_MAH", 350), ("FS_BATT_ENABLE", 2)):
        set_param(gcs, name, value)
    take_off(gcs)
    expect_rtl_with_text(gcs, "Battery 1 is low", timeout=60)
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
    expect_rtl_with_text(gcs, "GCS Failsafe", timeout=20)
    gcs.close()


def test_fence_breach_triggers_rtl(autopilot):
    gcs = Gcs(autopilot.pymavlink_url)
    for name, value in (("FENCE_ENABLE", 1), ("FENCE_TYPE", 2), ("FENCE_RADIUS", 40), ("FENCE_ACTION", 1)):
        set_param(gcs, name, value)
    status = gcs.recv("SYS_STATUS", 5)
    assert status.onboard_control_sensors_present & mav.MAV_SYS_STATUS_GEOFENCE
    take_off(gcs)
    gcs.mav.set_position_target_local_ned_send(0, 1, 1, mav.MAV_FRAME_LOCAL_NED, 0x9F8, 80, 0, -10,
                                               0, 0, 0, 0, 0, 0, 0, 0)
    expect_rtl_with_text(gcs, "Fence Breached")
    status = gcs.recv("SYS_STATUS", 5)
    assert not status.onboard_control_sensors_health & mav.MAV_SYS_STATUS_GEOFENCE
    gcs.close()

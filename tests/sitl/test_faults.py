"""Fault injection on the real process: a SIM_* parameter set over pymavlink mid-flight (or in a
scenario's [faults]) and the reaction seen on the wire — HEARTBEAT mode and system status,
STATUSTEXT, SYS_STATUS health bits, GPS_RAW_INT, and the link itself going quiet."""
from __future__ import annotations

import json
import time

import pytest
from pymavlink import mavutil

from .pymav import Gcs, expect_failsafe, set_param, take_off

pytestmark = pytest.mark.sitl
mav = mavutil.mavlink
RTL, LAND = 6, 9
GPS_BIT, BATTERY_BIT = mav.MAV_SYS_STATUS_SENSOR_GPS, mav.MAV_SYS_STATUS_SENSOR_BATTERY


def sys_status_healthy(gcs: Gcs, bit: int, healthy: bool, timeout: float = 5.0):
    status = gcs.recv("SYS_STATUS", timeout, lambda m: bool(m.onboard_control_sensors_health & bit) == healthy)
    assert status is not None, f"SYS_STATUS bit {bit:#x} never {'healthy' if healthy else 'unhealthy'}"
    return status


def test_gps_disabled_mid_flight_lands_by_ekf_failsafe_and_recovers(autopilot_factory):
    gcs = Gcs(autopilot_factory(speedup="10").pymavlink_url)
    take_off(gcs)
    set_param(gcs, "SIM_GPS1_ENABLE", 0)
    raw = gcs.recv("GPS_RAW_INT", 5, lambda m: m.fix_type < 3)
    assert raw is not None and raw.satellites_visible == 0
    sys_status_healthy(gcs, GPS_BIT, False)
    expect_failsafe(gcs, "EKF Failsafe: changed to LAND Mode", LAND, timeout=10)
    set_param(gcs, "SIM_GPS1_ENABLE", 1)
    assert gcs.recv("STATUSTEXT", 10, lambda m: "EKF Failsafe Cleared" in m.text) is not None
    sys_status_healthy(gcs, GPS_BIT, True)
    gcs.close()


def test_a_weak_motor_on_a_loaded_copter_reports_potential_thrust_loss(autopilot_factory, tmp_path):
    scenario = tmp_path / "loaded.toml"
    scenario.write_text("[airframe]\nmass_kg = 3.6\n")
    gcs = Gcs(autopilot_factory(speedup="10", extra=("--scenario", str(scenario))).pymavlink_url)
    take_off(gcs, 20.0)
    set_param(gcs, "SIM_ENGINE_MUL", 0.71)
    set_param(gcs, "SIM_ENGINE_FAIL", 4)  # output 3, the front motor, at half thrust
    text = gcs.recv("STATUSTEXT", 10, lambda m: "Thrust Loss" in m.text)
    # ... which is ArduCopter's output 3 on a QUAD PLUS (autopilot/motor_outputs.py)
    assert text is not None and text.text == "Potential Thrust Loss (3)"
    assert text.severity == mav.MAV_SEVERITY_EMERGENCY
    assert gcs.recv("GLOBAL_POSITION_INT", 10, lambda m: m.relative_alt < 15_000) is not None  # sinking
    gcs.close()


def test_battery_fault_mid_flight_triggers_the_battery_failsafe(autopilot_factory):
    """As a test written for ArduPilot SITL does it: SIM_BATT_VOLTAGE 10 on the 12.6 V pack, the
    default BATT_LOW_VOLT (10.5 V), and BATT_LOW_TIMER's 10 s (1 s of wall time at 10x) later RTL."""
    gcs = Gcs(autopilot_factory(speedup="10").pymavlink_url)
    set_param(gcs, "BATT_FS_LOW_ACT", 2)
    take_off(gcs)
    set_param(gcs, "SIM_BATT_VOLTAGE", 10.0)
    expect_failsafe(gcs, "Battery 1 is low", RTL, timeout=10)
    sys_status_healthy(gcs, BATTERY_BIT, False)
    gcs.close()


def test_rc_failure_mid_flight_triggers_the_radio_failsafe(autopilot_factory):
    """A test written for ArduPilot SITL: SIM_RC_FAIL 1 with FS_THR_ENABLE at its default (1, RTL)."""
    gcs = Gcs(autopilot_factory(speedup="10").pymavlink_url)
    take_off(gcs)
    set_param(gcs, "SIM_RC_FAIL", 1)
    expect_failsafe(gcs, "Radio Failsafe", RTL, timeout=10)
    set_param(gcs, "SIM_RC_FAIL", 0)
    assert gcs.recv("STATUSTEXT", 10, lambda m: m.text == "Radio Failsafe Cleared") is not None
    gcs.close()


def recv_as_gcs(gcs: Gcs, types, timeout: float, condition=None):
    """Like Gcs.recv, but sending a GCS heartbeat every half second meanwhile, as a ground
    station keeps doing: whatever trips the GCS failsafe is then the link, not the station."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        gcs.mav.heartbeat_send(mav.MAV_TYPE_GCS, mav.MAV_AUTOPILOT_INVALID, 0, 0, 0)
        msg = gcs.recv(types, min(0.5, deadline - time.monotonic()), condition)
        if msg is not None:
            return msg
    return None


def test_a_cut_link_trips_the_gcs_failsafe_and_its_return_shows_rtl(autopilot_factory):
    gcs = Gcs(autopilot_factory(speedup="5").pymavlink_url)
    set_param(gcs, "FS_GCS_ENABLE", 1)
    set_param(gcs, "FS_GCS_TIMEOUT", 2)
    recv_as_gcs(gcs, "HEARTBEAT", 2)
    take_off(gcs)
    set_param(gcs, "SIM_LINK_DOWN", 4)  # wall seconds
    # While the link is down nothing arrives, though the ground station keeps talking.
    assert recv_as_gcs(gcs, "HEARTBEAT", 3) is None
    # The first thing through: our heartbeat got in, so the failsafe it had tripped clears.
    cleared = recv_as_gcs(gcs, "STATUSTEXT", 6, lambda m: "GCS Failsafe" in m.text)
    assert cleared is not None and cleared.text == "GCS Failsafe Cleared"
    assert recv_as_gcs(gcs, "HEARTBEAT", 3, lambda m: m.custom_mode == RTL) is not None
    gcs.close()


def test_scenario_packet_loss_drops_about_that_share_and_counts_it(autopilot_factory, tmp_path):
    scenario = tmp_path / "lossy.toml"
    scenario.write_text("[faults]\nSIM_LINK_LOSS = 50\n")
    stats = tmp_path / "stats.json"
    ap = autopilot_factory(speedup="20", extra=("--scenario", str(scenario), "--stats", str(stats)))
    gcs = Gcs(ap.pymavlink_url)
    start_ms = now_ms = gcs.recv("SYSTEM_TIME", 5).time_boot_ms
    heartbeats = 0
    while now_ms - start_ms < 60_000:  # a sim minute, by the vehicle's own clock
        msg = gcs.recv(["HEARTBEAT", "SYSTEM_TIME"], 5)
        assert msg is not None
        if msg.get_type() == "HEARTBEAT":
            heartbeats += 1
        else:
            now_ms = msg.time_boot_ms
    assert 15 <= heartbeats <= 45  # 60 sent at 1 Hz, about half through (binomial: 30 +- 4)
    gcs.close()
    assert ap.stop() == 0
    counters = json.loads(stats.read_text())["vehicles"][0]["counters"]
    assert counters["link_dropped_out"] > 0 and counters["link_dropped_in"] >= 0

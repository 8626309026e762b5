"""Fault injection on the vehicle, no sockets: each SIM_* parameter set mid-flight, and how the
vehicle reacts as ArduCopter would (failsafe action, STATUSTEXT, SYS_STATUS and EKF flags) or as
physics says it must (a weak motor flown around, a failed one falling)."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.estimate import DEAD_RECKONING_S
from firefly.autopilot.safety.ekf_check import EKF_CHECK_ITERATIONS_MAX
from firefly.autopilot.mavlink import sensor_messages, telemetry
from firefly.autopilot.mavlink.dialect import mavlink as mav
from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.modes import AltHold, Guided, Land
from firefly.autopilot.params import ParamStore
from firefly.autopilot.results import Result, Severity
from firefly.autopilot.vehicle import Vehicle, VehicleConfig
from firefly.sim.airframe import Airframe
from firefly.sim.vehicle import SimConfig
from firefly.sim.wind import SteadyWind

from ._util import altitude, fly_until, hovering_vehicle, throttle_at_mid, ready_vehicle

CODEC = new_codec(1)
# the EKF dead-reckons DEAD_RECKONING_S, then ten bad checks at 10 Hz
EKF_FAILSAFE_S = DEAD_RECKONING_S + EKF_CHECK_ITERATIONS_MAX / 10.0


def texts(v: Vehicle) -> list[str]:
    return [text for _, text in v.events]


def said(v: Vehicle, text: str) -> bool:
    return any(text in t for t in texts(v))


def gps_healthy(v: Vehicle) -> bool:
    return bool(telemetry.sys_status(v, CODEC).onboard_control_sensors_health & mav.MAV_SYS_STATUS_SENSOR_GPS)


def true_altitude(v: Vehicle) -> float:
    return v.home_ned[2] - v.sim.state.body.d_m


def horizontal_distance(v: Vehicle, ne: tuple) -> float:
    b = v.sim.state.body
    return math.hypot(b.n_m - ne[0], b.e_m - ne[1])


def hovering_with(*settings) -> tuple[Vehicle, tuple]:
    """A vehicle hovering at 10 m in GUIDED, the point it holds, and then these (name, value)s set."""
    v = hovering_vehicle(10.0)
    b = v.sim.state.body
    v.events.clear()
    for name, value in settings:
        v.params.set(name, value)
    return v, (b.n_m, b.e_m)


# ----- GPS loss: the EKF failsafe -------------------------------------------------------------------
@pytest.mark.parametrize("fault", [("SIM_GPS_DISABLE", 1), ("SIM_GPS1_ENABLE", 0)])
def test_gps_loss_in_guided_lands_with_ekf_failsafe_and_recovers_when_the_gps_returns(fault):
    v = hovering_vehicle(10.0)
    v.events.clear()
    t0 = v.time_s
    v.params.set(*fault)
    assert fly_until(v, lambda x: x.mode.number == Land.number, EKF_FAILSAFE_S + 2.0)
    assert v.time_s - t0 == pytest.approx(EKF_FAILSAFE_S, abs=0.15)  # 8 s on ArduCopter SITL
    assert texts(v)[:2] == ["EKF variance", "EKF Failsafe: changed to LAND Mode"]
    assert (int(Severity.CRITICAL), "EKF variance") in v.events
    assert not gps_healthy(v) and not v.has_position()
    assert telemetry.heartbeat(v, CODEC).system_status == mav.MAV_STATE_CRITICAL
    ekf = telemetry.ekf_status_report(v, CODEC)
    assert ekf.flags == 0x25  # attitude and height only, flying (ArduCopter SITL, area ekf_variances)
    assert v.set_mode(Guided.number) == Result.FAILED  # no position, no GUIDED
    v.run_until(v.time_s + 2.0)
    assert altitude(v) < 9.5  # LAND is coming down

    v.params.set(fault[0], {"SIM_GPS_DISABLE": 0, "SIM_GPS1_ENABLE": 1}[fault[0]])
    assert fly_until(v, lambda x: said(x, "EKF Failsafe Cleared"), 2.0)
    assert gps_healthy(v) and not v.failsafes.active
    assert v.mode.number == Land.number  # ArduCopter does not go back to the mode it left
    assert v.set_mode(Guided.number) == Result.ACCEPTED


def test_no_gps_from_power_on_never_counts_towards_the_ekf_failsafe():
    """ArduCopter's EKF check counts nothing before its EKF has an origin and its checks have once
    passed (measured, area refusals: armed in STABILIZE with no GPS, it says "Arming motors" alone)."""
    v = ready_vehicle(boot_params={"SIM_GPS1_ENABLE": 0})
    v.events.clear()
    assert v.arm() == Result.ACCEPTED
    v.run_until(v.time_s + 5.0)
    assert texts(v) == ["Arming motors"] and not v.failsafes.active


def test_three_satellites_change_nothing_in_flight():
    """Measured on ArduCopter SITL: SIM_GPS1_NUMSATS 3 in a GUIDED hover keeps the fix and the mode."""
    v, _ = hovering_with(("SIM_GPS1_NUMSATS", 3))
    v.run_until(v.time_s + 5.0)
    assert v.mode.number == Guided.number and v.has_position() and not texts(v)
    assert v.gps.satellites == 3


def test_land_without_gps_comes_down_level_and_drifts_with_the_wind():
    v = hovering_vehicle(10.0, sim=SimConfig(wind=SteadyWind(4.0, 270.0)))  # from the west
    start_e = v.sim.state.body.e_m
    v.params.set("SIM_GPS_DISABLE", 1)
    assert fly_until(v, lambda x: not x.armed, 40.0)
    assert v.cascade.lean_t == (0.0, 0.0)
    assert v.sim.state.body.e_m - start_e > 3.0  # nothing held it against the wind


def test_gps_loss_in_alt_hold_keeps_the_mode_unless_fs_ekf_action_is_3():
    for action, mode in ((1, AltHold.number), (3, Land.number)):
        v = throttle_at_mid(hovering_vehicle(10.0))
        v.params.set("FS_EKF_ACTION", action)
        assert v.set_mode(AltHold.number) == Result.ACCEPTED
        v.params.set("SIM_GPS_DISABLE", 1)
        v.run_until(v.time_s + 2 * EKF_FAILSAFE_S)
        assert v.failsafes.ekf.failsafe
        assert v.mode.number == mode


def test_fs_ekf_action_2_switches_to_alt_hold():
    v, _ = hovering_with(("FS_EKF_ACTION", 2), ("SIM_GPS_DISABLE", 1))
    assert fly_until(v, lambda x: x.mode.number == AltHold.number, EKF_FAILSAFE_S + 2.0)
    assert said(v, "EKF Failsafe: changed to ALT_HOLD Mode")


def test_no_ekf_failsafe_when_fs_ekf_thresh_is_zero():
    v, _ = hovering_with(("FS_EKF_THRESH", 0), ("SIM_GPS_DISABLE", 1))
    v.run_until(v.time_s + 3.0)
    assert v.mode.number == Guided.number and not v.failsafes.ekf.failsafe


@pytest.mark.parametrize("fault,reason", [(("SIM_GPS_DISABLE", 1), "Need 3D Fix"),
                                          (("SIM_GPS_GLITCH_Y", -0.0005), "GPS glitching")])
def test_arming_is_refused_without_a_fix_or_while_the_gps_glitches(fault, reason):
    v = ready_vehicle()
    v.params.set(*fault)
    v.run_until(v.time_s + 1.3)  # a glitch is a fix off for a second (EKF3's hysteresis)
    v.set_mode(Guided.number)
    assert v.arm() == Result.FAILED
    assert f"Arm: {reason}" in texts(v)


# ----- GPS glitch -----------------------------------------------------------------------------------
def test_gps_glitch_is_announced_rejected_and_cleared():
    v, hold = hovering_with(("SIM_GPS_GLITCH_X", 0.001))  # about 111 m north
    assert not fly_until(v, lambda x: said(x, "GPS Glitch or Compass error"), 0.9)  # off for a second first
    assert fly_until(v, lambda x: said(x, "GPS Glitch or Compass error"), 0.4)
    assert v.gps.n_m - v.sim.state.body.n_m == pytest.approx(111.3, abs=1.5)
    assert telemetry.ekf_status_report(v, CODEC).flags & telemetry.EKF_GPS_GLITCH
    v.run_until(v.time_s + 3.0)
    assert horizontal_distance(v, hold) < 0.3  # the estimate did not follow the glitch
    assert v.mode.number == Guided.number and gps_healthy(v)  # still a 3D fix: no failsafe
    v.params.set("SIM_GPS_GLITCH_X", 0.0)
    assert not fly_until(v, lambda x: said(x, "Glitch cleared"), 9.8)  # well for 10 s first
    assert fly_until(v, lambda x: said(x, "Glitch cleared"), 0.5)


# ----- GPS jamming ----------------------------------------------------------------------------------
def test_a_jammed_gps_trips_the_ekf_failsafe_by_its_velocity_and_comes_and_goes():
    """SIM_GPS1_JAM in a GUIDED hover, as measured on ArduCopter SITL (six flights): the fix goes,
    comes back wandering hundreds of metres off with wild velocities, the EKF failsafe lands the
    vehicle within seconds (4.3 to 7.5 s), then clears and trips again as the readings come."""
    v, hold = hovering_with(("SIM_GPS1_JAM", 1))
    t0 = v.time_s
    fix_types, offsets = set(), []
    while v.mode.number != Land.number and v.time_s - t0 < 20.0:
        v.run_until(v.time_s + 0.1)
        fix_types.add(v.gps.fix_type)
        offsets.append(math.hypot(v.gps.n_m - v.sim.state.body.n_m, v.gps.e_m - v.sim.state.body.e_m))
    assert v.mode.number == Land.number, "no EKF failsafe within 20 s of jamming"
    assert 1.0 < v.time_s - t0 < 20.0  # the first second at least has no fix at all
    assert fix_types == {1, 3} and max(offsets) > 20.0
    assert said(v, "GPS Glitch or Compass error") and said(v, "EKF Failsafe: changed to LAND Mode")
    assert horizontal_distance(v, hold) < 1.0  # rejected: the estimate did not follow the fixes
    assert fly_until(v, lambda x: said(x, "EKF Failsafe Cleared"), 20.0)
    v.params.set("SIM_GPS1_JAM", 0)
    v.run_until(v.time_s + 1.0)
    assert v.gps.n_m - v.sim.state.body.n_m == pytest.approx(0.0, abs=2.0)  # the receiver as before


def test_a_glitch_alone_is_no_variance_but_wild_velocities_are():
    """ArduCopter's ekf_over_threshold: a high position variance (a glitching GPS) counts only
    with another; the velocity variance at twice FS_EKF_THRESH counts alone."""
    v, _ = hovering_with(("SIM_GPS_GLITCH_X", 0.001))
    v.run_until(v.time_s + 5.0)
    ekf = v.failsafes.ekf
    assert ekf.gps_glitching and ekf.vel_variance < 0.1 and ekf.fail_count == 0
    v.params.set("SIM_GPS_GLITCH_X", 0.0)
    v.sim.gps.glitch_ned = (0.0, 0.0, 0.0)
    reading = v.sim.gps.read  # a receiver whose velocity is 20 m/s off: a variance of 5.7
    v.sim.gps.read = lambda body, now_s=0.0: reading(body, now_s)._replace(vn_m_s=body.vn_m_s + 20.0)
    t0 = v.time_s
    assert fly_until(v, lambda x: x.mode.number == Land.number, 2.0)
    assert v.time_s - t0 >= 0.9  # ten checks over the threshold, at 10 Hz
    assert said(v, "EKF variance")


def test_vibration_compensation_comes_on_after_a_second_of_high_velocity_variance_and_goes_after_15_s():
    v = hovering_vehicle(10.0)
    v.events.clear()
    reading = v.sim.gps.read
    v.params.set("FS_EKF_THRESH", 0)  # the variance high, the failsafe kept out of it
    v.sim.gps.read = lambda body, now_s=0.0: reading(body, now_s)._replace(vd_m_s=body.vd_m_s + 10.0)
    assert not fly_until(v, lambda x: said(x, "Vibration compensation ON"), 1.0)
    assert fly_until(v, lambda x: said(x, "Vibration compensation ON"), 0.5)
    v.sim.gps.read = reading
    assert not fly_until(v, lambda x: said(x, "Vibration compensation OFF"), 14.5)
    assert fly_until(v, lambda x: said(x, "Vibration compensation OFF"), 1.0)


def test_in_a_mode_that_needs_no_position_the_ekf_failsafe_is_only_said_and_cleared():
    """failsafe_ekf_event(): no action where the mode needs no position, "EKF Failsafe" said, and
    "EKF Failsafe Cleared" once the checks pass again."""
    v = throttle_at_mid(hovering_vehicle(10.0))
    assert v.set_mode(AltHold.number) == Result.ACCEPTED
    v.events.clear()
    v.params.set("SIM_GPS_DISABLE", 1)
    assert fly_until(v, lambda x: x.failsafes.ekf.failsafe, EKF_FAILSAFE_S + 1.0)
    assert v.mode.number == AltHold.number and texts(v)[:2] == ["EKF variance", "EKF Failsafe"]
    v.params.set("SIM_GPS_DISABLE", 0)
    assert fly_until(v, lambda x: said(x, "EKF Failsafe Cleared"), 2.0)


# ----- motors ---------------------------------------------------------------------------------------
def test_a_motor_at_70_percent_thrust_still_holds_position():
    v, hold = hovering_with(("SIM_ENGINE_FAIL", 4), ("SIM_ENGINE_MUL", 0.84))  # output 3, the front: 70 % thrust
    worst_xy = worst_z = 0.0
    for _ in range(200):  # 10 s
        v.run_until(v.time_s + 0.05)
        worst_xy = max(worst_xy, horizontal_distance(v, hold))
        worst_z = max(worst_z, abs(true_altitude(v) - 10.0))
    assert worst_xy < 0.5 and worst_z < 0.3
    assert v.cascade.omega_cmd[0] > max(v.cascade.omega_cmd[1:])  # the weak motor is driven harder
    assert not said(v, "Thrust Loss")


def test_a_failed_motor_on_a_quad_cannot_keep_it_flying():
    v = hovering_vehicle(20.0)
    v.params.set("SIM_ENGINE_FAIL", 2)  # output 2, the sim's motor 2 (SIM_ENGINE_MUL 0 by default)
    assert fly_until(v, lambda x: true_altitude(x) < 0.05, 10.0)  # down within seconds
    assert v.sim.state.omega_rad_s[1] == pytest.approx(0.0, abs=1e-6)  # motor 2 stopped


def test_a_loaded_copter_with_a_weak_motor_reports_potential_thrust_loss():
    heavy = SimConfig(airframe=Airframe(mass_kg=3.6))  # hovers at 78 % thrust
    v = hovering_vehicle(20.0, sim=heavy)
    v.params.set("SIM_ENGINE_MUL", 0.71)
    v.params.set("SIM_ENGINE_FAIL", 4)  # output 3 at half thrust: total thrust available now below the weight
    assert fly_until(v, lambda x: said(x, "Potential Thrust Loss"), 5.0)
    # the sim's motor 1 (front) is ArduCopter's motor 3 (autopilot/motor_outputs.py)
    assert (int(Severity.EMERGENCY), "Potential Thrust Loss (3)") in v.events
    assert true_altitude(v) < 19.5  # it was coming down


# ----- barometer ----------------------------------------------------------------------------------
def test_baro_drift_moves_the_height_estimate_so_the_vehicle_sinks_while_reporting_its_height():
    v, _ = hovering_with(("SIM_BARO_DRIFT", 0.5))
    v.run_until(v.time_s + 8.0)
    assert altitude(v) - true_altitude(v) == pytest.approx(4.0, abs=0.01)  # 8 s at 0.5 m/s (updated at 100 Hz)
    # It holds the height it believes in, lagging the ramp by about drift / PSC_POSZ_P.
    assert 10.0 < altitude(v) < 10.0 + 0.5 / v.params["PSC_POSZ_P"] + 0.1
    assert telemetry.global_position_int(v, CODEC).relative_alt == pytest.approx(altitude(v) * 1000, abs=1)
    assert true_altitude(v) < 7.0  # where it really is
    assert -v.gps.d_m == pytest.approx(true_altitude(v), abs=2.0)  # the GPS altitude tells the truth
    v.params.set("SIM_BARO_DRIFT", 0.0)
    assert fly_until(v, lambda x: abs(true_altitude(x) - 10.0) < 0.2, 10.0)


def test_scaled_pressure_reports_what_the_drifting_barometer_reads():
    v = ready_vehicle()
    before = sensor_messages.scaled_pressure(v, CODEC)
    v.params.set("SIM_BARO_DRIFT", 1.0)
    v.run_until(v.time_s + 20.0)  # still on the ground: only the sensor rises, by 20 m
    after = sensor_messages.scaled_pressure(v, CODEC)
    # About 0.12 hPa per metre near sea level (this home is at 150 m).
    assert before.press_abs - after.press_abs == pytest.approx(20 * 0.118, rel=0.05)
    assert 1013.25 > before.press_abs > 900 and after.temperature < before.temperature
    assert -v.gps.d_m == pytest.approx(0.0, abs=2.0)  # the GPS still says the ground


# ----- wind -----------------------------------------------------------------------------------------
def turbulent_track(seed: int, turbulence: float) -> list:
    v = hovering_vehicle(10.0, sim=SimConfig(seed=seed, wind=SteadyWind(3.0, 45.0)))
    v.params.set("SIM_WIND_TURB", turbulence)
    track = []
    for _ in range(100):  # 10 s
        v.run_until(v.time_s + 0.1)
        track.append(v.sim.state.body[:3])
    return track


def test_turbulence_moves_the_vehicle_the_same_way_for_the_same_seed():
    calm, gusty = turbulent_track(1, 0.0), turbulent_track(1, 3.0)
    assert gusty == turbulent_track(1, 3.0)  # deterministic per seed
    assert gusty != turbulent_track(2, 3.0)
    start = calm[0]
    spread = max(math.dist(p, start) for p in gusty)
    assert spread > 3 * max(math.dist(p, start) for p in calm)
    assert 0.2 < spread < 5.0  # pushed about, and still held by the position loop


def test_a_wind_change_blows_in_over_sim_wind_tc_and_is_held_against():
    # (SIM_WIND_T 1: the same wind at every height, for the change alone)
    v, hold = hovering_with(("SIM_WIND_T", 1), ("SIM_WIND_TC", 2.0), ("SIM_WIND_SPD", 8.0),
                            ("SIM_WIND_DIR", 90.0))  # from the east
    v.run_until(v.time_s + 2.0)
    assert v.sim.wind_ned[1] == pytest.approx(-8.0 * (1 - math.exp(-1.0)), abs=0.3)
    v.run_until(v.time_s + 15.0)
    assert v.sim.wind_ned[1] == pytest.approx(-8.0, abs=0.01)
    assert horizontal_distance(v, hold) < 0.3


def test_the_wind_weakens_near_the_ground_as_sim_wind_t_says():
    """ArduPilot SITL's profile: by default (SIM_WIND_T 0) the speed times the square root of the
    height's share of SIM_WIND_T_ALT below it; 1 the same everywhere; 2 less by SIM_WIND_T_COEF a
    metre under SIM_WIND_T_ALT."""
    v, _ = hovering_with(("SIM_WIND_TC", 0.0), ("SIM_WIND_SPD", 8.0), ("SIM_WIND_DIR", 90.0))

    def blowing() -> float:
        v.run_until(v.time_s + 0.5)
        return -v.sim.wind_ned[1]
    assert blowing() == pytest.approx(8.0 * math.sqrt(altitude(v) / 60.0), abs=0.05)
    v.params.set("SIM_WIND_T", 1)
    assert blowing() == pytest.approx(8.0, abs=1e-9)
    v.params.set("SIM_WIND_T", 2)
    v.params.set("SIM_WIND_T_COEF", 0.1)
    assert blowing() == pytest.approx(8.0 - (60.0 - altitude(v)) * 0.1, abs=0.05)
    v.params.set("SIM_WIND_T_COEF", 1.0)
    assert blowing() == 0.0  # never backwards
    v.params.set("SIM_WIND_T_ALT", -3e38)  # any value is taken, as ArduPilot's; the wind stays physical
    v.params.set("SIM_WIND_T_COEF", 3e38)
    assert blowing() == 100.0


# ----- battery --------------------------------------------------------------------------------------
def test_a_battery_that_suddenly_rests_low_triggers_the_battery_failsafe_after_batt_low_timer():
    """ArduCopter SITL's test: SIM_BATT_VOLTAGE 10 on its 12.6 V pack, BATT_LOW_VOLT at its
    default 10.5 V; the failsafe fires once the voltage has been low for BATT_LOW_TIMER (10 s)."""
    v, _ = hovering_with(("FS_BATT_ENABLE", 2))
    v.run_until(v.time_s + 1.0)
    assert not v.failsafes.battery_level
    v.params.set("SIM_BATT_VOLTAGE", 10.0)  # 3.33 V a cell: nearly empty
    assert v.battery.voltage_v == pytest.approx(10.0, abs=0.3)  # the reading follows the setting
    assert not fly_until(v, lambda x: x.mode.name == "RTL", 9.9)
    assert fly_until(v, lambda x: x.mode.name == "RTL", 0.5)
    assert texts(v) == ["Battery 1 is low 9.63V used 5003 mAh", "Battery Failsafe"]
    status = telemetry.sys_status(v, CODEC)
    assert not status.onboard_control_sensors_health & mav.MAV_SYS_STATUS_SENSOR_BATTERY
    assert status.battery_remaining < 10


def test_a_voltage_above_batt_low_volt_trips_nothing():
    v, _ = hovering_with(("FS_BATT_ENABLE", 2))
    v.params.set("SIM_BATT_VOLTAGE", 11.0)
    assert not fly_until(v, lambda x: x.failsafes.battery_level > 0, 15.0)
    assert v.mode.name == "GUIDED"


def test_a_voltage_that_recovers_before_batt_low_timer_restarts_the_timer():
    v, _ = hovering_with(("FS_BATT_ENABLE", 2))
    v.params.set("SIM_BATT_VOLTAGE", 10.0)
    v.run_until(v.time_s + 8.0)
    v.params.set("SIM_BATT_VOLTAGE", 12.6)
    v.run_until(v.time_s + 0.5)
    v.params.set("SIM_BATT_VOLTAGE", 10.0)
    assert not fly_until(v, lambda x: x.failsafes.battery_level > 0, 9.5)
    assert fly_until(v, lambda x: x.failsafes.battery_level == 1, 1.0)


def test_batt_low_timer_0_turns_the_voltage_failsafe_off_but_not_the_capacity_one():
    v, _ = hovering_with(("FS_BATT_ENABLE", 2), ("BATT_LOW_TIMER", 0))
    v.params.set("SIM_BATT_VOLTAGE", 10.0)
    assert not fly_until(v, lambda x: x.failsafes.battery_level > 0, 12.0)
    v.params.set("BATT_LOW_MAH", v.params["BATT_CAPACITY"])  # any use at all leaves less than this
    assert fly_until(v, lambda x: x.failsafes.battery_level == 1, 0.5)


@pytest.mark.parametrize("critical_action, mode", [(0, "GUIDED"), (1, "LAND"), (2, "RTL")])
def test_the_critical_battery_failsafe_takes_its_own_action(critical_action, mode):
    """BATT_FS_CRT_ACT, not the low action (which is RTL here), decides what a critical battery does."""
    v, _ = hovering_with(("BATT_CRT_VOLT", 10.2), ("FS_BATT_ENABLE", 2), ("BATT_FS_CRT_ACT", critical_action))
    v.run_until(v.time_s + 1.0)
    v.params.set("SIM_BATT_VOLTAGE", 10.0)
    assert fly_until(v, lambda x: x.failsafes.battery_level == 2, 10.5)
    assert said(v, "Battery 1 is critical")
    v.run_until(v.time_s + 0.5)
    assert v.mode.name == mode


# ----- radio ----------------------------------------------------------------------------------------
def test_rc_frames_that_stop_trip_the_radio_failsafe_after_rc_fs_timeout_and_clear_when_back():
    """Measured on ArduCopter SITL: SIM_RC_FAIL 1 in a GUIDED hover, FS_THR_ENABLE 1 (its default):
    RTL 1 s later, "Radio Failsafe"; SIM_RC_FAIL 0: "Radio Failsafe Cleared", RTL flown on."""
    v, _ = hovering_with(("SIM_RC_FAIL", 1))
    assert not fly_until(v, lambda x: x.mode.name == "RTL", 0.85)
    assert fly_until(v, lambda x: x.mode.name == "RTL", 0.3)
    assert texts(v) == ["Radio Failsafe"] and v.failsafes.active
    assert (int(Severity.WARNING), "Radio Failsafe") in v.events
    v.params.set("SIM_RC_FAIL", 0)
    v.run_until(v.time_s + 0.2)
    assert texts(v)[-1] == "Radio Failsafe Cleared" and not v.failsafes.radio
    assert v.mode.name == "RTL"


def test_a_failsafe_throttle_from_the_receiver_trips_it_at_once():
    v, _ = hovering_with(("SIM_RC_FAIL", 2))  # 950 us, below FS_THR_VALUE's 975
    assert fly_until(v, lambda x: x.mode.name == "RTL", 0.35)
    assert texts(v) == ["Radio Failsafe"]


@pytest.mark.parametrize("settings, mode, text", [
    ((("FS_THR_ENABLE", 0),), "GUIDED", None),
    ((("FS_THR_ENABLE", 3),), "LAND", "Radio Failsafe"),
    ((("FS_OPTIONS", 4),), "GUIDED", "Radio Failsafe - Continuing Guided Mode"),
])
def test_fs_thr_enable_and_fs_options_decide_what_the_radio_failsafe_does(settings, mode, text):
    v, _ = hovering_with(*settings, ("SIM_RC_FAIL", 1))
    v.run_until(v.time_s + 2.0)
    assert v.mode.name == mode
    assert texts(v) == ([text] if text else [])


def test_the_radio_failsafe_on_the_ground_says_it_disarms():
    v = ready_vehicle()
    v.params.set("SIM_RC_FAIL", 1)
    v.run_until(v.time_s + 1.5)
    assert said(v, "Radio Failsafe - Disarming") and not v.armed


# ----- where faults come from -------------------------------------------------------------------
def test_faults_in_the_vehicle_config_apply_from_the_start():
    v = Vehicle(VehicleConfig(faults={"SIM_GPS_DISABLE": 1, "SIM_ENGINE_FAIL": 4, "SIM_ENGINE_MUL": 0.5}))
    v.run_until(0.5)
    assert not v.has_position() and v.home_ned is None
    assert v.sim.motor_speed_scale[0] == pytest.approx(0.5)  # output 3: its PWM, so its speed, halved


def test_the_wind_and_battery_parameters_start_as_the_scenario_describes_them():
    config = VehicleConfig(sim=SimConfig(wind=SteadyWind(6.0, -90.0), airframe=Airframe(battery_cells=6)))
    params = ParamStore()
    Vehicle(config, params)
    assert (params["SIM_WIND_SPD"], params["SIM_WIND_DIR"]) == (6.0, 270.0)
    assert params["SIM_BATT_VOLTAGE"] == pytest.approx(25.2)


def test_fault_parameters_are_not_kept_across_restarts(tmp_path):
    path = tmp_path / "params.json"
    params = ParamStore(path)
    params.set("SIM_ENGINE_FAIL", 4)
    params.set("RTL_ALT", 2000)
    again = ParamStore(path)
    assert again["RTL_ALT"] == 2000 and again["SIM_ENGINE_FAIL"] == 0

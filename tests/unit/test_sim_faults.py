"""The simulated world's faults as plain settings: motor health, wind and turbulence, the GPS's
switch, satellites and glitch, barometer drift, the battery's resting voltage. No autopilot."""
from __future__ import annotations

import math
import statistics

import pytest

from firefly.sim.airframe import Airframe
from firefly.sim.battery import open_circuit_volts_per_cell, soc_at_open_circuit_volts
from firefly.sim.rigid_body import BodyState
from firefly.sim.rotors import motor_lag_factor, step_motors
from firefly.sim.sensors import FIX_3D, NO_FIX, Barometer, Gps, NoiseConfig
from firefly.sim.vehicle import BATTERY_EVERY, SimConfig, SimVehicle
from firefly.sim.wind import TURBULENCE_TC_S, SteadyWind, Wind

AF = Airframe()
DT = 1.0 / 400.0
QUIET = NoiseConfig(gps_horizontal_m=0.0, gps_vertical_m=0.0, gps_velocity_m_s=0.0, baro_m=0.0)


# ----- motors -----------------------------------------------------------------------------------
def test_a_weak_motor_reaches_its_share_of_the_speed_and_a_failed_one_stops():
    omega = (400.0,) * 4
    for _ in range(400):
        omega = step_motors(omega, (400.0,) * 4, motor_lag_factor(AF, DT), AF.omega_max_rad_s,
                            (1.0, math.sqrt(0.5), 0.0, 1.0))
    assert omega[0] == pytest.approx(400.0) and omega[3] == pytest.approx(400.0)
    assert AF.thrust_coeff_b * omega[1] ** 2 == pytest.approx(0.5 * AF.thrust_coeff_b * 400.0 ** 2, rel=1e-6)
    assert omega[2] == pytest.approx(0.0, abs=1e-9)


def test_motor_thrust_shares_become_speed_scales_and_say_that_they_changed():
    sim = SimVehicle(SimConfig())
    before = sim.conditions_version
    sim.set_motor_thrust_scale((1.0, 0.49, 0.0, 2.0))
    assert sim.motor_speed_scale == pytest.approx((1.0, 0.7, 0.0, 1.0))  # shares clamped to 0..1
    assert sim.conditions_version > before


# ----- wind ---------------------------------------------------------------------------------------
def gusts(seed: int, std: float, seconds: float = 60.0) -> list:
    wind = Wind(SteadyWind(5.0, 270.0), seed)
    wind.turbulence_m_s = std
    return [wind.advance(0.01) for _ in range(round(seconds / 0.01))]


def test_turbulence_is_the_same_for_the_same_seed_and_differs_between_seeds():
    assert gusts(3, 2.0, 5.0) == gusts(3, 2.0, 5.0)
    assert gusts(3, 2.0, 5.0) != gusts(4, 2.0, 5.0)


def test_turbulence_has_the_set_spread_around_the_mean_wind():
    samples = gusts(1, 2.0, 600.0)
    mean = SteadyWind(5.0, 270.0).velocity_ned()
    for axis in range(3):
        values = [s[axis] for s in samples]
        assert statistics.fmean(values) == pytest.approx(mean[axis], abs=0.3)
        assert statistics.pstdev(values) == pytest.approx(2.0, rel=0.15)
    # Correlated over TURBULENCE_TC_S: consecutive 10 ms samples are close, not independent.
    north = [s[0] for s in samples]
    lag1 = statistics.correlation(north[:-1], north[1:])
    assert lag1 == pytest.approx(math.exp(-0.01 / TURBULENCE_TC_S), abs=0.02)


def test_a_changed_wind_takes_effect_over_its_time_constant():
    wind = Wind(SteadyWind(0.0, 0.0), seed=0)
    wind.change_tc_s = 2.0
    wind.set_mean(SteadyWind(10.0, 0.0))  # from the north: blows south
    assert wind.changing
    for _ in range(200):  # one time constant
        wind.advance(0.01)
    assert wind.velocity_ned[0] == pytest.approx(-10.0 * (1.0 - math.exp(-1.0)), rel=1e-3)
    for _ in range(3000):
        wind.advance(0.01)
    assert wind.velocity_ned == pytest.approx((-10.0, 0.0, 0.0), abs=1e-12)
    assert not wind.changing  # settled: no more work per step


def test_the_sim_steps_the_wind_with_the_battery_and_only_while_it_changes():
    sim = SimVehicle(SimConfig(wind=SteadyWind(4.0, 90.0)))
    steady = sim.wind_ned
    for _ in range(40):
        sim.step((0.0,) * 4)
    assert sim.wind_ned == steady and sim.conditions_version == 0
    sim.wind.turbulence_m_s = 3.0
    seen = set()
    for _ in range(40):
        sim.step((0.0,) * 4)
        seen.add(sim.wind_ned)
    assert len(seen - {steady}) == 40 // BATTERY_EVERY  # a new wind every BATTERY_EVERY steps
    assert sim.conditions_version == 40 // BATTERY_EVERY


# ----- GPS and barometer ---------------------------------------------------------------------------
def test_gps_fix_follows_the_switch_only_and_the_satellites_are_reported():
    """As ArduPilot SITL's GPS: SIM_GPS1_NUMSATS is the count reported, the fix is SIM_GPS1_ENABLE's."""
    gps = Gps(0, QUIET)
    body = BodyState(n_m=1.0, e_m=2.0, d_m=-3.0)
    assert gps.read(body).fix_type == FIX_3D
    gps.satellites = 3
    assert gps.read(body).fix_type == FIX_3D and gps.read(body).satellites == 3
    gps.satellites, gps.enabled = 12, False
    reading = gps.read(body)
    assert reading.fix_type == NO_FIX and reading.satellites == 0
    gps.enabled = True
    assert gps.read(body).fix_type == FIX_3D and gps.read(body).satellites == 12


def test_gps_glitch_offsets_every_position_reading():
    gps = Gps(0, QUIET)
    gps.glitch_ned = (30.0, -20.0, 5.0)
    r = gps.read(BodyState(n_m=1.0, e_m=2.0, d_m=-3.0))
    assert (r.n_m, r.e_m, r.d_m) == pytest.approx((31.0, -18.0, 2.0))


def jammed_readings(seed: int, seconds: float = 30.0, body=BodyState(n_m=5.0, e_m=-3.0, d_m=-10.0)) -> list:
    gps = Gps(seed, NoiseConfig())
    gps.jam(True)
    return [gps.read(body, k * 0.1) for k in range(round(seconds * 10))]


def test_a_jammed_gps_loses_its_fix_then_wanders_as_sitls_does():
    """SIM_GPS1_JAM as ArduPilot SITL jams: no lock for the first 1 to 6 s, then fixes that come
    and go, a position stepped up to 200 m at a time from where it started, and speeds within
    +-400 m/s now and then; a reading held for SITL's 0.2 s between its samples."""
    readings = jammed_readings(7)
    assert all(r.fix_type == NO_FIX and r.satellites == 3 for r in readings[:10])
    later = readings[60:]
    assert {r.fix_type for r in later} == {NO_FIX, FIX_3D}
    assert all(2 <= r.satellites <= 16 for r in later)
    steps = [math.hypot(b.n_m - a.n_m, b.e_m - a.e_m) for a, b in zip(readings, readings[1:])]
    assert 0 < max(steps) <= 200.0 * math.sqrt(2) and max(map(abs, (r.n_m - 5.0 for r in later))) > 20.0
    speeds = [max(abs(r.vn_m_s), abs(r.ve_m_s), abs(r.vd_m_s)) for r in later]
    assert 10.0 < max(speeds) <= 400.0 and sorted(speeds)[len(speeds) // 2] < 1.0  # wild only now and then
    assert all(a == b for a, b in zip(readings[::2], readings[1::2]))  # SITL's 5 Hz at Firefly's 10 Hz
    assert all(r.d_m == pytest.approx(-10.0, abs=3.0) for r in readings)  # the height is left alone


def test_jamming_is_repeatable_and_leaves_the_receivers_own_noise_as_it_was():
    assert jammed_readings(3) == jammed_readings(3) != jammed_readings(4)
    quiet, jammed = Gps(3, NoiseConfig()), Gps(3, NoiseConfig())
    body = BodyState()
    jammed.jam(True)
    for k in range(50):
        quiet.read(body, k * 0.1), jammed.read(body, k * 0.1)
    jammed.jam(False)
    assert quiet.read(body, 5.0) == jammed.read(body, 5.0)


def test_barometer_drift_grows_from_when_it_is_set_and_clears_with_zero():
    baro = Barometer(0, QUIET)
    body = BodyState(d_m=-10.0)
    assert baro.altitude_m(body, 5.0) == pytest.approx(10.0)
    baro.set_drift(0.5, 5.0)
    assert baro.altitude_m(body, 9.0) == pytest.approx(12.0)  # 4 s at 0.5 m/s
    baro.set_drift(-0.25, 9.0)  # a new rate continues from the error reached
    assert baro.error_m(13.0) == pytest.approx(1.0)
    baro.set_drift(0.0, 13.0)
    assert baro.altitude_m(body, 20.0) == pytest.approx(10.0)


# ----- battery ----------------------------------------------------------------------------------------
@pytest.mark.parametrize("volts_per_cell", [3.3, 3.61, 3.75, 3.9, 4.1])
def test_resting_voltage_and_state_of_charge_are_inverse(volts_per_cell):
    assert open_circuit_volts_per_cell(soc_at_open_circuit_volts(volts_per_cell)) == pytest.approx(volts_per_cell)


def test_setting_the_resting_voltage_re_initialises_the_charge():
    sim = SimVehicle(SimConfig())
    sim.set_battery_resting_voltage(3 * 3.70)
    soc = soc_at_open_circuit_volts(3.70)
    assert sim.battery.consumed_mah == pytest.approx((1 - soc) * AF.battery_capacity_mah)
    assert sim.battery.voltage_v == pytest.approx(11.1)
    assert sim.battery_remaining == pytest.approx(soc)
    sim.set_battery_resting_voltage(99.0)  # above full: a full pack
    assert sim.battery.consumed_mah == 0.0 and sim.battery.voltage_v == pytest.approx(12.6)

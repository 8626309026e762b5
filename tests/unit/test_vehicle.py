"""The vehicle as ground stations drive it: arming, modes, takeoff, goto, land, RTL, disarm."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.modes import Auto, Brake, Guided, Land, Loiter, Rtl, Stabilize
from firefly.autopilot.results import Result, Severity
from firefly.autopilot.vehicle import Vehicle, VehicleConfig
from firefly.sim.vehicle import SimConfig

from ._util import altitude, fly_until, hovering_vehicle, ready_vehicle


def texts(v: Vehicle) -> list[str]:
    return [text for _, text in v.events]


# ----- home and arming --------------------------------------------------------------------------
def test_home_is_set_and_vehicle_armable_after_half_a_second():
    v = Vehicle(VehicleConfig())
    v.run_until(0.5)
    assert v.home_ned is not None
    assert v.home_ned == pytest.approx((0.0, 0.0, 0.0))
    assert v.home.lat_deg == pytest.approx(v.config.home.lat_deg, abs=1e-9)
    assert v.home.alt_m == pytest.approx(v.config.home.alt_m, abs=1e-9)
    assert v.is_armable(), v.prearm_failure()
    assert "Home set" not in texts(v)  # ArduCopter sets home without a word


def test_home_follows_the_start_offset():
    v = Vehicle(VehicleConfig(offset_ne_m=(12.0, -4.0)))
    v.run_until(0.5)
    assert v.home_ned == pytest.approx((12.0, -4.0, 0.0))


@pytest.mark.parametrize("mode", [Land, Rtl, Brake])
def test_arming_refused_in_non_armable_modes(mode):
    v = ready_vehicle()
    assert v.set_mode(mode.number) == Result.ACCEPTED
    v.events.clear()
    assert v.arm() == Result.FAILED
    assert not v.armed
    assert (int(Severity.CRITICAL), f"Arm: {v.mode.name} mode not armable") in v.events
    # Even a forced arm does not arm in a mode that cannot fly from the ground.
    assert v.arm(force=True) == Result.FAILED


@pytest.mark.parametrize("mode", [Stabilize, Guided, Loiter])
def test_arming_accepted_in_armable_modes(mode):
    v = ready_vehicle()
    assert v.set_mode(mode.number) == Result.ACCEPTED
    assert v.arm() == Result.ACCEPTED
    assert v.armed and v.landed
    assert "Arming motors" in texts(v)


def test_takeoff_refused_when_disarmed():
    v = ready_vehicle()
    v.set_mode(Guided.number)
    assert v.takeoff(10.0) == Result.FAILED
    v.run_until(2.0)
    assert v.body.d_m == 0.0


def test_takeoff_refused_for_nonsense_altitudes():
    v = ready_vehicle()
    v.set_mode(Guided.number)
    v.arm()
    assert v.takeoff(math.nan) == Result.FAILED
    assert v.takeoff(0.0) == Result.FAILED
    assert v.takeoff(-5.0) == Result.FAILED


def test_set_mode_unknown_number_fails_and_keeps_the_mode():
    v = ready_vehicle()
    before = v.mode
    assert v.set_mode(99) == Result.FAILED
    assert v.set_mode(13) == Result.FAILED  # SPORT: not built into ArduCopter SITL either
    assert v.mode is before


def test_auto_without_a_mission_is_refused_armed_with_a_reason_and_entered_disarmed():
    v = ready_vehicle()
    assert v.set_mode(Auto.number) == Result.ACCEPTED  # disarmed: ArduCopter enters it...
    assert v.arm() == Result.FAILED and "Arm: Mode requires mission" in texts(v)  # ...and refuses to arm
    v.set_mode(4)
    assert v.arm() == Result.ACCEPTED
    before = v.mode
    assert v.set_mode(Auto.number) == Result.FAILED
    assert v.mode is before
    refusals = [t for t in texts(v) if t.startswith("Mode change to AUTO failed")]
    assert refusals and refusals[0].split("failed:", 1)[1].strip()


def test_mode_numbers_are_arducopters():
    from firefly.autopilot.modes import MODE_BY_NAME
    assert {name: cls.number for name, cls in MODE_BY_NAME.items()} == {
        "STABILIZE": 0, "ALT_HOLD": 2, "AUTO": 3, "GUIDED": 4, "LOITER": 5, "RTL": 6,
        "LAND": 9, "POSHOLD": 16, "BRAKE": 17,
        "ACRO": 1, "DRIFT": 11, "FLIP": 14, "AUTOTUNE": 15, "THROW": 18, "FLOWHOLD": 22, "FOLLOW": 23,
        "SYSTEMID": 25, "TURTLE": 28,
        "CIRCLE": 7, "AVOID_ADSB": 19, "SMART_RTL": 21, "ZIGZAG": 24, "AUTO_RTL": 27, "GUIDED_NOGPS": 20}


# ----- flying -----------------------------------------------------------------------------------
def test_guided_takeoff_reaches_10m_without_overshoot_and_settles_as_arducopter():
    """ArduCopter SITL, armed and told to take off to 10 m at once: off the ground after 4.0 s (the
    arming delay and the throttle's slew), done at 10.0 m after 10.5 s (parity area `takeoff`)."""
    v = ready_vehicle()
    v.set_mode(Guided.number)
    v.arm()
    t0 = v.time_s
    assert v.takeoff(10.0) == Result.ACCEPTED
    samples = []
    saw_takeoff_state = False
    while v.time_s < t0 + 20.0:
        v.run_until(v.time_s + 0.05)
        samples.append((v.time_s - t0, altitude(v)))
        saw_takeoff_state |= v.landed_state() == "TAKEOFF"
    assert saw_takeoff_state
    assert all(a < 0.05 for t, a in samples if t < 3.0)  # the arming delay, then the slew: still down
    peak = max(a for _, a in samples)
    assert peak < 10.0 * 1.10
    assert all(abs(a - 10.0) <= 0.3 for t, a in samples if t >= 11.0)
    assert abs(samples[-1][1] - 10.0) <= 0.3
    assert not v.landed and v.landed_state() == "IN_AIR"
    # It climbed straight up.
    assert math.hypot(v.body.n_m, v.body.e_m) < 0.5


def test_guided_goto_30m_north_arrives_within_1m():
    v = hovering_vehicle(10.0)
    assert v.guided_goto(30.0, 0.0, None) == Result.ACCEPTED
    arrived = fly_until(v, lambda x: math.hypot(x.body.n_m - 30.0, x.body.e_m) < 1.0 and
                        math.hypot(x.body.vn_m_s, x.body.ve_m_s) < 0.2, 30.0)
    assert arrived
    v.run_until(v.time_s + 3.0)  # and it stays there
    assert math.hypot(v.body.n_m - 30.0, v.body.e_m) < 1.0
    assert abs(altitude(v) - 10.0) < 0.5


def test_guided_goto_refused_outside_guided():
    v = ready_vehicle()
    v.set_mode(Loiter.number)
    assert v.guided_goto(10.0, 0.0, -5.0) == Result.DENIED


def test_land_from_hover_lands_and_disarms():
    v = hovering_vehicle(10.0)
    n0, e0 = v.body.n_m, v.body.e_m
    assert v.set_mode(Land.number) == Result.ACCEPTED
    v.run_until(v.time_s + 1.0)
    assert v.landed_state() == "LANDING"
    assert fly_until(v, lambda x: not x.armed, 60.0)
    assert v.landed and v.body.d_m == 0.0
    assert math.hypot(v.body.n_m - n0, v.body.e_m - e0) < 1.0  # straight down
    assert "Disarming motors" in texts(v)


def test_rtl_returns_home_and_disarms():
    v = hovering_vehicle(10.0)
    v.guided_goto(25.0, -15.0, None)
    assert fly_until(v, lambda x: math.hypot(x.body.n_m - 25.0, x.body.e_m + 15.0) < 1.0, 30.0)
    assert v.set_mode(Rtl.number) == Result.ACCEPTED
    max_alt = 0.0

    def done(x):
        nonlocal max_alt
        max_alt = max(max_alt, altitude(x))
        return not x.armed

    assert fly_until(v, done, 120.0)
    assert math.hypot(v.body.n_m - v.home_ned[0], v.body.e_m - v.home_ned[1]) < 2.0
    assert v.body.d_m == 0.0
    # It returned at RTL_ALT (15 m), above the 10 m it was flying at.
    assert max_alt == pytest.approx(v.params["RTL_ALT"] / 100.0, abs=0.5)


def test_disarm_in_flight_refused_without_force_and_accepted_with_force():
    v = hovering_vehicle(5.0)
    assert v.disarm("gcs") == Result.FAILED
    assert v.armed
    assert "Disarm: not landed" not in texts(v)  # ArduCopter refuses in silence
    assert v.disarm("gcs", force=True) == Result.ACCEPTED
    assert not v.armed
    v.run_until(v.time_s + 0.5)
    assert v.body.vd_m_s > 1.0  # motors stopped: it falls
    assert fly_until(v, lambda x: x.sim.state.on_ground, 10.0)


def test_auto_disarm_after_disarm_delay_on_the_ground():
    v = ready_vehicle()
    v.set_mode(Guided.number)
    v.arm()
    t0 = v.time_s
    delay = v.params["DISARM_DELAY"]
    v.run_until(t0 + delay - 0.5)
    assert v.armed
    v.run_until(t0 + delay + 0.5)
    assert not v.armed
    assert "Disarming motors" in texts(v)


def test_land_and_rtl_entered_on_the_ground_disarm_as_arducopter_does():
    """Measured on ArduCopter SITL: LAND entered armed on the ground disarms 1.1-1.5 s later;
    RTL stays armed until the auto-disarm, DISARM_DELAY after arming."""
    v = ready_vehicle()
    v.set_mode(Guided.number)
    v.arm()
    armed_at = v.time_s
    v.run_until(armed_at + 1.0)
    v.set_mode(Land.number)
    v.run_until(v.time_s + 0.5)
    assert v.armed
    v.run_until(v.time_s + 1.0)
    assert not v.armed
    v = ready_vehicle()
    v.set_mode(Guided.number)
    v.arm()
    armed_at = v.time_s
    v.run_until(armed_at + 1.0)
    v.set_mode(Rtl.number)
    v.run_until(armed_at + v.params["DISARM_DELAY"] - 0.5)
    assert v.armed and v.landed
    v.run_until(armed_at + v.params["DISARM_DELAY"] + 0.5)
    assert not v.armed


def test_auto_disarm_follows_the_parameter():
    v = ready_vehicle()
    v.params.set("DISARM_DELAY", 2)
    v.set_mode(Guided.number)
    v.arm()
    v.run_until(v.time_s + 2.5)
    assert not v.armed
    v2 = ready_vehicle()
    v2.params.set("DISARM_DELAY", 0)  # 0 = never
    v2.set_mode(Guided.number)
    v2.arm()
    v2.run_until(v2.time_s + 15.0)
    assert v2.armed


def test_idle_props_when_armed_on_the_ground_after_the_arming_delay_and_stopped_when_disarmed():
    v = ready_vehicle()
    v.set_mode(Guided.number)
    v.run_until(v.time_s + 0.2)
    assert v.sim.state.omega_rad_s == (0.0,) * 4
    v.arm()
    v.run_until(v.time_s + 1.9)  # ArduCopter's arming delay: nothing spins for 2 s
    assert v.sim.state.omega_rad_s == (0.0,) * 4
    v.run_until(v.time_s + 0.6)
    idle = v.sim.airframe.omega_idle_rad_s
    assert v.sim.state.omega_rad_s == pytest.approx((idle,) * 4, rel=1e-3)
    assert v.body.d_m == 0.0


def _fly_sequence(seed: int) -> Vehicle:
    v = Vehicle(VehicleConfig(sim=SimConfig(seed=seed)))
    v.run_until(0.5)
    v.set_mode(Guided.number)
    v.arm()
    v.takeoff(6.0)
    v.run_until(6.0)
    v.guided_goto(12.0, -7.0, -8.0, yaw=1.0)
    v.run_until(14.0)
    v.guided_velocity(1.0, 1.0, 0.0)
    v.run_until(16.0)
    v.set_mode(Land.number)
    v.run_until(20.0)
    return v


def test_same_seed_and_commands_give_bit_identical_states():
    a, b = _fly_sequence(5), _fly_sequence(5)
    assert a.body == b.body  # exact equality of every float
    assert a.sim.state.omega_rad_s == b.sim.state.omega_rad_s
    assert a.sim.battery == b.sim.battery
    assert a.gps == b.gps
    assert a.body.d_m < -1.0  # it really flew


def test_gps_noise_depends_on_the_seed():
    a, b = _fly_sequence(5), _fly_sequence(6)
    assert a.gps != b.gps


@pytest.mark.parametrize("home_yaw_deg", [90.0, 225.0])
@pytest.mark.parametrize("wp_yaw_behavior", [0, 2])
def test_goto_works_whatever_the_heading_and_faces_the_way_as_wp_yaw_behavior_says(home_yaw_deg, wp_yaw_behavior):
    v = hovering_vehicle(10.0, home_yaw_deg=home_yaw_deg)
    v.params.set("WP_YAW_BEHAVIOR", wp_yaw_behavior)
    v.guided_goto(20.0, 5.0, None)
    assert fly_until(v, lambda x: math.hypot(x.body.n_m - 20.0, x.body.e_m - 5.0) < 1.0 and
                     math.hypot(x.body.vn_m_s, x.body.ve_m_s) < 0.2, 30.0)
    heading = math.degrees(v.attitude[2])
    if wp_yaw_behavior == 0:  # never change yaw: the heading was not asked to change, so it did not
        assert math.degrees(wrap(math.radians(heading - home_yaw_deg))) == pytest.approx(0, abs=2)
    else:  # ArduCopter's default faces the way it flies: the target's bearing (14°) as it comes
        assert math.degrees(wrap(math.radians(heading - 14.0))) == pytest.approx(0, abs=10)


def test_a_velocity_target_turns_the_nose_the_way_it_flies():
    """Measured on ArduCopter SITL: 3 m/s east as a velocity-only SET_POSITION_TARGET_LOCAL_NED
    turns the nose from 0° to 90° within 5 s (WP_YAW_BEHAVIOR's default)."""
    v = hovering_vehicle(10.0)
    v.mode.set_velocity(v.ctx, 0.0, 3.0, 0.0)
    for _ in range(50):
        v.run_until(v.time_s + 0.1)
        v.mode.set_velocity(v.ctx, 0.0, 3.0, 0.0)
    assert math.degrees(v.attitude[2]) == pytest.approx(90.0, abs=5)


def test_position_hold_in_steady_wind():
    from firefly.sim.wind import SteadyWind
    v = hovering_vehicle(10.0, sim=SimConfig(wind=SteadyWind(6.0, 45.0)))
    n0, e0 = v.body.n_m, v.body.e_m
    v.run_until(v.time_s + 10.0)
    assert math.hypot(v.body.n_m - n0, v.body.e_m - e0) < 0.5
    roll, pitch, _ = v.attitude
    # Leaning into a wind from the north-east: nose down (toward north) and right wing down.
    assert pitch < -0.01 and roll > 0.01


def wrap(angle: float) -> float:
    return (angle + math.pi) % (2 * math.pi) - math.pi


def test_condition_yaw_reaches_the_heading():
    v = hovering_vehicle(10.0)
    assert v.set_yaw(90.0, relative=False, direction=1) == Result.ACCEPTED
    v.run_until(v.time_s + 15.0)
    assert math.degrees(v.attitude[2]) == pytest.approx(90.0, abs=1.0)
    assert v.set_yaw(30.0, relative=True, direction=-1) == Result.ACCEPTED
    v.run_until(v.time_s + 15.0)
    assert math.degrees(v.attitude[2]) == pytest.approx(60.0, abs=1.0)
    assert v.set_yaw(400.0, relative=False, direction=1) == Result.FAILED


def test_heading_step_overshoots_less_than_10_percent():
    v = hovering_vehicle(10.0)
    v.set_yaw(90.0, relative=False, direction=1)
    peak = 0.0
    for _ in range(300):
        v.run_until(v.time_s + 0.05)
        peak = max(peak, math.degrees(v.attitude[2]))
    assert peak < 99.0

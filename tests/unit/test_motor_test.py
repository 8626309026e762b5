"""The motor test (autopilot/motor_test.py) on its own and through the vehicle and its session, in
sim time, as ArduCopter SITL was measured running one (tests/parity/probes/motor_test.py)."""
from __future__ import annotations

import math
from types import SimpleNamespace

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from firefly.autopilot.mavlink.dialect import mavlink as mav
from firefly.autopilot.mavlink.sensor_messages import motor_pwm
from firefly.autopilot.motor_outputs import OUTPUT_OF_MOTOR, omega_of_pwm
from firefly.autopilot.motor_test import COMPASS_CAL, PERCENT, PILOT, PWM, MotorTest

from ._session_link import Link
from ._util import hovering_vehicle, ready_vehicle, statustexts

RANGE = (1000, 2000)
MOTOR_TEST = mav.MAV_CMD_DO_MOTOR_TEST


def run(test: MotorTest, until_s: float, dt: float = 0.01, pilot_us: int = 1000) -> list[tuple[float, list[int]]]:
    """The outputs at each update from 0 until the test ends or `until_s`."""
    seen, t = [], 0.0
    while t <= until_s + 1e-9 and test.update(t, RANGE, pilot_us):
        seen.append((round(t, 2), test.outputs(RANGE[0])))
        t += dt
    return seen


def test_each_place_in_the_test_order_is_one_output_clockwise_from_the_front():
    for seq, output in ((1, 3), (2, 1), (3, 4), (4, 2)):
        test = MotorTest()
        assert test.start(seq, PERCENT, 10, 1.0, 0, 0.0)
        outputs = run(test, 2.0)[-1][1]
        assert outputs[output - 1] == 1100 and sum(outputs) == 1100 + 3 * 1000


def test_the_test_ends_at_its_timeout_and_a_count_runs_the_next_motors_after_half_a_timeout_at_rest():
    test = MotorTest()
    test.start(1, PERCENT, 10, 1.0, 4, 0.0)
    seen = run(test, 10.0)
    running = {t: [i + 1 for i, pwm in enumerate(o) if pwm > 1000] for t, o in seen}
    assert running[0.5] == [3] and running[1.2] == [] and running[2.0] == [1] and running[3.5] == [4]
    assert running[5.0] == [2] and seen[-1][0] == 5.49  # 4 x 1 s and 3 x 0.5 s at rest
    assert not test.running


def test_a_throttle_outside_800_to_2200_us_or_of_an_unknown_type_ends_the_test_at_once():
    for kind, value in ((PERCENT, 150.0), (PWM, 2300.0), (PWM, 700.0), (PERCENT, math.nan), (7, 10.0)):
        test = MotorTest()
        test.start(1, kind, value, 1.0, 0, 0.0)
        assert run(test, 2.0) == [] and not test.running
    test = MotorTest()
    test.start(1, PILOT, 0.0, 1.0, 0, 0.0)
    assert run(test, 0.0, pilot_us=1234)[0][1][2] == 1234
    test = MotorTest()
    test.start(1, COMPASS_CAL, 25.0, 1.0, 0, 0.0)
    assert run(test, 0.0)[0][1][2] == 1250


def test_a_nan_or_negative_timeout_runs_on_and_a_second_start_keeps_the_first_motor_spinning():
    for timeout in (math.nan, -1.0):
        test = MotorTest()
        test.start(1, PERCENT, 10, timeout, 0, 0.0)
        assert len(run(test, 30.0, dt=0.5)) == 61 and test.running
    test = MotorTest()
    test.start(1, PERCENT, 10, 4.0, 0, 0.0)
    run(test, 0.5)
    assert not test.start(3, PERCENT, 20, 4.0, 0, 0.6)  # no new "starting"
    test.update(0.7, RANGE, 1000)
    assert test.outputs(1000) == [1000, 1000, 1100, 1200]


def test_the_rotor_speed_of_a_pwm_is_the_inverse_of_the_reported_output():
    v = ready_vehicle()
    p = v.params
    args = (*v.pwm_range, p["MOT_SPIN_MIN"], p["MOT_SPIN_MAX"], p["MOT_THST_EXPO"], v.omega_idle_rad_s, v.omega_max_rad_s)
    assert omega_of_pwm(1000, *args) == 0.0 and omega_of_pwm(2000, *args) == v.omega_max_rad_s
    assert 0.0 < omega_of_pwm(1050, *args) < v.omega_idle_rad_s
    speeds = [omega_of_pwm(pwm, *args) for pwm in range(1000, 2001, 25)]
    assert speeds == sorted(speeds)
    for pwm in (1300, 1500, 1800):  # the output mapping reads a command at that speed as that PWM
        flying = SimpleNamespace(safety_on=False, motor_test_pwm=None, params=p, pwm_range=v.pwm_range, armed=True, omega_idle_rad_s=v.omega_idle_rad_s,
                                 omega_max_rad_s=v.omega_max_rad_s, motor_commands=(omega_of_pwm(pwm, *args),) * 4)
        assert abs(motor_pwm(flying)[0] - pwm) <= 1


def test_through_the_vehicle_the_motor_spins_the_heartbeat_says_armed_and_the_end_disarms():
    link = Link()
    v = link.vehicle
    ack, out = link.command(MOTOR_TEST, 2, PWM, 1300, 1.0, 0, 0)
    assert ack.result == mav.MAV_RESULT_ACCEPTED and "starting motor test" in statustexts(out + link.poll())
    v.run_until(v.time_s + 0.5)
    assert v.motors_armed and not v.armed
    assert motor_pwm(v) == [1300, 1000, 1000, 1000]
    sim_motor = OUTPUT_OF_MOTOR.index(1)
    assert v.motor_speeds_rad_s[sim_motor] > 0.0 and max(v.motor_speeds_rad_s[:sim_motor] + v.motor_speeds_rad_s[sim_motor + 1:]) == 0.0
    assert v.landed  # 30 % on one motor lifts nothing
    v.run_until(v.time_s + 1.0)
    assert not v.motors_armed and "finished motor test" in statustexts(link.poll())
    assert motor_pwm(v) == [1000] * 4


def test_armed_in_the_arming_delay_it_is_cancelled_and_after_it_arming_answers_but_never_arms():
    link = Link()
    v = link.vehicle
    v.arm()
    ack, _ = link.command(MOTOR_TEST, 1, PERCENT, 10, 1.0)
    assert ack.result == mav.MAV_RESULT_ACCEPTED
    v.run_until(v.time_s + 0.1)
    assert statustexts(link.poll())[-3:] == ["starting motor test", "Motor Test: cancelled", "finished motor test"]
    assert not v.armed and not v.motors_armed
    for arm in (1, 0, 1):
        ack, out = link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, arm)
        assert ack.result == mav.MAV_RESULT_ACCEPTED and statustexts(out + link.poll()) == [] and not v.motors_armed


def test_refused_in_flight_in_words_and_an_arm_during_a_test_is_accepted_silently():
    link = Link(hovering_vehicle(5.0))
    ack, out = link.command(MOTOR_TEST, 1, PERCENT, 10, 1.0)
    assert ack.result == mav.MAV_RESULT_FAILED and "Motor Test: vehicle not landed" in statustexts(out + link.poll())
    link = Link()
    link.command(MOTOR_TEST, 1, PERCENT, 10, 2.0)
    link.poll()
    ack, out = link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    assert ack.result == mav.MAV_RESULT_ACCEPTED and statustexts(out + link.poll()) == [] and not link.vehicle.armed


FLOATS = st.one_of(st.floats(width=32, allow_nan=True, allow_infinity=True), st.sampled_from([0.0, 1.0, 4.0, 100.0, -1.0]))


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.lists(FLOATS, min_size=7, max_size=7))
def test_any_parameters_get_one_ack_and_the_vehicle_runs_on(params):
    link = Link()
    ack, _ = link.command(MOTOR_TEST, *params)
    assert ack.result in (mav.MAV_RESULT_ACCEPTED, mav.MAV_RESULT_FAILED)
    v = link.vehicle
    v.run_until(v.time_s + 0.3)
    link.poll()
    assert not v.internal_error_bits

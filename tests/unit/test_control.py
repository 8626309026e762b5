"""Outer and inner loops: square-root shaping, thrust with tilt compensation, lean from
acceleration, attitude torques' signs and limits."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.control.attitude import AttitudeController, wrap_pi
from firefly.autopilot.control.position import PositionController, sqrt_controller
from firefly.autopilot.params import ParamStore
from firefly.sim.airframe import GRAVITY_M_S2, Airframe

AF = Airframe()


@pytest.fixture
def params():
    return ParamStore()


def test_sqrt_controller_linear_near_zero_and_continuous_at_the_join():
    p, a = 2.0, 4.0
    assert sqrt_controller(0.1, p, a) == pytest.approx(0.2)
    assert sqrt_controller(-0.1, p, a) == pytest.approx(-0.2)
    join = a / (p * p)
    below, above = sqrt_controller(join * (1 - 1e-9), p, a), sqrt_controller(join * (1 + 1e-9), p, a)
    assert below == pytest.approx(above, rel=1e-6)
    # Far out: the speed from which constant deceleration a stops in the remaining distance.
    e = 100.0
    assert sqrt_controller(e, p, a) == pytest.approx(math.sqrt(2 * a * (e - join / 2)))
    assert sqrt_controller(e, p, a) < p * e


def test_thrust_for_level_hover_is_the_weight_and_compensates_tilt(params):
    pc = PositionController(AF, params)
    assert pc.thrust_for(0.0, 0.0, 0.0) == pytest.approx(AF.weight_n)
    tilt = math.radians(20)
    assert pc.thrust_for(0.0, tilt, 0.0) == pytest.approx(AF.weight_n / math.cos(tilt))
    # Downward acceleration asked: less thrust; never negative nor above the motors' total.
    assert pc.thrust_for(2.0, 0.0, 0.0) < AF.weight_n
    assert pc.thrust_for(100.0, 0.0, 0.0) == 0.0
    assert pc.thrust_for(-1000.0, 0.0, 0.0) == pytest.approx(4 * AF.max_rotor_thrust_n)


def test_lean_from_accel_directions_and_limit(params):
    pc = PositionController(AF, params)
    roll, pitch = pc.lean_from_accel(2.0, 0.0, 0.0)  # north, heading north: nose down
    assert pitch == pytest.approx(math.atan2(-2.0, GRAVITY_M_S2)) and roll == pytest.approx(0.0)
    roll, pitch = pc.lean_from_accel(0.0, 2.0, 0.0)  # east, heading north: right wing down
    assert roll > 0.0 and pitch == pytest.approx(0.0)
    roll, pitch = pc.lean_from_accel(2.0, 0.0, math.pi / 2)  # north while heading east: roll left
    assert roll < 0.0 and pitch == pytest.approx(0.0, abs=1e-12)
    lean_max = math.radians(params["ANGLE_MAX"] / 100.0)
    roll, pitch = pc.lean_from_accel(1000.0, 0.0, 0.0)
    assert abs(pitch) == pytest.approx(lean_max)


def test_horizontal_velocity_target_is_slewed_at_the_acceleration_limit(params):
    pc = PositionController(AF, params)
    pc.reset((0.0, 0.0), 0.0)
    dt = 0.01
    pc.horizontal((1000.0, 0.0), (0.0, 0.0), 10.0, (0.0, 0.0), (0.0, 0.0), 0.0, dt)
    assert math.hypot(*pc.vel_target_ne) == pytest.approx(pc.accel_xy_max * dt)
    for _ in range(10000):
        pc.horizontal((1000.0, 0.0), (0.0, 0.0), 10.0, (0.0, 0.0), (0.0, 0.0), 0.0, dt)
    assert pc.vel_target_ne[0] == pytest.approx(10.0)  # capped at speed_max


def test_vertical_climb_rate_is_limited_to_wpnav_speeds(params):
    pc = PositionController(AF, params)
    pc.reset((0.0, 0.0), 0.0)
    for _ in range(1000):
        pc.vertical(-1000.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.01)
    assert pc.vel_target_d == pytest.approx(-params["WPNAV_SPEED_UP"] / 100.0)
    for _ in range(1000):
        pc.vertical(1000.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.01)
    assert pc.vel_target_d == pytest.approx(params["WPNAV_SPEED_DN"] / 100.0)


def test_attitude_torque_signs_follow_the_angle_errors(params):
    ac = AttitudeController(AF, params)
    u2, u3, u4 = ac.update(0.2, -0.1, 0.3, 0.0, 0.0, 0.0, 0.0, (0.0, 0.0, 0.0), 0.0025)
    assert u2 > 0.0 and u3 < 0.0 and u4 > 0.0
    assert abs(u2) <= AF.arm_length_m * AF.max_rotor_thrust_n
    assert abs(u4) <= 2 * AF.torque_ratio_c * AF.max_rotor_thrust_n


def test_attitude_yaw_error_takes_the_short_way_round(params):
    ac = AttitudeController(AF, params)
    # Target 170 deg, at -170 deg: the short way is -20 deg (negative yaw torque).
    _, _, u4 = ac.update(0.0, 0.0, math.radians(170), 0.0, 0.0, 0.0, math.radians(-170),
                         (0.0, 0.0, 0.0), 0.0025)
    assert u4 < 0.0


def test_attitude_torques_saturate_at_rotor_limits(params):
    ac = AttitudeController(AF, params)
    u2, u3, _ = ac.update(3.0, 3.0, None, 0.0, 0.0, 0.0, 0.0, (-50.0, -50.0, 0.0), 0.0025)
    assert u2 == pytest.approx(AF.arm_length_m * AF.max_rotor_thrust_n)
    assert u3 == pytest.approx(AF.arm_length_m * AF.max_rotor_thrust_n)


@pytest.mark.parametrize("angle,expected", [(0.0, 0.0), (math.pi / 2, math.pi / 2),
                                            (3 * math.pi / 2, -math.pi / 2),
                                            (-3 * math.pi / 2, math.pi / 2), (7.0, 7.0 - 2 * math.pi)])
def test_wrap_pi(angle, expected):
    assert wrap_pi(angle) == pytest.approx(expected)
    assert -math.pi <= wrap_pi(angle) < math.pi


def test_param_change_reconfigures_gains(params):
    ac = AttitudeController(AF, params)
    params.set("ATC_RAT_RLL_P", 0.3)
    ac.configure(params)
    assert ac.rate_pids[0].kp == 0.3

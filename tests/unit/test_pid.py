"""PID: proportional/integral arithmetic, anti-windup, derivative on measurement, reset."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.control.pid import Pid

DT = 0.01


def test_proportional_only():
    pid = Pid(2.0)
    assert pid.update(3.0, 1.0, DT) == pytest.approx(4.0)
    assert pid.update(1.0, 3.0, DT) == pytest.approx(-4.0)
    assert pid.integrator == 0.0


def test_integrator_accumulates_ki_error_dt():
    pid = Pid(0.0, ki=0.5)
    for _ in range(100):
        pid.update(1.0, 0.0, DT)
    assert pid.integrator == pytest.approx(0.5 * 1.0 * 100 * DT)
    # Output of a pure integrator is the integrator (already updated after the output was formed).
    out = pid.update(1.0, 0.0, DT)
    assert out == pytest.approx(0.5)


def test_integrator_is_limited_to_imax():
    pid = Pid(0.0, ki=10.0, imax=0.3)
    for _ in range(1000):
        pid.update(1.0, 0.0, DT)
    assert pid.integrator == pytest.approx(0.3)
    for _ in range(1000):
        pid.update(-1.0, 0.0, DT)
    assert pid.integrator == pytest.approx(-0.3)


def test_no_windup_while_output_saturated():
    pid = Pid(1.0, ki=5.0, imax=10.0, out_limit=1.0)
    pid.update(0.5, 0.0, DT)  # unsaturated: integrates
    i0 = pid.integrator
    assert i0 > 0.0
    for _ in range(500):  # large error pushing further into saturation
        assert pid.update(5.0, 0.0, DT) == 1.0
    assert pid.integrator == i0
    assert abs(pid.integrator) <= pid.imax


def test_saturated_integrator_still_unwinds_when_the_error_reverses():
    pid = Pid(1.0, ki=5.0, out_limit=1.0)
    pid.integrator = 3.0  # e.g. preloaded
    before = pid.integrator
    out = pid.update(-1.0, 0.0, DT)  # kp*e + I = 2 > limit, but the error now pulls it back
    assert out == 1.0
    assert pid.integrator < before


def test_recovers_at_once_after_long_saturation():
    pid = Pid(1.0, ki=2.0, imax=5.0, out_limit=1.0)
    for _ in range(2000):
        pid.update(10.0, 0.0, DT)
    # The target is reached: without wind-up the output falls out of saturation immediately.
    out = pid.update(0.0, 0.0, DT)
    assert out < 1.0
    out = pid.update(0.0, 0.2, DT)
    assert out < 0.0


def test_derivative_on_measurement_has_no_setpoint_kick():
    pid = Pid(0.0, kd=1.0)
    pid.update(0.0, 0.0, DT)
    assert pid.update(100.0, 0.0, DT) == 0.0  # setpoint step: measurement unchanged
    assert pid.update(-50.0, 0.0, DT) == 0.0


def test_derivative_opposes_measurement_change():
    pid = Pid(0.0, kd=1.0)
    pid.update(0.0, 0.0, DT)
    assert pid.update(0.0, 0.1, DT) < 0.0


def test_filtered_derivative_converges_to_minus_kd_times_slope():
    pid = Pid(0.0, kd=0.5, d_filter_hz=20.0)
    slope = 2.0
    out = None
    for k in range(200):  # 2 s, many filter time constants (8 ms)
        out = pid.update(0.0, slope * k * DT, DT)
    assert out == pytest.approx(-0.5 * slope, rel=1e-6)


def test_first_update_has_no_derivative():
    pid = Pid(0.0, kd=10.0)
    assert pid.update(0.0, 123.0, DT) == 0.0


def test_reset_forgets_history_and_clamps_preload():
    pid = Pid(1.0, ki=1.0, kd=1.0, imax=0.5)
    for k in range(50):
        pid.update(1.0, 0.01 * k, DT)
    pid.reset()
    assert pid.integrator == 0.0
    # No derivative from the measurement seen before the reset.
    assert pid.update(0.0, 50.0, DT) == pytest.approx(-50.0)
    pid.reset(integrator=3.0)
    assert pid.integrator == 0.5
    pid.reset(integrator=-3.0)
    assert pid.integrator == -0.5


def test_output_limit_is_symmetric():
    pid = Pid(10.0, out_limit=2.0)
    assert pid.update(1.0, 0.0, DT) == 2.0
    assert pid.update(-1.0, 0.0, DT) == -2.0
    assert math.isinf(Pid(1.0).out_limit)


def test_derivative_on_error_kicks_on_a_target_step_and_on_measurement_does_not():
    on_measurement, on_error = Pid(0.0, kd=1.0), Pid(0.0, kd=1.0)
    on_error.d_on_error = 1.0
    for pid in (on_measurement, on_error):
        pid.update(0.0, 0.0, DT)
    assert on_measurement.update(1.0, 0.0, DT) == 0.0  # the target stepped; nothing moved
    assert on_error.update(1.0, 0.0, DT) > 0.0  # ArduCopter's AC_PID with FLTT 0: a kick
    # The measurement moving alone: both see the same derivative, the same sign
    a, b = Pid(0.0, kd=1.0), Pid(0.0, kd=1.0)
    b.d_on_error = 1.0
    a.update(0.0, 0.0, DT), b.update(0.0, 0.0, DT)
    assert a.update(0.0, 0.1, DT) == b.update(0.0, 0.1, DT) < 0.0

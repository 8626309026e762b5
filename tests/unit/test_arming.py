"""Arming (safety/arming.py): the pre-arm table and the refusals, on real vehicles in sim time."""
from __future__ import annotations

import pytest

from firefly.autopilot.modes import ModeNumber
from firefly.autopilot.results import Result
from firefly.autopilot.safety.arming import PREARM_CHECKS, arm_refusal, prearm_failure

from ._util import ready_vehicle


def texts(v) -> list[str]:
    return [text for _, text in v.drain_events()]


def test_a_ready_vehicle_passes_every_check():
    v = ready_vehicle()
    assert not any(check(v) for check in PREARM_CHECKS)  # None, or no words
    assert prearm_failure(v) is None and arm_refusal(v, force=False) is None


@pytest.mark.parametrize("param, value, words", [
    ("SIM_GPS_DISABLE", 1, "Need 3D Fix"),
    ("BATT_LOW_VOLT", 20.0, "Battery 1 low voltage failsafe"),
    ("BATT_ARM_VOLT", 20.0, "Battery 1 below minimum arming voltage"),
])
def test_a_failing_check_refuses_the_arm_with_arducopters_words(param, value, words):
    v = ready_vehicle()
    assert v.set_mode(ModeNumber.GUIDED) == Result.ACCEPTED
    v.params.set(param, value)
    v.run_until(v.time_s + 0.2)  # the next GPS sample sees the change
    assert prearm_failure(v) == words
    texts(v)
    assert v.arm() == Result.FAILED and not v.armed
    assert texts(v) == [f"Arm: {words}"]  # as ArduCopter 4.7 words the checks an ARM runs


def test_a_mode_that_flies_without_a_position_arms_without_a_fix():
    v = ready_vehicle()
    v.params.set("SIM_GPS_DISABLE", 1)
    v.run_until(v.time_s + 0.2)
    assert v.mode.number == ModeNumber.STABILIZE
    assert prearm_failure(v) is None and v.arm() == Result.ACCEPTED


def test_arming_check_0_and_force_skip_the_checks_but_not_the_mode_rule():
    v = ready_vehicle()
    v.params.set("SIM_GPS_DISABLE", 1)
    v.run_until(v.time_s + 0.2)
    v.params.set("ARMING_CHECK", 0)
    assert prearm_failure(v) is None
    v.params.set("ARMING_CHECK", 1)
    assert arm_refusal(v, force=True) is None
    v.mode = v.modes[ModeNumber.LAND]
    assert arm_refusal(v, force=True) == "Arm: LAND mode not armable"


def test_a_manual_throttle_mode_refuses_to_arm_with_the_stick_up():
    v = ready_vehicle()
    assert v.mode.number == ModeNumber.STABILIZE
    v.rc.hold_sticks(0.0, 0.0, 0.0, 0.6, v.time_s)
    assert arm_refusal(v, force=False) == "Arm: Throttle too high"
    v.rc.hold_sticks(0.0, 0.0, 0.0, 0.0, v.time_s)
    assert v.arm() == Result.ACCEPTED and v.armed


def test_auto_armed_is_set_by_takeoff_and_cleared_by_disarm():
    v = ready_vehicle()
    assert v.set_mode(ModeNumber.GUIDED) == Result.ACCEPTED and v.arm() == Result.ACCEPTED
    assert not v.arming.auto_armed
    assert v.takeoff(5.0) == Result.ACCEPTED and v.arming.auto_armed
    assert v.disarm(force=True) == Result.ACCEPTED and not v.arming.auto_armed

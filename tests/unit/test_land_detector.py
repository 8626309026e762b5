"""The land detector and auto-disarm (safety/land_detector.py) on hand-made states."""
from __future__ import annotations

from firefly.autopilot.safety.land_detector import LAND_DETECT_S, MOTOR_WIND_DOWN_S, AutoDisarm, LandDetector
from firefly.sim.rigid_body import BodyState

WEIGHT = 15.0
STILL_LOW = BodyState(d_m=-0.05)


def test_it_leaves_the_ground_only_when_armed_and_rising_or_climbing():
    detector = LandDetector(WEIGHT)
    assert detector.landed
    detector.update(BodyState(d_m=-1.0), False, 0.0, 0.0, 0.0)
    assert detector.landed  # disarmed: a vehicle carried up is still "landed"
    detector.update(BodyState(d_m=-0.1, vd_m_s=-0.1), True, 0.0, WEIGHT, 0.0)
    assert detector.landed  # 10 cm and slow: not yet
    detector.update(BodyState(d_m=-0.1, vd_m_s=-0.5), True, 0.0, WEIGHT, 0.0)
    assert not detector.landed


def test_it_lands_after_the_wind_down_and_a_second_of_low_thrust_and_stillness():
    detector = LandDetector(WEIGHT)
    detector.update(BodyState(d_m=-2.0), True, 0.0, WEIGHT, 0.0)
    assert not detector.landed
    t, just_landed = 0.0, []
    while t < MOTOR_WIND_DOWN_S + LAND_DETECT_S + 0.05:
        just_landed.append(detector.update(STILL_LOW, True, 0.0, 0.5 * WEIGHT, t))
        t += 0.01
    assert detector.landed and just_landed.count(True) == 1 and just_landed[-1] is False
    assert just_landed.index(True) >= round((MOTOR_WIND_DOWN_S + LAND_DETECT_S) / 0.01)


def test_thrust_or_motion_restarts_the_landing_count():
    detector = LandDetector(WEIGHT)
    detector.update(BodyState(d_m=-2.0), True, 0.0, WEIGHT, 0.0)
    detector.update(STILL_LOW, True, 0.0, 0.5 * WEIGHT, 0.0)
    detector.update(STILL_LOW, True, 0.0, WEIGHT, 0.5)  # carrying its weight again
    assert not detector.update(STILL_LOW, True, 0.0, 0.5 * WEIGHT, 1.2)
    assert not detector.landed


def test_disarming_in_the_air_counts_as_landed():
    detector = LandDetector(WEIGHT)
    detector.update(BodyState(d_m=-2.0), True, 0.0, WEIGHT, 0.0)
    detector.update(BodyState(d_m=-2.0), False, 0.0, 0.0, 0.1)
    assert detector.landed


def test_auto_disarm_waits_the_delay_landed_and_not_climbing():
    disarm = AutoDisarm()
    disarm.restart(0.0)
    assert not disarm.due(True, True, False, 10.0, 9.9)
    assert disarm.due(True, True, False, 10.0, 10.0)
    assert not disarm.due(True, True, False, 0.0, 100.0)  # DISARM_DELAY 0: never
    assert not disarm.due(False, True, False, 10.0, 100.0)  # already disarmed


def test_a_climb_request_or_leaving_the_ground_restarts_the_count():
    disarm = AutoDisarm()
    disarm.restart(0.0)
    assert not disarm.due(True, True, True, 10.0, 9.0)
    assert not disarm.due(True, True, False, 10.0, 15.0)  # counting again from 15 s
    assert disarm.due(True, True, False, 10.0, 25.0)
    disarm.cancel()
    assert not disarm.due(True, True, False, 10.0, 30.0)

"""DO_CHANGE_SPEED while a leg is flown: the leg changes speed as ArduCopter's S-curve does
(SCurve::set_speed_max): a long leg slows where it cruises; a short leg already accelerating, with
no cruise to change in, keeps its plan (ArduCopter SITL: 4.3 m/s mid-leg on the 20 m leg after a
3 m/s DO_CHANGE_SPEED, tests/parity/recorded/surface_mission.json)."""
from __future__ import annotations

import math

from firefly.autopilot.control.scurve import SCurve
from firefly.autopilot.mission import MissionItem
from firefly.autopilot.results import Result

from ._util import ready_vehicle
from .test_auto import takeoff, wp_at

REL = 3


def speed(v) -> float:
    return math.hypot(v.body.vn_m_s, v.body.ve_m_s)


def test_a_cruising_leg_slows_to_the_new_speed_and_still_ends_at_its_point():
    leg = SCurve((0.0, 0.0, 0.0), (100.0, 0.0, 0.0), 10.0, 2.5, 1.5, 2.5, 1.0, 1.0)
    t = leg.accel_end + 0.5
    s_before = leg.along(t)[0]
    leg.set_speed_max(3.0, 2.5, 1.5, t, 0.15)
    assert leg.along(t)[0] == s_before  # nothing flown changes
    slowest = leg.along(leg.decel_start - 0.1)[1]
    assert 3.0 < slowest < 9.9  # part of the way: half the 3 s of cruise left is no room for 3 m/s
    long_leg = SCurve((0.0, 0.0, 0.0), (300.0, 0.0, 0.0), 10.0, 2.5, 1.5, 2.5, 1.0, 1.0)
    long_leg.set_speed_max(3.0, 2.5, 1.5, long_leg.accel_end + 1.0, 0.15)
    assert abs(long_leg.along(long_leg.decel_start - 0.1)[1] - 3.0) < 1e-6
    assert long_leg.along(long_leg.duration)[0] == 300.0
    assert leg.along(leg.duration)[0] == leg.length and abs(leg.along(leg.duration - 1e-3)[1]) < 0.01


def test_a_short_leg_with_no_cruise_keeps_its_plan():
    leg = SCurve((0.0, 0.0, 0.0), (0.0, 20.0, 0.0), 10.0, 2.5, 1.5, 2.5, 1.0, 1.0)
    duration, peak = leg.duration, leg.along(leg.duration / 2)[1]
    leg.set_speed_max(3.0, 2.5, 1.5, 1.0, 0.15)
    assert leg.duration == duration and leg.along(leg.duration / 2)[1] == peak


def test_change_speed_mid_leg_in_auto_slows_a_long_leg():
    v = ready_vehicle()
    v.mission.replace(0, [takeoff(), wp_at(v, 0, 1), wp_at(v, 150, 1), MissionItem(21, REL)])
    v.set_mode(4)
    assert v.arm() == Result.ACCEPTED
    v.mission_start()
    while v.body.n_m < 40.0 and v.time_s < 60.0:
        v.run_until(v.time_s + 0.2)
    assert speed(v) > 8.0  # cruising at WPNAV_SPEED
    assert v.set_speed(3.0) == Result.ACCEPTED
    v.run_until(v.time_s + 8.0)
    assert abs(speed(v) - 3.0) < 0.3 and v.body.n_m < 120.0


def test_change_speed_item_keeps_the_short_leg_begun_at_its_corner():
    v = ready_vehicle()
    v.mission.replace(0, [takeoff(), wp_at(v, 20, 0), MissionItem(178, REL, p1=1, p2=3, p3=-1),
                          wp_at(v, 20, 20), MissionItem(21, REL)])
    v.set_mode(4)
    v.arm()
    v.mission_start()
    mid: list[float] = []
    while v.armed and v.time_s < 80.0 and v.body.e_m < 18.0:
        v.run_until(v.time_s + 0.1)
        if 8.0 <= v.body.e_m <= 12.0 and v.body.n_m > 15.0:
            mid.append(speed(v))
    assert mid and abs(sum(mid) / len(mid) - 4.3) < 0.8  # ArduCopter's 4.3, not the new 3

"""Where a spline meets a straight leg: a plain waypoint before NAV_SPLINE_WAYPOINT is passed at
the speed the curve can start with, and a straight leg after a spline flown through starts at the
speed the curve ends with, as ArduCopter's AC_WPNav joins its S-curves and splines. Flown by the
real vehicle model in process; the figures are ArduCopter 4.7 SITL's (tests/parity/recorded/
mission_navgeo.json, probe wp_spline)."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.control.scurve import SCurve

from ._util import fly_until, hovering_vehicle
from .test_auto_items_navgeo import SPLINE, WAYPOINT, item_at


def leg(length: float) -> SCurve:
    return SCurve((0.0, 0.0, 0.0), (length, 0.0, 0.0), 10.0, 2.5, 1.5, 2.5, 1.0, 1.0)


def samples(c: SCurve, dt: float = 0.001) -> list[tuple[float, float, float]]:
    n = int(c.duration / dt) + 2
    return [c.along(i * dt) for i in range(n)]


def test_a_leg_ending_at_speed_keeps_its_start_and_reaches_its_end_at_that_speed():
    at_rest, passing = leg(20.0), leg(20.0)
    passing.set_destination_speed(3.0)
    assert passing.along(passing.duration) == (pytest.approx(20.0), 3.0, 0.0)
    assert passing.along(passing.duration - 1e-4)[1] == pytest.approx(3.0, abs=1e-3)
    assert passing.duration < at_rest.duration
    # the start (up to the cruise) is the same plan
    assert passing.along(1.0) == pytest.approx(at_rest.along(1.0))
    # speed never above the cruise, distance never beyond the end, acceleration continuous
    run = samples(passing)
    assert max(v for _, v, _ in run) <= passing.peak + 1e-9
    assert max(s for s, _, _ in run) <= 20.0 + 1e-9
    assert max(abs(a1 - a0) for (_, _, a0), (_, _, a1) in zip(run, run[1:])) < 0.01


def test_a_leg_starting_at_speed_starts_there_and_stops_at_its_end():
    c = leg(14.0)
    assert c.set_origin_speed(2.0) == 2.0
    assert c.along(0.0)[1] == 2.0 and c.along(1e-4)[1] == pytest.approx(2.0, abs=1e-3)
    assert c.along(c.duration) == (pytest.approx(14.0), 0.0, 0.0)
    assert abs(c.along(c.duration - 1e-4)[1]) < 1e-3
    # never faster than the speed it cruises at from rest
    short = leg(2.0)
    assert short.set_origin_speed(50.0) == pytest.approx(short.peak)
    assert leg(0.0).set_origin_speed(3.0) == 0.0


def test_a_waypoint_before_a_spline_is_passed_at_the_curves_speed():
    """ArduCopter: the waypoint 20 m north passed at 3.5 m/s, 7.5 s after its leg began; the
    spline to (30, 10) then takes 5.5 s, the waypoint back to (20, 20) 6.6 s."""
    v = hovering_vehicle()
    v.mission.replace(0, [item_at(v, WAYPOINT, 20, 0), item_at(v, SPLINE, 30, 10), item_at(v, WAYPOINT, 20, 20)])
    v.set_mode(3)
    start = v.time_s
    slowest = math.inf
    while 1 not in v.mission_progress.reached or math.hypot(v.body.n_m - 20.0, v.body.e_m) < 3.0:
        assert v.time_s - start < 20.0
        v.run_until(v.time_s + 0.05)
        if math.hypot(v.body.n_m - 20.0, v.body.e_m) < 3.0:
            slowest = min(slowest, math.hypot(v.body.vn_m_s, v.body.ve_m_s))
    assert 2.7 < slowest < 4.3
    assert fly_until(v, lambda x: 2 in x.mission_progress.reached, 10.0)
    assert fly_until(v, lambda x: 3 in x.mission_progress.reached, 12.0)
    assert 17.0 < v.time_s - start < 22.0  # ArduCopter 19.6 s; stopping at each point: 23.9 s


def test_a_leg_after_a_spline_flown_through_starts_moving():
    """ArduCopter leaves the spline's end at about 2 m/s straight onto the next leg, never
    slower than 1.9 m/s on the way, rather than braking where the curve ends."""
    v = hovering_vehicle()
    v.mission.replace(0, [item_at(v, SPLINE, 10, 10), item_at(v, WAYPOINT, 0, 20)])
    v.set_mode(3)
    assert fly_until(v, lambda x: 1 in x.mission_progress.reached, 15.0)
    slowest = math.inf
    while math.hypot(v.body.n_m - 10.0, v.body.e_m - 10.0) < 5.0:
        v.run_until(v.time_s + 0.05)
        slowest = min(slowest, math.hypot(v.body.vn_m_s, v.body.ve_m_s))
    assert slowest > 1.8  # stopping where the curve ends dips to 1.5
    assert fly_until(v, lambda x: 2 in x.mission_progress.reached, 12.0)


def test_a_waypoint_with_a_hold_before_a_spline_stops_and_the_curve_starts_from_rest():
    v = hovering_vehicle()
    v.mission.replace(0, [item_at(v, WAYPOINT, 15, 0, p1=1.0), item_at(v, SPLINE, 25, 10),
                          item_at(v, WAYPOINT, 15, 20)])
    v.set_mode(3)
    assert fly_until(v, lambda x: 1 in x.mission_progress.reached, 20.0)
    assert math.hypot(v.body.vn_m_s, v.body.ve_m_s) < 0.3
    assert fly_until(v, lambda x: 3 in x.mission_progress.reached, 30.0)

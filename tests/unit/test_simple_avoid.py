"""Simple avoidance against the geofence (safety/simple_avoid.py, AC_Avoid): the rules between the
flights the parity area `avoid` compares with ArduCopter."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.mission.store import MissionItem
from firefly.autopilot.modes import ModeNumber
from firefly.autopilot.params import ParamStore
from firefly.autopilot.safety.fence_shapes import Shape
from firefly.autopilot.safety.simple_avoid import FenceGeometry, Quadrants, SimpleAvoid

from ._util import altitude, hovering_vehicle

CIRCLE, POLYGON, ALT_MAX = 2, 4, 1
SQUARE = Shape("poly", True, ((-30.0, -30.0), (-30.0, 30.0), (30.0, 30.0), (30.0, -30.0)), (0.0, 0.0, 0.0))


def geometry(position, fences, shapes=(), height=10.0, **params) -> tuple[FenceGeometry, ParamStore]:
    store = ParamStore()
    for name, value in params.items():
        store.set(name, value)
    return FenceGeometry(position, (0.0, 0.0), height, fences, shapes, store), store


def test_pushes_the_same_way_count_once_and_opposite_ones_add_up():
    q = Quadrants()
    q.add(1.0, 0.0)  # along an axis: kept (ArduCopter drops it; see Quadrants)
    assert q.total() == (1.0, 0.0)
    q.add(1.0, 0.5)
    q.add(0.5, 1.0)  # the same quadrant: the larger of each component
    q.add(-1.0, -0.25)  # the opposite one adds up
    assert q.total() == (0.0, 0.75)


def test_the_circle_fence_lets_a_slow_move_through_and_cuts_a_fast_one():
    g, params = geometry((30.0, 0.001), CIRCLE, FENCE_RADIUS=40)
    avoid = SimpleAvoid(params)
    slow = avoid.adjust_velocity(g, (1.0, 0.0, 0.0), 1.0, 5.0, 1.0, 2.5, 0.0, 0.01)
    assert slow == (1.0, 0.0, 0.0)
    fast = avoid.adjust_velocity(g, (10.0, 0.0, 0.0), 1.0, 5.0, 1.0, 2.5, 1.0, 0.01)
    # cut, but no faster than AVOID_ACCEL_MAX from the wanted velocity in one tick
    assert 10.0 - 3.0 * 0.01 - 1e-9 <= fast[0] < 10.0
    for i in range(300):
        fast = avoid.adjust_velocity(g, (10.0, 0.0, 0.0), 1.0, 5.0, 1.0, 2.5, 1.0 + i * 0.01, 0.01)
    # 8 m to the safe radius at 1 m/s/s past the linear region: sqrt(2 * (8 - 0.5))
    assert fast[0] == pytest.approx(math.sqrt(2.0 * 7.5), abs=0.01)


def test_sliding_keeps_the_move_along_a_polygon_edge_and_stopping_does_not():
    g, params = geometry((27.0, 0.0), POLYGON, (SQUARE,))
    slide = SimpleAvoid(params).adjust_velocity(g, (3.0, 3.0, 0.0), 1.0, 5.0, 1.0, 2.5, 0.0, 0.0)
    assert slide == pytest.approx((1.0, 3.0, 0.0))  # 1 m to the margin, p * 1 m
    params.set("AVOID_BEHAVE", 1)
    stop = SimpleAvoid(params).adjust_velocity(g, (3.0, 3.0, 0.0), 1.0, 5.0, 1.0, 2.5, 0.0, 0.0)
    assert stop[0] == pytest.approx(stop[1]) and stop[0] < 3.0  # the same direction, slower


def test_inside_the_margin_a_still_vehicle_is_pushed_back_at_most_at_the_backup_speed():
    g, params = geometry((29.5, 0.5), POLYGON, (SQUARE,))
    avoid = SimpleAvoid(params)
    vel = (0.0, 0.0, 0.0)
    for i in range(100):
        vel = avoid.adjust_velocity(g, (0.0, 0.0, 0.0), 1.0, 5.0, 1.0, 2.5, i * 0.01, 0.01)
    assert -0.75 - 1e-9 <= vel[0] < -0.3 and abs(vel[1]) < 1e-3


def test_an_exclusion_circle_is_kept_outside_of():
    hole = Shape("circle", False, (), (20.0, 0.0, 10.0))
    g, params = geometry((5.0, 0.001), POLYGON, (hole,))
    vel = SimpleAvoid(params).adjust_velocity(g, (10.0, 0.0, 0.0), 1.0, 5.0, 1.0, 2.5, 0.0, 0.0)
    assert vel[0] < 10.0


def test_the_climb_stops_short_of_the_ceiling_and_backs_off_above_it():
    g, params = geometry((0.0, 0.0), ALT_MAX, height=17.0, FENCE_ALT_MAX=20)
    avoid = SimpleAvoid(params)
    climb, back = avoid.adjust_climb(g, 2.5, 1.0, 2.5, 0.01)
    assert climb == pytest.approx(1.0) and back == 0.0  # 1 m to go, linear region: p * 1 m
    g, _ = geometry((0.0, 0.0), ALT_MAX, height=19.0, FENCE_ALT_MAX=20)
    climb, back = avoid.adjust_climb(g, 2.5, 1.0, 2.5, 0.01)
    assert climb == 0.0 and back == pytest.approx(-0.75)  # 1 m above the safe ceiling: AVOID_BACKZ_SPD
    assert avoid.adjust_climb(g, 0.0, 1.0, 2.5, 0.01) == (0.0, 0.0)  # a still stick: nothing


def test_avoidance_off_changes_nothing():
    g, params = geometry((37.0, 0.0), CIRCLE | ALT_MAX, height=19.0, FENCE_RADIUS=40, AVOID_ENABLE=0)
    assert SimpleAvoid(params).adjust_velocity(g, (5.0, 0.0, 2.0), 1.0, 5.0, 1.0, 2.5, 0.0, 0.01) == (5.0, 0.0, 2.0)


# ----- flown ---------------------------------------------------------------------------------------
def fenced(**params):
    v = hovering_vehicle(10.0)
    for name, value in {"FENCE_ACTION": 0, "RC_OVERRIDE_TIME": -1, **params, "FENCE_ENABLE": 1}.items():
        v.params.set(name, value)
    v.fence.follow_param(v.params)
    return v


def distance_from_home(v) -> float:
    return math.hypot(v.body.n_m - v.home_ned[0], v.body.e_m - v.home_ned[1])


def most_over(v, measure, seconds: int) -> float:
    """The largest `measure(v)` seen once a second for `seconds` of flight."""
    most = -math.inf
    for _ in range(seconds):
        v.run_until(v.time_s + 1.0)
        most = max(most, measure(v))
    return most


@pytest.mark.parametrize("avoid_enable", [3, 0])
def test_loiter_with_the_stick_held_stops_inside_the_circle_fence_unless_avoidance_is_off(avoid_enable):
    v = fenced(FENCE_TYPE=CIRCLE, FENCE_RADIUS=40, AVOID_ENABLE=avoid_enable)
    assert v.set_mode(ModeNumber.LOITER) == 0
    v.rc.hold_sticks(0.0, 1.0, 0.0, 0.5, v.time_s)
    farthest = most_over(v, distance_from_home, 25)
    if avoid_enable:
        assert 37.0 < farthest < 38.6 and not v.failsafes.fence.breaches
    else:
        assert farthest > 60.0 and v.failsafes.fence.breaches


def test_a_loiter_climb_stops_short_of_the_altitude_fence():
    v = fenced(FENCE_TYPE=ALT_MAX, FENCE_ALT_MAX=20)
    assert v.set_mode(ModeNumber.LOITER) == 0
    v.rc.hold_sticks(0.0, 0.0, 0.0, 1.0, v.time_s)
    top = most_over(v, altitude, 15)
    assert 17.5 < top < 18.2


def test_a_guided_velocity_toward_a_polygon_edge_stops_at_the_margin():
    v = fenced(FENCE_TYPE=POLYGON)
    lat0, lon0 = v.origin.lat_deg, v.origin.lon_deg
    m = 1.0 / 111319.5
    corners = [(-30, -30), (-30, 30), (30, 30), (30, -30)]
    items = [MissionItem(5001, 0, p1=4, x=round((lat0 + n * m) * 1e7),
                         y=round((lon0 + e * m / math.cos(math.radians(lat0))) * 1e7))
             for n, e in corners]
    v.mission.replace(1, items)
    v.fence.follow_param(v.params)
    assert v.fence.enabled_fences & POLYGON
    north = -100.0
    for _ in range(25):
        v.guided_velocity(3.0, 0.0, 0.0)
        v.run_until(v.time_s + 1.0)
        north = max(north, v.body.n_m)
    assert 27.0 < north < 29.0 and not v.failsafes.fence.breaches  # ArduCopter: 28.9 (parity avoid)


def test_loiter_holding_inside_the_circle_margin_backs_out_to_it():
    v = fenced(FENCE_TYPE=CIRCLE, FENCE_RADIUS=40)
    v.params.set("FENCE_ENABLE", 0)
    v.fence.follow_param(v.params)
    v.guided_goto(39.3, 0.0, v.body.d_m)
    v.run_until(v.time_s + 15.0)
    v.params.set("FENCE_ENABLE", 1)
    v.fence.follow_param(v.params)
    assert v.set_mode(ModeNumber.LOITER) == 0
    v.rc.hold_sticks(0.0, 0.0, 0.0, 0.5, v.time_s)
    start = distance_from_home(v)
    v.run_until(v.time_s + 10.0)
    assert start > 39.0 and 37.3 < distance_from_home(v) < 38.2

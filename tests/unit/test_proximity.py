"""The proximity sensor (proximity.py) and what uses it: its DISTANCE_SENSOR messages, the pre-arm
check and simple avoidance. ArduCopter's answers are in the parity area proximity; these pin the
rules between them."""
from __future__ import annotations

import math

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.mavlink.rangefinder_messages import proximity_sensors
from firefly.autopilot.mavlink.session import Session
from firefly.autopilot.modes import ModeNumber
from firefly.autopilot.params import ParamStore
from firefly.autopilot.proximity import MAVLINK, SITL, Proximity, sector_of
from firefly.autopilot.results import Result
from firefly.autopilot.safety.arming import prearm_failures
from firefly.autopilot.safety.simple_avoid import FenceGeometry, SimpleAvoid

from ..fuzz.checks import vehicle_problems
from ._util import client_codec, ready_vehicle, wire


def sensor(kind: int, **params) -> Proximity:
    store = ParamStore()
    store.set("PRX1_TYPE", kind)
    for name, value in params.items():
        store.set(name, value)
    return Proximity(store)


def square_30(north: float, east: float):
    """SITL's lidar test: outside a +-30 m square, seen from (north, east)."""
    return lambda dn, de: abs(north + dn) > 30.0 or abs(east + de) > 30.0


def test_sectors_are_45_degrees_centred_ahead_and_clockwise():
    assert [sector_of(a) for a in (0.0, 22.4, 22.6, 90.0, 200.0, 337.6, -10.0)] == [0, 0, 1, 2, 4, 0, 0]


def test_sitl_lidar_measures_the_inclusion_fence_in_each_sector_and_the_room_above():
    prox = sensor(SITL)
    prox.update(1.0, 0.0, square_30(10.0, 0.0), False, 10.0)
    assert not prox.good and prox.upward_m == pytest.approx(90.0)  # no inclusion fence: no data
    prox.update(1.1, 0.0, square_30(10.0, 0.0), True, 10.0)
    assert prox.good
    want = [20.0, 20.0 * math.sqrt(2), 30.0, 30.0 * math.sqrt(2), 40.0, 30.0 * math.sqrt(2), 30.0, 20.0 * math.sqrt(2)]
    for got, expected in zip(prox.distance, want):
        assert expected - 0.1 < got <= expected  # halved down to 0.1 m, from below
    prox.update(1.2, math.radians(90.0), square_30(10.0, 0.0), True, 10.0)  # turned east: ahead is 30 m
    assert prox.distance[0] == pytest.approx(30.0, abs=0.1)


def test_distance_sensor_messages_go_out_per_sector_ever_heard_then_upward():
    prox = sensor(MAVLINK)
    distances = [3001] * 72
    for j in (0, 1, 2, 69, 70, 71):  # a wall ahead, 20 m
        distances[j] = 2000
    prox.obstacle_distance(distances, 5.0, 0.0, 20, 3000, 1.0)
    prox.update(1.0, 0.0, lambda dn, de: False, False, 10.0)
    msgs = proximity_sensors(prox, 1000, client_codec())
    assert [(m.id, m.orientation, m.min_distance, m.max_distance, m.current_distance) for m in msgs] == \
        [(10, 0, 19, 3000, 2000)]  # ArduPilot's float32 centimetres: 20 cm reads 19
    prox.update(2.5, 0.0, lambda dn, de: False, False, 10.0)  # silent past the timeouts
    assert not prox.good and proximity_sensors(prox, 2500, client_codec()) == []


def test_a_reading_of_zero_or_out_of_the_messages_limits_is_none():
    prox = sensor(MAVLINK)
    prox.obstacle_distance([0, 65535, 10, 3001] + [3001] * 68, 5.0, 0.0, 20, 3000, 1.0)
    assert not any(prox.valid)
    prox.obstacle_distance([500] * 72, math.nan, 0.0, 20, 3000, 1.1)  # no usable increment: ignored
    assert not any(prox.valid)


def test_the_boundary_has_an_obstacle_ahead_and_one_each_side_of_a_lone_reading():
    prox = sensor(MAVLINK)
    prox.distance_sensor(0, 1000, 20, 2000, 1.0)
    obstacles = sorted(prox.obstacles(), key=lambda p: p[1])
    ahead = 10.0 * math.cos(math.radians(22.5))
    assert obstacles[1] == pytest.approx((ahead, 0.0))
    assert obstacles[0][1] < 0.0 < obstacles[2][1]  # the cup around the reading


def test_avoidance_cuts_a_move_toward_an_obstacle_and_backs_out_of_the_margin():
    params = ParamStore()
    avoid = SimpleAvoid(params)
    far = FenceGeometry((0.0, 0.0), (0.0, 0.0), 10.0, 0, (), params, [(5.0, 0.0)], 0.0)
    vn, ve, _ = avoid.adjust_velocity(far, (5.0, 1.0, 0.0), 1.0, 5.0, 1.0, 2.5, 0.0, 0.0)
    assert vn == pytest.approx(math.sqrt(2.0 * (3.0 - 0.5))) and ve == 1.0  # 3 m left to the margin
    turned = FenceGeometry((0.0, 0.0), (0.0, 0.0), 10.0, 0, (), params, [(5.0, 0.0)], math.pi / 2)
    vn, ve, _ = avoid.adjust_velocity(turned, (5.0, 1.0, 0.0), 1.0, 5.0, 1.0, 2.5, 1.0, 0.0)
    assert vn == 5.0 and ve == pytest.approx(1.0)  # facing east: the obstacle is east, north is free
    near = FenceGeometry((0.0, 0.0), (0.0, 0.0), 10.0, 0, (), params, [(1.0, 0.0)], 0.0)
    vel = (0.0, 0.0, 0.0)
    for i in range(100):
        vel = avoid.adjust_velocity(near, (0.0, 0.0, 0.0), 1.0, 5.0, 1.0, 2.5, 2.0 + i * 0.01, 0.01)
    assert vel[0] == pytest.approx(-0.75)  # at AVOID_BACKUP_SPD


def test_alt_hold_leans_away_from_a_near_obstacle_within_its_share_of_the_limit():
    params = ParamStore()
    avoid = SimpleAvoid(params)
    roll, pitch = avoid.adjust_lean([(0.0, 3.0)], (0.0, 0.0), math.radians(30.0))
    assert roll == 0.0 and pitch == pytest.approx(math.radians(10.0))  # nose up, at AVOID_ANGLE_MAX
    assert avoid.adjust_lean([(90.0, 6.0)], (0.1, 0.2), math.radians(30.0)) == (0.1, 0.2)  # past AVOID_DIST_MAX


def test_arming_wants_data_and_nothing_within_60_cm():
    v = ready_vehicle({"PRX1_TYPE": 2})
    assert "PRX1: No Data" in prearm_failures(v)
    v.proximity.distance_sensor(0, 50, 20, 2000, v.time_s)
    v.run_until(v.time_s + 0.2)
    v.proximity.distance_sensor(0, 50, 20, 2000, v.time_s)
    assert "Proximity 0 deg, 0.50m (want > 0.6m)" in prearm_failures(v)
    v.proximity.distance_sensor(0, 500, 20, 2000, v.time_s)
    assert not any("roximity" in f or "PRX1" in f for f in prearm_failures(v))


def test_obstacle_distance_3d_points_reach_the_boundary_a_batch_at_a_time():
    prox = sensor(MAVLINK)
    prox.obstacle_3d(100, 12, (5.0, 0.0, 0.0), 0.2, 30.0, 1.00)
    prox.obstacle_3d(100, 12, (4.0, 0.0, 0.0), 0.2, 30.0, 1.01)  # the nearer of a sector's points
    prox.obstacle_3d(100, 12, (5.0, 5.0 * math.tan(math.radians(30.0)), 0.0), 0.2, 30.0, 1.02)
    prox.obstacle_3d(100, 12, (3.0, 0.0, -3.0), 0.2, 30.0, 1.03)  # 45 degrees up: not the middle layer
    assert prox.good and not any(prox.valid)  # the batch waits for the next stamp
    prox.obstacle_3d(200, 12, (9.0, 0.0, 0.0), 0.2, 30.0, 1.1)
    assert prox.valid[0] and prox.distance[0] == pytest.approx(4.0)
    assert prox.valid[1] and prox.angle[1] == pytest.approx(30.0) and not prox.valid[7]
    prox.obstacle_3d(200, 1, (2.0, 0.0, 0.0), 0.2, 30.0, 1.2)  # MAV_FRAME_LOCAL_NED: heard, dropped
    prox.obstacle_3d(200, 12, (50.0, 0.0, 0.0), 0.2, 30.0, 1.3)  # out of the sensor's range
    prox.obstacle_3d(200, 12, (math.nan, 0.0, 0.0), 0.2, 30.0, 1.31)
    prox.obstacle_3d(201, 12, (6.0, 0.0, 0.0), 0.2, 30.0, 1.4)  # a new stamp commits 9 m
    assert prox.distance[0] == pytest.approx(9.0)
    prox.update(1.85, 0.0, lambda dn, de: False, False, 10.0)
    assert prox.good  # heard within 0.5 s, whatever the frame
    prox.update(1.95, 0.0, lambda dn, de: False, False, 10.0)
    assert not prox.good


def test_obstacle_distance_3d_is_ignored_without_a_companion_sensor():
    prox = sensor(SITL)
    prox.obstacle_3d(100, 12, (5.0, 0.0, 0.0), 0.2, 30.0, 1.0)
    prox.obstacle_3d(200, 12, (5.0, 0.0, 0.0), 0.2, 30.0, 1.1)
    assert not any(prox.valid) and not prox.good


F32 = st.floats(width=32) | st.sampled_from([0.0, -1.0, 1e30, math.inf, -math.inf, math.nan, 0.2, 30.0])
OBSTACLES_3D = st.builds(lambda ts, fr, x, y, z, lo, hi: CODEC.obstacle_distance_3d_encode(ts, 0, fr, 0, x, y, z, lo, hi),
                         st.sampled_from([0, 1, 100, 2**32 - 1]), st.sampled_from([12, 1, 8, 255]), F32, F32, F32, F32,
                         F32)
CODEC = client_codec()


@settings(max_examples=40, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(OBSTACLES_3D, st.sampled_from([0, 4, 40])), min_size=1, max_size=12))
def test_hostile_obstacles_3d_to_a_hovering_companion_sensor_leave_it_valid(sequence):
    """PRX1_TYPE 2 in a LOITER hover, sent OBSTACLE_DISTANCE_3D with any numbers (NaN, infinite or
    negative limits and points, other frames): nothing raises, the DISTANCE_SENSOR messages still
    go out, the vehicle stays valid."""
    v = ready_vehicle({"PRX1_TYPE": 2, "AVOID_ENABLE": 2})
    session = Session(v, new_codec(1))
    session.receive(wire(CODEC.obstacle_distance_3d_encode(1, 0, 12, 0, 10.0, 0.0, 0.0, 0.2, 30.0)), v.time_s)
    assert v.set_mode(ModeNumber.GUIDED) == Result.ACCEPTED and v.arm() == Result.ACCEPTED
    assert v.takeoff(5.0) == Result.ACCEPTED
    v.run_until(v.time_s + 3.0)
    for msg, steps in sequence:
        session.receive(wire(msg), v.time_s)
        v.run_until(v.time_s + steps / 400.0)
        session.poll(v.time_s, 0.0)
        assert not vehicle_problems(v, session), vehicle_problems(v, session)
    for sensor in proximity_sensors(v.proximity, 0, CODEC):  # the builder that raised on a NaN range
        assert 0 <= sensor.min_distance <= sensor.max_distance <= 65535

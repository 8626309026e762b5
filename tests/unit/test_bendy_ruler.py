"""BendyRuler (OA_TYPE 1, path_planning/bendy_ruler.py): its margins from the fence, its search,
its answers to the waypoint legs, and legs flown round a fence by AUTO (the figures measured on
ArduCopter SITL are in the parity area `oa_bendy`)."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.mission import MissionItem
from firefly.autopilot.mission.store import FENCE
from firefly.autopilot.path_planning.bendy_ruler import (BendyRuler, FenceView, Settings, bearing_deg,
                                                         polygon_line_distance)
from firefly.autopilot.params import ParamStore
from firefly.autopilot.path_planning.obstacle_database import Obstacle, ObstacleDatabase
from firefly.autopilot.path_planning.planner import NOT_REQUIRED, PROCESSING, SUCCESS
from firefly.autopilot.modes.position_target import PositionTarget, kinematic_limit
from firefly.autopilot.results import Result

from ._util import altitude, fly_until, ready_vehicle
from .test_path_planning import EXCLUSION_CIRCLE, REL, circle, item_at, planner, poly, square

POLYGON_AND_CIRCLE = 2 | 4  # FENCE_TYPE bits BendyRuler reads
DEFAULTS = Settings(lookahead=15.0, ratio=1.5, angle=75.0, margin_max=5.0)


def view(*shapes, fences=POLYGON_AND_CIRCLE, radius=300.0, fence_margin=2.0) -> FenceView:
    return FenceView(tuple(shapes), fences, radius, fence_margin)


# ----- margins ---------------------------------------------------------------------------------
def test_an_exclusion_circle_s_margin_is_the_segment_s_distance_less_radius_and_fence_margin():
    fence = view(circle(50, 0, 10), fences=4)
    assert fence.margin((0, 20), (100, 20)) == pytest.approx(20 - 12)
    assert fence.margin((0, 0), (30, 0)) == pytest.approx(20 - 12)  # the nearer end
    assert fence.margin((0, 0), (100, 0)) == pytest.approx(-12)  # through the centre
    assert view(circle(50, 0, 10), fences=2).margin((0, 0), (100, 0)) == 198  # polygon fence off: home circle only


def test_the_circle_round_home_counts_the_further_end():
    fence = view(fences=2, radius=100.0)
    assert fence.margin((0, 0), (50, 0)) == pytest.approx(100 - 2 - 50)
    assert fence.margin((0, 0), (120, 0)) == pytest.approx(-22)
    assert view(fences=0).margin((0, 0), (500, 0)) == math.inf  # nothing to see


def test_a_segment_across_a_polygon_is_short_by_its_end_s_depth_past_the_crossing():
    sq = square(50, 0, 10)  # south edge at north 40 is the closing one (last vertex to first)
    assert polygon_line_distance(sq, (0, 0), (45, 0)) == pytest.approx(-5)
    assert polygon_line_distance(sq, (0, 0), (100, 0)) == pytest.approx(-60)  # from the crossing nearest the start
    # clear of it: the closing edge is skipped, so ending 1 m short of the south edge's middle counts
    # the distance to its corners and the other edges, not 1 m
    assert polygon_line_distance(sq, (0, 0), (39, 0)) == pytest.approx(math.hypot(1, 10))
    assert polygon_line_distance(sq, (50, -30), (50, -12)) == pytest.approx(2)  # the west edge, not skipped
    fence = view(poly(sq), fences=4)
    assert fence.margin((50, -30), (50, -12)) == pytest.approx(0)  # less FENCE_MARGIN
    inclusion = view(poly(square(0, 0, 50), inclusion=True), fences=4)
    assert inclusion.margin((0, 0), (0, 30)) == pytest.approx(20 - 2)
    assert inclusion.margin((0, 60), (0, 70)) == pytest.approx(-10 - 2)  # outside: negative


def test_bearings_are_rounded_to_centidegrees_as_arducopter_s_locations_give_them():
    assert bearing_deg((0, 0), (10, 0)) == 0.0
    assert bearing_deg((0, 0), (0, -10)) == pytest.approx(270.0)
    assert bearing_deg((0, 0), (100, 1)) == pytest.approx(0.57)  # 0.5729...


# ----- the search ------------------------------------------------------------------------------
def test_a_clear_way_needs_no_avoidance_and_the_look_ahead_grows_from_half():
    br = BendyRuler()
    active, point = br.update((0, 0), (100, 0), (0, 0), 0.0, view(), DEFAULTS)
    assert not active and point == pytest.approx((7.5, 0.0))
    assert br.current_lookahead == pytest.approx(8.25)
    for _ in range(20):
        br.update((0, 0), (100, 0), (0, 0), 0.0, view(), DEFAULTS)
    assert br.current_lookahead == 15.0  # OA_BR_LOOKAHEAD at most


def test_a_circle_on_the_line_is_passed_on_its_left_the_first_side_searched():
    """Measured (auto_circle_centred): round the west side, at most 27 m off the line."""
    br, fence = BendyRuler(), view(circle(50, 0, 10))
    br.current_lookahead = 15.0
    active, point = br.update((30, 0), (100, 0), (5, 0), 0.0, fence, DEFAULTS)
    assert active and point[1] < -5.0
    assert fence.margin((30, 0), point) > 5.0  # step 1 clear by more than OA_MARGIN_MAX


def test_no_clear_bearing_flies_the_best_margin_at_a_shortened_reach():
    br, fence = BendyRuler(), view(circle(0, 0, 30))  # inside an exclusion circle
    active, point = br.update((0, 0), (100, 0), (0, 0), 0.0, fence, DEFAULTS)
    assert active and math.dist((0, 0), point) < 7.5
    assert br.current_lookahead == 7.5  # shrinks, but never below half


def test_a_big_turn_is_resisted_unless_the_margin_is_ratio_times_better():
    br = BendyRuler()
    fence = view(circle(50, 0, 10))
    br.current_lookahead = 15.0
    br.update((30, 0), (100, 0), (5, 0), 0.0, fence, DEFAULTS)  # the first bearing: west of the circle
    first = br.bearing_prev
    assert -90.0 < first < 0.0
    br.bearing_prev = 90.0  # as if it had been heading east: the west bearing turns more than 75
    active, point = br.update((30, 0), (100, 0), (5, 0), 0.0, fence, DEFAULTS)
    # the east bearing's margin (a clear 15 m east) is not 1.5 times worse: kept
    assert active and point == pytest.approx((30.0, 15.0), abs=0.01) and br.bearing_prev == 90.0
    lenient = Settings(15.0, 1.5, 180.0, 5.0)  # OA_BR_CONT_ANGLE 180: never resisted
    br.bearing_prev = 90.0
    active, point = br.update((30, 0), (100, 0), (5, 0), 0.0, fence, lenient)
    assert point[1] < 0 and br.bearing_prev == pytest.approx(first)


# ----- the planner's answers -------------------------------------------------------------------
def test_oa_type_1_answers_points_for_the_position_controller_and_never_a_clear_way_on():
    p, _, said = planner([circle(50, 0, 10)], oa_type=1)
    answers = [p.avoid(k * 0.01, (30.0, 0.0), (100.0, 0.0), (100.0, 40.0), (5.0, 0.0)) for k in range(300)]
    assert {a.state for a in answers} == {PROCESSING, SUCCESS}
    last = answers[-1]
    assert last.bendy and last.destination is not None and last.destination[1] < 0 and not last.dest_to_next_clear
    p, _, _ = planner([circle(50, 40, 10)], oa_type=1)  # out of the way
    last = [p.avoid(k * 0.01, (30.0, 0.0), (100.0, 0.0), None) for k in range(300)][-1]
    assert last.state == NOT_REQUIRED and not last.dest_to_next_clear
    assert said.texts == []  # BendyRuler says nothing


def test_oa_type_3_without_proximity_obstacles_plans_as_dijkstra():
    p, _, _ = planner([circle(50, 4, 10)], oa_type=3)
    last = [p.avoid(k * 0.01, (0.0, 0.0), (100.0, 0.0), None) for k in range(300)][-1]
    assert last.state == SUCCESS and not last.bendy  # measured: the corner (50, -13.3)
    assert last.destination == pytest.approx((50.0, -13.28), abs=0.05)


# ----- flown -----------------------------------------------------------------------------------
def test_auto_bends_round_an_exclusion_circle_and_reaches_its_waypoint():
    """Measured (auto_circle): round the west side, 15.7 m off the line at most, 6.2 m from the
    circle at the closest, the waypoint reached 25.1 s after AUTO was set."""
    v = ready_vehicle({"OA_TYPE": 1, "FENCE_ENABLE": 1})
    v.mission.replace(FENCE, [item_at(v, EXCLUSION_CIRCLE, 50, 4, p1=10)])
    v.mission.replace(0, [MissionItem(22, REL, z=10.0), item_at(v, 16, 100, 0)])
    v.set_mode(4)
    assert v.arm() == Result.ACCEPTED
    assert v.takeoff(10.0) == Result.ACCEPTED
    assert fly_until(v, lambda x: altitude(x) > 9.8, 20.0)
    v.set_mode(3)
    start = v.time_s
    assert v.mission_start() == Result.ACCEPTED
    track = []
    assert fly_until(v, lambda x: track.append((x.body.n_m, x.body.e_m)) or 2 in x.mission_progress.reached, 60.0)
    closest = min(math.dist(p, (50, 4)) for p in track) - 10
    assert closest == pytest.approx(6.2, abs=1.0)
    assert min(e for _, e in track) == pytest.approx(-15.7, abs=1.5)
    assert v.time_s - start == pytest.approx(25.1, abs=3.0)
    assert math.dist(track[-1], (100, 0)) < 1.0 and altitude(v) == pytest.approx(10, abs=0.5)


# ----- the vertical search and the position controller's target --------------------------------
def test_the_vertical_search_climbs_by_the_distance_still_to_go_when_level_is_blocked():
    """Measured (auto_circle_vertical): at 20.9 m north and 10 m up, ArduCopter's point was 88.8 m
    high above the same spot; further out, level on to the destination itself, avoiding (a level
    step 1 clear, step 2 blocked level but clear up)."""
    fence = view(circle(50, 4, 10), fences=POLYGON_AND_CIRCLE | 1)
    br = BendyRuler()
    br.current_lookahead = 13.3
    active, point = br.update_vertical((20.9, 0.0, 10.0), (100.0, 0.0), fence, DEFAULTS)
    assert active and point == pytest.approx((20.9, 0.0, 10.0 + 79.1), abs=0.01)
    br = BendyRuler()
    br.current_lookahead = 12.1
    active, point = br.update_vertical((12.8, 0.0, 10.0), (100.0, 0.0), fence, DEFAULTS)
    assert active and point == pytest.approx((100.0, 0.0, 10.0), abs=0.01)
    active, point = BendyRuler().update_vertical((0.0, 0.0, 10.0), (100.0, 0.0), fence, DEFAULTS)
    assert not active  # level and clear two steps on


def test_the_vertical_search_keeps_below_the_ceiling():
    fence = view(circle(50, 0, 10), fences=1 | 4)
    assert fence.margin_3d((0, 0, 90), (0, 0, 95)) == pytest.approx(100 - 2 - 95)
    br = BendyRuler()
    br.current_lookahead = 15.0
    active, point = br.update_vertical((30.0, 0.0, 90.0), (100.0, 0.0), fence, DEFAULTS)
    assert active and point[2] < 90.0  # up is no way out under the ceiling: down


def test_a_kinematic_limit_is_the_first_limit_reached_along_the_way():
    assert kinematic_limit((1, 0, 0), 10, 2.5, 1.5) == 10
    assert kinematic_limit((0, 0, 1), 10, 2.5, 1.5) == 2.5
    assert kinematic_limit((0, 0, -3), 10, 2.5, 1.5) == 1.5
    assert kinematic_limit((1, 0, 1), 10, 2.5, 1.5) == pytest.approx(2.5 * math.sqrt(2))  # the climb binds
    assert kinematic_limit((10, 0, 1), 10, 2.5, 1.5) == pytest.approx(10 / math.cos(math.atan(0.1)))


def test_the_position_target_runs_to_its_point_and_stops_there():
    target = PositionTarget((0.0, 0.0, 10.0), (5.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    speeds = []
    for _ in range(int(20 / 0.0025)):
        target.run_to((30.0, 0.0, 15.0), 0.0025, (10.0, 2.5, 1.5), 2.5, 5.0, 1.0, 5.0)
        speeds.append(math.hypot(*target.vel_ne))
    assert max(speeds) <= 10.0 + 1e-6
    assert target.pos_ne == pytest.approx((30.0, 0.0), abs=0.05) and target.pos_up == pytest.approx(15.0, abs=0.05)
    assert math.hypot(*target.vel_ne) < 0.05 and abs(target.vel_up) < 0.05


# ----- the obstacle database -------------------------------------------------------------------
def database(**params) -> ObstacleDatabase:
    store = ParamStore()
    for name, value in params.items():
        store.set(name, value)
    return ObstacleDatabase(store)


def test_a_reading_is_a_point_rotated_by_the_attitude_with_a_radius_by_the_beam_width():
    db = database()
    db.push(0.0, (10.0, 0.0, 10.0), (0.0, 0.0, math.radians(90)), 0.0, 20.0, (0.0, 0.0, 0.0))
    (o,) = db.obstacles
    assert o.pos == pytest.approx((10.0, 20.0, 10.0), abs=1e-9)  # facing east: 20 m east
    assert o.radius == pytest.approx(20.0 * math.tan(math.radians(5)))  # OA_DB_BEAM_WIDTH 5
    db.push(0.0, (0.0, 0.0, 10.0), (0.0, math.radians(-30), 0.0), 0.0, 20.0, (0.0, 0.0, 0.0))
    assert db.obstacles[1].pos == pytest.approx((20 * math.cos(math.radians(30)), 0.0, 0.0), abs=1e-9)  # nose down


def test_a_point_near_a_kept_one_refreshes_it_and_old_ones_expire():
    db = database()
    here, level, home = (0.0, 0.0, 10.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
    db.push(0.0, here, level, 0.0, 20.0, home)
    db.push(0.3, here, level, 1.0, 20.0, home)  # 0.35 m away, within the radius: the same
    assert len(db.obstacles) == 1 and db.obstacles[0].time_s == 0.0  # same radius, under 0.5 s: untouched
    db.push(0.6, here, level, 1.0, 20.0, home)
    assert db.obstacles[0].time_s == 0.6 and db.obstacles[0].pos == pytest.approx((20.0, 0.0, 10.0))
    db.push(1.0, here, level, 90.0, 20.0, home)
    db.expire(10.6)  # OA_DB_EXPIRE 10
    assert len(db.obstacles) == 2
    db.expire(10.9)
    assert [o.pos for o in db.obstacles] == [pytest.approx((0.0, 20.0, 10.0))]


def test_the_database_is_limited_and_can_fail_to_be_made():
    db = database(OA_DB_SIZE=2)
    for k in range(5):
        db.push(0.0, (0.0, 0.0, 10.0), (0.0, 0.0, 0.0), 60.0 * k, 20.0, (0.0, 0.0, 0.0))
    assert len(db.obstacles) == 2
    failed = database(OA_DB_QUEUE_SIZE=1, OA_DB_SIZE=0)
    assert not failed.healthy and failed.init_failure == "DB init failed . Sizes queue:1, db:0"
    low = database(OA_DB_ALT_MIN=2)
    low.push(0.0, (1.0, 0.0, 1.5), (0.0, 0.0, 0.0), 0.0, 5.0, (0.0, 0.0, 0.0))  # near home, below 2 m
    far = database(OA_DB_DIST_MAX=5)
    far.push(0.0, (0.0, 0.0, 10.0), (0.0, 0.0, 0.0), 0.0, 8.0, (0.0, 0.0, 0.0))  # 7.3 m to its edge
    assert low.obstacles == [] and far.obstacles == []


def test_bendy_ruler_keeps_its_margin_from_database_obstacles_in_3d():
    obstacle = Obstacle((50.0, 2.0, 10.0), 2.0, 0.0)
    fence = FenceView((), 0, 300.0, 2.0, obstacles=[obstacle], up=10.0)
    assert fence.margin((30.0, 0.0), (60.0, 0.0)) == pytest.approx(0.0)
    below = FenceView((), 0, 300.0, 2.0, obstacles=[Obstacle((50.0, 2.0, 0.0), 2.0, 0.0)], up=10.0)
    assert below.margin((30.0, 0.0), (60.0, 0.0)) == pytest.approx(math.hypot(2, 10) - 2)
    only = FenceView((circle(50, 0, 10),), 4, 300.0, 2.0, obstacles=[], up=10.0, proximity_only=True)
    assert only.margin((0.0, 0.0), (100.0, 0.0)) == math.inf  # OA_TYPE 3's: the fence is Dijkstra's


def test_oa_type_3_bends_round_proximity_obstacles_then_plans_dijkstra_afresh():
    p, store, _ = planner([circle(50, 40, 10)], oa_type=3)
    db = p.database
    assert db is not None
    answers = [p.avoid(k * 0.01, (30.0, 0.0), (100.0, 0.0), None) for k in range(300)]
    assert answers[-1].state == NOT_REQUIRED  # the circle is off the way
    for k in range(20):
        db.push(3.0, (30.0, 0.0, 0.0), (0.0, 0.0, 0.0), -3.0 + 0.3 * k, 12.0, (0.0, 0.0, 0.0))
    answers = [p.avoid(3.0 + k * 0.01, (30.0, 0.0), (100.0, 0.0), None) for k in range(300)]
    assert answers[-1].state == SUCCESS and answers[-1].bendy

"""The path planner round the fence (OA_TYPE 2, path_planning/): its geometry, its answers to the
waypoint legs, and legs flown round a fence by AUTO and GUIDED (the figures measured on ArduCopter
SITL are in the module docs and the parity area `oa`)."""
from __future__ import annotations

import itertools
import math
import random

import pytest

from firefly.autopilot.mission import MissionItem
from firefly.autopilot.mission.store import FENCE
from firefly.autopilot.params import ParamStore
from firefly.autopilot.path_planning.dijkstra import (NO_PATH, OVERLAPPING_POINTS, TOO_MANY_POINTS, FenceGraph,
                                                      PlanError, crosses_fence, fence_corners)
from firefly.autopilot.path_planning.planner import ERROR, NOT_REQUIRED, PROCESSING, SUCCESS, PathPlanner
from firefly.autopilot.results import Result
from firefly.autopilot.safety.fence_shapes import Shape, closest_point
from firefly.autopilot.safety.fence_switch import FenceSwitch

from ._util import altitude, fly_until, ready_vehicle

MARGIN = 5.0
EXCLUSION_POLY, INCLUSION_POLY, EXCLUSION_CIRCLE = 5002, 5001, 5004


def square(cn: float, ce: float, half: float) -> tuple:
    return (cn - half, ce - half), (cn + half, ce - half), (cn + half, ce + half), (cn - half, ce + half)


def poly(vertices, inclusion=False) -> Shape:
    return Shape("poly", inclusion, tuple(vertices), (0.0, 0.0, 0.0))


def circle(n, e, r, inclusion=False) -> Shape:
    return Shape("circle", inclusion, (), (n, e, r))


def length(path) -> float:
    return sum(math.dist(a, b) for a, b in zip(path, path[1:]))


def clearance(path, shape: Shape) -> float:
    """How near the path comes to the shape's boundary (a polygon's edges, a circle's rim)."""
    if shape.kind == "circle":
        n, e, r = shape.circle
        return min(math.dist(closest_point((n, e), a, b), (n, e)) - r for a, b in zip(path, path[1:]))
    v = shape.vertices
    edges = [(v[i], v[(i + 1) % len(v)]) for i in range(len(v))]
    samples = [(a[0] + (b[0] - a[0]) * k / 50, a[1] + (b[1] - a[1]) * k / 50) for a, b in zip(path, path[1:])
               for k in range(51)]
    return min(math.dist(p, closest_point(p, s, t)) for p in samples for s, t in edges)


# ----- geometry --------------------------------------------------------------------------------
def test_a_square_is_passed_at_its_corners_pushed_out_along_the_bisectors():
    """Measured on ArduCopter: a 20 m square centred 3 m east of the line, OA_MARGIN_MAX 5: the
    corners (36.5, -10.5) and (63.5, -10.5), on the shorter, west side."""
    fence = poly(square(50, 3, 10))
    path = FenceGraph([fence], MARGIN).shortest_path((0.0, 0.0), (100.0, 0.0))
    offset = MARGIN / math.sqrt(2.0)
    assert [tuple(round(c, 2) for c in p) for p in path[1:-1]] == [(40 - round(offset, 2), -7 - round(offset, 2)),
                                                                    (60 + round(offset, 2), -7 - round(offset, 2))]
    assert path[0] == (0.0, 0.0) and path[-1] == (100.0, 0.0)
    assert clearance(path, fence) == pytest.approx(offset, abs=0.01)


def test_the_shortest_of_the_ways_round_is_taken():
    east_way = [(0.0, 0.0), (36.46, 16.54), (63.54, 16.54), (100.0, 0.0)]
    path = FenceGraph([poly(square(50, 3, 10))], MARGIN).shortest_path((0.0, 0.0), (100.0, 0.0))
    assert length(path) < length(east_way)
    # two fences in the way and a circle: no way through the corners is shorter (all tried)
    fences = [poly(square(30, -3, 8)), poly(square(70, 4, 8)), circle(50, -14, 4)]
    graph = FenceGraph(fences, MARGIN)
    path = graph.shortest_path((0.0, 0.0), (100.0, 0.0))
    assert len(path) > 2 and all(not crosses_fence(fences, a, b) for a, b in zip(path, path[1:]))
    ways = [[(0.0, 0.0), *middle, (100.0, 0.0)] for k in range(1, 5)
            for middle in itertools.permutations(graph.corners, k)]
    clear = [w for w in ways if all(not crosses_fence(fences, a, b) for a, b in zip(w, w[1:]))]
    assert length(path) == pytest.approx(min(map(length, clear)))


def test_nothing_in_the_way_is_a_straight_path():
    graph = FenceGraph([poly(square(50, 40, 10))], MARGIN)
    assert graph.shortest_path((0.0, 0.0), (100.0, 0.0)) == [(0.0, 0.0), (100.0, 0.0)]


def test_an_inclusion_polygon_is_kept_inside_and_turned_at_its_notch():
    """Measured: a notch cut from the west edge across the line north: the corners (36.5, 23.5)
    and (63.5, 23.5), inside the notch's two corners; convex corners give none."""
    notched = poly([(-20, -40), (40, -40), (40, 20), (60, 20), (60, -40), (120, -40), (120, 40), (-20, 40)], True)
    graph = FenceGraph([notched], MARGIN)
    assert [tuple(round(c, 1) for c in p) for p in graph.corners] == [(36.5, 23.5), (63.5, 23.5)]
    path = graph.shortest_path((0.0, 0.0), (100.0, 0.0))
    assert [tuple(round(c, 1) for c in p) for p in path] == [(0.0, 0.0), (36.5, 23.5), (63.5, 23.5), (100.0, 0.0)]


def test_a_circle_is_passed_at_a_hexagon_outside_its_margin():
    """Measured: r 10 at (50, 0), margin 5: the corner (50, -17.3) (15 / cos 30 degrees out)."""
    fence = circle(50, 4, 10)
    corners = fence_corners([fence], MARGIN)
    assert len(corners) == 6
    assert all(math.dist(c, (50, 4)) == pytest.approx(15 / math.cos(math.radians(30))) for c in corners)
    path = FenceGraph([fence], MARGIN).shortest_path((0.0, 0.0), (100.0, 0.0))
    assert [tuple(round(c, 1) for c in p) for p in path[1:-1]] == [(50.0, -13.3)]
    assert clearance(path, fence) > MARGIN - 0.01


def test_no_path_into_an_exclusion_zone_nor_out_of_an_inclusion_zone():
    with pytest.raises(PlanError, match=NO_PATH):
        FenceGraph([poly(square(50, 0, 10))], MARGIN).shortest_path((0.0, 0.0), (50.0, 0.0))
    with pytest.raises(PlanError, match=NO_PATH):
        FenceGraph([poly(square(0, 0, 30), True)], MARGIN).shortest_path((0.0, 0.0), (100.0, 0.0))
    with pytest.raises(PlanError, match=NO_PATH):  # an inclusion circle: both ends must be in it
        FenceGraph([circle(0, 0, 30, True)], MARGIN).shortest_path((0.0, 0.0), (40.0, 0.0))


# ----- hostile fences: an answer, never an exception other than PlanError ------------------------
HOSTILE = {
    "repeated vertex": [poly([(0, 0), (0, 0), (10, 10), (0, 10)])],
    "collinear vertex": [poly([(40, -10), (50, -10), (60, -10), (60, 10), (40, 10)])],
    "two vertices": [poly([(40, -10), (60, 10), (40, -10)])],
    "bow tie": [poly([(40, -10), (60, 10), (60, -10), (40, 10)])],
    "zero radius": [circle(50, 0, 0.0)],
    "negative radius": [circle(50, 0, -20.0)],
    "nan radius": [circle(50, 0, math.nan)],
    "infinite radius": [circle(50, 0, math.inf)],
    "huge square": [poly(square(50, 0, 1e9))],
    "nan vertex": [poly([(40, -10), (math.nan, -10), (60, 10)])],
    "infinite vertex": [poly([(40, -10), (math.inf, -10), (60, 10)])],
    "tiny square": [poly(square(50, 0, 1e-9))],
}


@pytest.mark.parametrize("name", sorted(HOSTILE))
@pytest.mark.parametrize("margin", [0.0, -5.0, 5.0, 1e6, math.nan, math.inf])
def test_hostile_fences_give_a_path_or_a_reason(name, margin):
    try:
        path = FenceGraph(HOSTILE[name], margin).shortest_path((0.0, 0.0), (100.0, 0.0))
    except PlanError as error:
        assert str(error)
    else:
        assert path[0] == (0.0, 0.0) and path[-1] == (100.0, 0.0)


def test_random_fences_give_a_clear_path_or_a_reason():
    rng = random.Random(7)
    for _ in range(200):
        shapes = []
        for _ in range(rng.randint(1, 4)):
            if rng.random() < 0.3:
                shapes.append(circle(rng.uniform(-50, 150), rng.uniform(-80, 80), rng.uniform(-5, 30),
                                     rng.random() < 0.2))
            else:
                count = rng.randint(3, 9)
                shapes.append(poly([(rng.uniform(-50, 150), rng.uniform(-80, 80)) for _ in range(count)],
                                   rng.random() < 0.2))
        start, goal = (rng.uniform(-50, 150), rng.uniform(-80, 80)), (rng.uniform(-50, 150), rng.uniform(-80, 80))
        try:
            path = FenceGraph(shapes, rng.choice([0.0, 2.0, 5.0, 50.0])).shortest_path(start, goal)
        except PlanError as error:
            assert str(error)
            continue
        assert path[0] == start and path[-1] == goal
        assert all(not crosses_fence(shapes, a, b) for a, b in zip(path, path[1:]))


def test_degenerate_polygons_are_refused_as_arducopter_refuses_them():
    with pytest.raises(PlanError, match=OVERLAPPING_POINTS):
        FenceGraph(HOSTILE["repeated vertex"], MARGIN)
    with pytest.raises(PlanError, match=TOO_MANY_POINTS):
        ring = [(50 + 20 * math.cos(k * math.pi / 150), 20 * math.sin(k * math.pi / 150)) for k in range(300)]
        FenceGraph([poly(ring)], MARGIN)


# ----- the planner's answers -----------------------------------------------------------------
class Said:
    def __init__(self):
        self.texts: list[tuple[str, int]] = []

    def __call__(self, text, severity):
        self.texts.append((text, severity))


def planner(shapes, oa_type=2, fence_enable=1, **params):
    store = ParamStore()
    store.set("OA_TYPE", oa_type)
    store.set("FENCE_ENABLE", fence_enable)
    for name, value in params.items():
        store.set(name, value)
    said = Said()
    return PathPlanner(store, lambda: shapes, FenceSwitch(store), said), store, said


def test_a_new_destination_is_processing_until_the_next_plan_then_the_corners_come_in_turn():
    p, _, _ = planner([poly(square(50, 3, 10))])
    here, t = (0.0, 0.0), 10.5
    assert p.avoid(t, here, (100.0, 0.0), None).state == PROCESSING  # a request out of the blue waits
    answers = []
    while t < 12.0:
        t += 0.01
        answers.append(p.avoid(t, here, (100.0, 0.0), None))
    assert answers[-1].state == SUCCESS and answers[-1].destination == pytest.approx((36.46, -10.54), abs=0.01)
    first = next(i for i, a in enumerate(answers) if a.state == SUCCESS)
    assert all(a.state == PROCESSING for a in answers[:first])
    # within 2 m of the corner: the next corner from the plan after next on
    near = (35.0, -10.0)
    seen = [p.avoid(t + k * 0.1, near, (100.0, 0.0), None).destination for k in range(1, 30)]
    assert seen[0] == pytest.approx((36.46, -10.54), abs=0.01) and seen[-1] == pytest.approx((63.54, -10.54), abs=0.01)
    # past the last corner: nothing more in the way
    beyond = (64.0, -10.5)
    states = [p.avoid(t + 3.0 + k * 0.1, beyond, (100.0, 0.0), None).state for k in range(30)]
    assert states[-1] == NOT_REQUIRED


def test_no_path_is_an_error_said_every_five_seconds():
    p, _, said = planner([poly(square(50, 0, 10))])
    states = {p.avoid(k * 0.01, (0.0, 0.0), (50.0, 0.0), None).state for k in range(2000)}
    assert states == {PROCESSING, ERROR}
    assert said.texts == [("Dijkstra: could not find path", 2)] * 4  # at 1.0, 6.1, 11.2 and 16.3 s


def test_no_avoidance_without_a_polygon_fence_on():
    for shapes, enable in (([poly(square(50, 0, 10))], 0), ([], 1), ([circle(50, 0, 10, True)], 1)):
        p, _, _ = planner(shapes, fence_enable=enable)
        assert {p.avoid(k * 0.01, (0.0, 0.0), (100.0, 0.0), None).state for k in range(300)} == {PROCESSING, NOT_REQUIRED}


def test_oa_type_is_read_at_boot():
    p, store, _ = planner([poly(square(50, 0, 10))], oa_type=0)
    assert p.prearm_failure() is None
    store.set("OA_TYPE", 2)
    assert p.prearm_failure() == "Dijkstra OA requires reboot"  # measured, as "Arm: ..." on arming
    assert {p.avoid(k * 0.01, (0.0, 0.0), (100.0, 0.0), None).state for k in range(300)} == {NOT_REQUIRED}
    p, store, _ = planner([poly(square(50, 0, 10))], oa_type=2)
    store.set("OA_TYPE", 0)  # off at once
    assert p.prearm_failure() is None
    assert p.avoid(5.0, (0.0, 0.0), (100.0, 0.0), None).state == NOT_REQUIRED
    store.set("OA_TYPE", 1)  # BendyRuler, not made at boot: no answer, then a timeout after 3 s
    assert p.prearm_failure() == "BendyRuler OA requires reboot"
    states = [p.avoid(10.0 + k * 0.01, (0.0, 0.0), (100.0, 0.0), None).state for k in range(400)]
    assert states[0] == PROCESSING and states[-1] == ERROR and states.index(ERROR) == pytest.approx(300, abs=2)
    p, _, _ = planner([poly(square(50, 0, 10))], oa_type=1)  # BendyRuler made at boot: it plans
    assert {p.avoid(k * 0.01, (30.0, 0.0), (100.0, 0.0), None).state for k in range(300)} == {PROCESSING, SUCCESS}


# ----- flown -----------------------------------------------------------------------------------
REL = 3


def item_at(v, command, n, e, alt=10.0, p1=0.0) -> MissionItem:
    g = v.ned_to_global(n, e, 0.0)
    return MissionItem(command, REL, p1, 0, 0, 0, int(round(g.lat_deg * 1e7)), int(round(g.lon_deg * 1e7)), alt)


def fenced_vehicle(**params):
    v = ready_vehicle({"OA_TYPE": 2, "FENCE_ENABLE": 1, **params})
    v.mission.replace(FENCE, [item_at(v, EXCLUSION_POLY, n, e, p1=4) for n, e in square(50, 3, 10)])
    return v


def flying_fenced_vehicle(**params):
    """fenced_vehicle taken off in GUIDED to 10 m."""
    v = fenced_vehicle(**params)
    v.set_mode(4)
    assert v.arm() == Result.ACCEPTED and v.takeoff(10.0) == Result.ACCEPTED
    assert fly_until(v, lambda x: altitude(x) > 9.8, 20.0)
    return v


def fly_watching(v, done, timeout_s: float) -> tuple[list, set]:
    """Fly until done(v): the track flown and the destinations reported on the way (rounded)."""
    track, corners = [], set()

    def watch(x):
        track.append((x.body.n_m, x.body.e_m))
        dest = x.destination()
        if dest is not None:
            corners.add((round(dest[0], 1), round(dest[1], 1)))
        return done(x)
    assert fly_until(v, watch, timeout_s)
    return track, corners


def test_auto_flies_round_an_exclusion_square_and_reaches_its_waypoint():
    v = fenced_vehicle()
    v.mission.replace(0, [MissionItem(22, REL, z=10.0), item_at(v, 16, 100, 0)])
    v.set_mode(4)
    assert v.arm() == Result.ACCEPTED
    v.set_mode(3)
    assert v.mission_start() == Result.ACCEPTED
    track, corners = fly_watching(v, lambda x: 2 in x.mission_progress.reached, 60.0)
    assert {(36.5, -10.5), (63.5, -10.5)} <= corners
    assert min(math.dist(p, closest_point(p, (40, -7), (60, -7))) for p in track) > 2.5  # the west edge
    assert not any(40 < n < 60 and -7 < e < 13 for n, e in track)
    assert math.dist(track[-1], (100, 0)) < 1.0 and altitude(v) == pytest.approx(10, abs=0.5)


def test_guided_with_waypoint_navigation_flies_round_and_reports_its_arrival():
    v = flying_fenced_vehicle(GUID_OPTIONS=64)
    v.drain_events()
    assert v.guided_target((100.0, 0.0, v.home_ned[2] - 10.0), None, None) == Result.ACCEPTED
    track = []
    assert fly_until(v, lambda x: track.append((x.body.n_m, x.body.e_m)) or 0 in x.mission_progress.reached, 60.0)
    assert not any(40 < n < 60 and -7 < e < 13 for n, e in track)
    assert min(e for _, e in track) == pytest.approx(-10.5, abs=1.0)


def test_guided_refuses_a_destination_inside_the_fence_and_auto_stops_short_of_one():
    v = flying_fenced_vehicle(GUID_OPTIONS=64)
    assert v.guided_target((50.0, 3.0, v.home_ned[2] - 10.0), None, None) == Result.DENIED
    v.mission.replace(0, [MissionItem(22, REL, z=10.0), item_at(v, 16, 50, 3)])
    v.drain_events()
    assert v.set_mode(3) == Result.ACCEPTED
    v.run_until(v.time_s + 12.0)
    assert math.hypot(v.body.n_m, v.body.e_m) < 1.0  # held where it was
    said = [t for _, t in v.drain_events() if t.startswith("Dijkstra")]
    assert said == ["Dijkstra: could not find path"] * 3


def test_rtl_comes_back_round_the_fence():
    """Measured: out through the square in GUIDED (the position controller plans nothing), RTL
    returns by the corners (63.5, -10.5) and (36.5, -10.5)."""
    v = flying_fenced_vehicle(FENCE_ACTION=0)
    assert v.guided_target((100.0, 0.0, v.home_ned[2] - 10.0), None, None) == Result.ACCEPTED
    assert fly_until(v, lambda x: math.dist((x.body.n_m, x.body.e_m), (100, 0)) < 0.5, 40.0)
    assert v.set_mode(6) == Result.ACCEPTED
    track, corners = fly_watching(v, lambda x: math.hypot(x.body.n_m, x.body.e_m) < 1.0, 80.0)
    assert {(63.5, -10.5), (36.5, -10.5)} <= corners
    assert not any(40 < n < 60 and -7 < e < 13 for n, e in track)

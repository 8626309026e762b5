"""The team search at decision level: one vehicle is exactly the gig search; several share one
belief and one stopping rule, fly at separated heights, never take targets within 10 m of each
other's, and finish without a vehicle that drops out."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from firefly.groundstation.evaluation.episodes import EpisodeConfig, run_episode
from firefly.groundstation.evaluation.team_episodes import run_team_episode, team_starts
from firefly.groundstation.strategy.belief import Geometry
from firefly.groundstation.strategy.controller import Goto, SearchConfig
from firefly.groundstation.strategy.policies import lanes, make_policy
from firefly.groundstation.strategy.team import SEPARATION_M, JointGig, TeamController, make_team_policy, survey_heights
from firefly.sim.scenario import load_scenario

REPO = Path(__file__).resolve().parents[2]
WORLD = load_scenario(REPO / "scenarios" / "default.toml").world


@pytest.mark.parametrize("episode", [0, 1])
def test_one_vehicle_with_the_joint_planner_is_the_gig_search(episode):
    single = run_episode(WORLD, 1, episode, make_policy("gig"), EpisodeConfig())
    team = run_team_episode(WORLD, 1, episode, make_team_policy("joint"), 1, EpisodeConfig())
    assert team["team_path_m"] == single.path_m and tuple(team["declared"]) == tuple(single.declared)
    assert team["decisions"] == single.decisions


@pytest.mark.parametrize("policy", ["joint", "independent", "strips"])
def test_three_vehicles_find_the_fire(policy):
    results = [run_team_episode(WORLD, 1, i, make_team_policy(policy), 3, EpisodeConfig()) for i in range(3)]
    assert all(r["success"] and r["declared_by"] == "confident" for r in results), results
    assert all(len(r["paths_m"]) == 3 and min(r["paths_m"]) > 0 for r in results), "every vehicle flew"


def test_joint_targets_keep_apart_and_heights_are_separated():
    geometry = Geometry.from_world(WORLD)
    assert survey_heights(geometry, 3) == [geometry.survey_alt_m, geometry.survey_alt_m + 5, geometry.survey_alt_m + 10]
    team = TeamController(geometry, JointGig(), SearchConfig(), team_starts(geometry, 3, "corner"),
                          np.random.default_rng(0))
    for n, e, z in [(0, 0, 22.0), (5, 0, 22.3), (10, 0, 22.1)]:
        team.observe(0, n, e, z, 30.0)
    moves = team.step([(0.0, 0.0)] * 3, [0.0] * 3, [False] * 3)
    targets = [m.target for m in moves]
    assert all(isinstance(m, Goto) for m in moves)
    for a in range(3):
        for b in range(a + 1, 3):
            assert math.dist(targets[a], targets[b]) >= SEPARATION_M, targets


def test_a_vehicle_that_drops_out_leaves_the_others_to_finish():
    r = run_team_episode(WORLD, 1, 0, make_team_policy("joint"), 3, EpisodeConfig(), fail=(0, 10.0))
    assert r["dropped"] == [0] and r["success"]
    assert r["paths_m"][0] <= 10.0 * 5.0 + 5.0, "the dropped vehicle flew no further"
    alone = TeamController(Geometry.from_world(WORLD), JointGig(), SearchConfig(), [(0.0, 0.0)],
                           np.random.default_rng(0))
    alone.observe(0, 0.0, 0.0, 22.0, 30.0)
    alone.drop(0)
    assert alone.step([(0.0, 0.0)], [0.0], [False]).forced, "no vehicle left: a forced declaration"


def test_strips_cover_their_own_share_of_the_area():
    strip = lanes(400.0, 100.0, (0.0, 0.0), (200.0, 400.0))
    assert all(200.0 <= e <= 400.0 for _, e in strip) and len(strip) == 4
    assert lanes(400.0, 100.0, (0.0, 0.0)) == lanes(400.0, 100.0, (0.0, 0.0), (0.0, 400.0))


def test_the_team_flight_feed_pairs_each_vehicles_readings_with_its_own_positions_and_heights():
    """TeamSurvey (sans-IO): readings of each vehicle, paired with that vehicle's positions at
    their timestamps, reach the one team controller with that vehicle's height; moves come for
    every vehicle; a dropped vehicle's later readings count no more."""
    from firefly.groundstation.flight.team_survey import TeamSurvey
    geometry = Geometry.from_world(WORLD)
    config = SearchConfig()
    survey = TeamSurvey(geometry, config, 2)
    team = TeamController(geometry, JointGig(), config, [(0.0, 0.0), (0.0, 5.0)], np.random.default_rng(0))
    seen = []
    observe = team.observe
    team.observe = lambda i, n, e, z, h: (seen.append((i, round(n), round(e), h)), observe(i, n, e, z, h))
    survey.start(team)
    assert survey.next_moves() is None, "no reading yet: nothing to decide"
    for t_ms in range(0, 2100, 100):  # both fly north at 5 m/s, vehicle 1 at 30 m, vehicle 2 at 35 m, 5 m east
        survey.add_position(0, t_ms, t_ms / 200.0, 0.0, -30.0)
        survey.add_position(1, t_ms, t_ms / 200.0, 5.0, -35.0)
        survey.add_reading(0, t_ms, 22.0)
        survey.add_reading(1, t_ms, 22.0)
    assert {i for i, *_ in seen} == {0, 1}
    assert all(h == (30.0 if i == 0 else 35.0) and e == (0 if i == 0 else 5) for i, n, e, h in seen), seen
    moves = survey.next_moves()
    assert [type(m) for m in moves] == [Goto, Goto]
    assert survey.paths_m[0] == pytest.approx(10.0, abs=0.6) and survey.paths_m[1] == pytest.approx(10.0, abs=0.6)

    survey.drop(1, "it disarmed")
    counted = team.observations
    for t_ms in range(2100, 3200, 100):
        survey.add_position(1, t_ms, t_ms / 200.0, 5.0, -35.0)
        survey.add_reading(1, t_ms, 22.0)
    assert team.observations == counted, "a dropped vehicle's readings no longer count"
    moves = survey.next_moves()
    assert survey.out == {1: "it disarmed"} and (moves is None or moves[1] is None)


def test_a_candidate_on_another_vehicles_target_does_not_leave_a_vehicle_standing():
    """Two other vehicles' targets, one on a candidate: the excluded candidates must not turn the
    best score into NaN (a vehicle 'boxed in' would stay where it is)."""
    geometry = Geometry.from_world(WORLD)
    policy = JointGig()
    team = TeamController(geometry, policy, SearchConfig(), [(0.0, 0.0), (200.0, 200.0), (200.0, 205.0)],
                          np.random.default_rng(0))
    for n, e, z in [(0, 0, 22.0), (5, 0, 22.3), (10, 0, 22.1)]:
        team.observe(0, n, e, z, 30.0)
    candidates = policy.planners[0].candidates(team.belief, (0.0, 0.0))
    on_one = tuple(float(x) for x in candidates[0])
    with np.errstate(invalid="raise"):
        # the first other target excludes the candidate, the second sits on it (discount 0)
        chosen = policy.assign(team.belief, [(0.0, 0.0), (200.0, 200.0), (200.0, 205.0)],
                               [None, (on_one[0] + 5.0, on_one[1]), on_one], [0])
    assert chosen[0] != (0.0, 0.0), "the vehicle was left standing"
    assert math.dist(chosen[0], on_one) >= SEPARATION_M

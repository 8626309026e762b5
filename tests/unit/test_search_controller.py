"""The search controller (groundstation/strategy/controller.py) and the flight's feed of it
(groundstation/flight/survey.py): one set of decisions, whichever driver feeds the readings."""
from __future__ import annotations

import numpy as np
import pytest

from firefly.groundstation.evaluation.episodes import EpisodeConfig, episode_world, policy_rng, run_episode
from firefly.groundstation.flight.survey import Survey
from firefly.groundstation.strategy import Geometry, make_policy
from firefly.groundstation.strategy.controller import Goto, SearchConfig, SearchController
from firefly.groundstation.strategy.stopping import Declaration
from firefly.sim.fire import FireWorld


def replayed_through_the_flight_feed(world: FireWorld, seed: int, index: int, name: str, config: EpisodeConfig):
    """An episode's moves, and the moves of a fresh controller fed that episode's readings the way
    the flight feeds it: timestamped positions and readings through survey.py, which averages them
    into observations. Each reading is sent twice, a sample interval apart at the same place, so
    its observation is exactly that reading; the flight's driver asks for a move after each one."""
    readings, episode_moves = [], []
    run_episode(world, seed, index, make_policy(name), config, trace=readings, steps=episode_moves)
    geometry = Geometry.from_world(episode_world(world, seed, index, config))
    controller = SearchController(geometry, make_policy(name), config, readings[0][:2], policy_rng(seed, index))
    survey = Survey(geometry, config, arrival_m=0.0)  # the episodes fly onto their targets exactly
    survey.start(controller)
    interval_ms = int(1000 * config.sample_s)
    flight_moves = []
    for k, (n, e, z) in enumerate(readings):
        for t_ms in (2 * k * interval_ms, (2 * k + 1) * interval_ms):
            survey.add_position(t_ms, n, e, -geometry.survey_alt_m)
            survey.add_reading(t_ms, z)
        flight_moves.append(survey.next_move())
    return episode_moves, flight_moves, controller


@pytest.mark.parametrize("name", ["gig", "greedy", "lawnmower", "zigzag"])
def test_the_flight_feed_and_the_episode_make_the_same_decisions_from_the_same_readings(name):
    episode_moves, flight_moves, controller = replayed_through_the_flight_feed(FireWorld(), 1, 0, name, EpisodeConfig())
    assert flight_moves == episode_moves
    assert isinstance(episode_moves[-1], Declaration) and controller.declared == episode_moves[-1]
    assert sum(isinstance(m, Goto) and m.confirming for m in episode_moves) > 0 or name == "zigzag"


def test_the_flight_feed_keeps_the_settings_it_is_given():
    """A different threshold, no confirmation and a faster survey change the decisions alike."""
    config = EpisodeConfig(threshold=0.9, confirm_m=None, speed_m_s=8.0, subcells=1)
    episode_moves, flight_moves, _ = replayed_through_the_flight_feed(FireWorld(kernel="G"), 3, 2, "gig", config)
    default_moves, _, _ = replayed_through_the_flight_feed(FireWorld(kernel="G"), 3, 2, "gig", EpisodeConfig())
    assert flight_moves == episode_moves != default_moves
    assert not any(isinstance(m, Goto) and m.confirming for m in episode_moves)


def test_zigzag_declares_the_cell_of_its_hottest_observation_whoever_drives_it():
    g = Geometry(area_m=100.0)
    controller = SearchController(g, make_policy("zigzag"), SearchConfig(), (0.0, 0.0), np.random.default_rng(0))
    for n, e, z in [(3.0, 3.0, 20.0), (47.0, 62.0, 31.0), (80.0, 10.0, 25.0)]:
        controller.observe(n, e, z, 30.0)
    controller.policy.next_index = len(controller.policy.route)  # the route is flown: it has nothing more to do
    declared = controller.step((80.0, 10.0), 300.0)
    assert declared == Declaration((45.0, 65.0), (4, 6), controller.belief.mass_around((4, 6)), False, "end")
    assert controller.step((80.0, 10.0), 300.0) is declared  # and stays declared
    controller.observe(45.0, 65.0, 99.0, 30.0)
    assert controller.observations == 3  # observations after the declaration are not taken


def test_the_policy_is_reset_before_the_first_observation_and_a_step_needs_one():
    policy = make_policy("gradient")
    policy.leg = [(1.0, 1.0, 99.0)]  # left over from an earlier search
    controller = SearchController(Geometry(), policy, SearchConfig(), (0.0, 0.0), np.random.default_rng(0))
    assert policy.leg == []
    with pytest.raises(RuntimeError, match="before any observation"):
        controller.step((0.0, 0.0), 0.0)
    controller.observe(0.0, 0.0, 20.0, 30.0)
    assert policy.leg == [(0.0, 0.0, 20.0)] and isinstance(controller.step((0.0, 0.0), 0.0), Goto)


def test_the_budget_declares_with_the_belief_best_block():
    controller = SearchController(Geometry(), make_policy("random"), SearchConfig(budget_m=100.0), (0.0, 0.0),
                                  np.random.default_rng(0))
    controller.observe(0.0, 0.0, 20.0, 30.0)
    assert isinstance(controller.step((0.0, 0.0), 99.9), Goto)
    declared = controller.step((5.0, 0.0), 100.0)
    assert declared.reason == "budget" and declared.forced


def test_flight_readings_reach_the_controller_at_the_evaluated_density():
    """10 Hz readings in flight become one observation per 5 m or per second."""
    g = Geometry(area_m=200.0, survey_alt_m=25.0)
    survey = Survey(g, SearchConfig())
    survey.add_position(0, 0.0, 10.0, -25.0)
    survey.add_reading(0, 20.0)  # before the search starts: not used
    controller = SearchController(g, make_policy("gig"), SearchConfig(), (0.0, 10.0), np.random.default_rng(0))
    survey.start(controller)
    assert survey.next_move() is None  # nothing to decide on before the first observation
    t = 0
    for k in range(1, 101):  # 10 s north at 5 m/s, then 3 s hovering
        t = 100 * k
        survey.add_position(t, 0.5 * k, 10.0, -25.0)
        survey.add_reading(t, 20.0)
    moving = controller.observations
    for k in range(1, 31):
        survey.add_position(t + 100 * k, 50.0, 10.0, -25.0)
        survey.add_reading(t + 100 * k, 20.0)
    assert survey.readings == 130 and survey.path_m == pytest.approx(49.5)
    assert 9 <= moving <= 10  # 50 m flown: one per 5 m
    assert 2 <= controller.observations - moving <= 3  # hovering still gives the belief a look each second
    assert controller.belief.n == controller.observations


def test_a_reading_waits_for_the_position_of_its_instant_and_low_readings_are_not_used():
    g = Geometry(area_m=200.0, survey_alt_m=25.0)
    survey = Survey(g, SearchConfig())
    survey.start(SearchController(g, make_policy("gig"), SearchConfig(), (0.0, 0.0), np.random.default_rng(0)))
    survey.add_position(0, 0.0, 0.0, -25.0)
    survey.add_reading(50, 21.0)  # ahead of the positions: waits
    assert survey.readings == 0 and survey.pending == [(50, 21.0)]
    survey.add_position(100, 10.0, 0.0, -25.0)
    assert survey.readings == 1 and survey.track == [(5.0, 0.0)]  # interpolated at its own instant
    survey.add_position(200, 10.0, 0.0, -10.0)
    survey.add_reading(200, 22.0)  # from 10 m up: another height, not used
    assert survey.readings == 1 and survey.bin == []

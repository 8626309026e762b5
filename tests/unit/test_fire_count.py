"""A search not told how many fires there are (issue 30, item 3): it goes on after each find until
the belief is confident there is no other, and where the sensor sees farther from higher up it
climbs over the find to look (strategy/controller.py, "Several fires")."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from firefly.groundstation import cli
from firefly.groundstation.evaluation.episodes import EpisodeConfig, run_episode
from firefly.groundstation.strategy import controller, make_policy
from firefly.groundstation.strategy.belief import Geometry
from firefly.groundstation.strategy.refine import fit_hot_spots
from firefly.groundstation.strategy.controller import RULE_OUT_HEIGHT_M, Goto, SearchConfig, SearchController
from firefly.sim.fire import Fire, FireWorld, true_temperature

DEFAULT_SCENARIO = "scenarios/default.toml"


def one_fire(kernel: str) -> FireWorld:
    return FireWorld(fires=(Fire(250.0, 130.0, 45.0),), kernel=kernel, ambient_c=21.0)


def test_not_told_how_many_it_climbs_over_the_find_and_ends_clear():
    steps: list = []
    result = run_episode(one_fire("R"), 4, 0, make_policy("gig"), EpisodeConfig(fixed_fire=True, max_fires=None),
                         steps=steps)
    assert result.success and result.fires_found == 1 and len(result.declarations) == 1
    assert result.declared_by == "clear"
    climb = [m for m in steps if isinstance(m, Goto) and m.height_m == RULE_OUT_HEIGHT_M]
    assert climb, "no climb to look for another fire"
    # the path counts the climb (here it was clear before the top: 70 m up and over the fire)
    assert result.path_m - result.first_find_m > 30.0


def test_a_plume_that_does_not_widen_with_height_is_searched_at_the_survey_height():
    steps: list = []
    result = run_episode(one_fire("G"), 4, 0, make_policy("gig"), EpisodeConfig(fixed_fire=True, max_fires=None),
                         steps=steps)
    assert result.success and result.first_find_m is not None
    assert all(m.height_m is None for m in steps if isinstance(m, Goto))


def test_told_one_fire_it_declares_at_the_find_and_never_climbs():
    steps: list = []
    result = run_episode(one_fire("R"), 4, 0, make_policy("gig"), EpisodeConfig(fixed_fire=True), steps=steps)
    assert result.declared_by == "confident" and result.first_find_m == result.path_m
    assert all(m.height_m is None for m in steps if isinstance(m, Goto))


def test_the_clear_threshold_is_checked():
    with pytest.raises(ValueError, match="clear_threshold"):
        EpisodeConfig(clear_threshold=0.0)
    SearchConfig(max_fires=None)  # not told: allowed
    with pytest.raises(ValueError, match="max_fires"):
        SearchConfig(max_fires=0)


def test_evaluate_does_not_tell_the_search_how_many_fires_the_episodes_hold(tmp_path, capsys):
    out = tmp_path / "two.json"
    assert cli.main(["evaluate", "--scenario", DEFAULT_SCENARIO, "--episodes", "1", "--policies", "greedy",
                     "--fires", "2", "--json", str(out)]) == 0
    assert "not told how many fires" in capsys.readouterr().out
    doc = json.loads(out.read_text())
    assert doc["config"]["max_fires"] is None
    row = doc["results"]["greedy"][0]
    assert row["first_find_m"] is None or row["first_find_m"] <= row["path_m"]


def ghost_readings() -> tuple[FireWorld, list[tuple]]:
    """Two fires 160 m apart and 300 noisy readings at 30 m over the whole area."""
    w = FireWorld(fires=(Fire(200.0, 120.0, 50.0), Fire(200.0, 280.0, 40.0)), ambient_c=21.0, noise_k=0.5)
    rng = np.random.default_rng(5)
    points = rng.uniform(0.0, w.area_m, size=(300, 2))
    return w, [(n, e, true_temperature(w, n, e, 30.0, 0.0) + rng.normal(0.0, 0.5), 30.0) for n, e in points]


@pytest.mark.parametrize("ghost_below_k, kept", [(-math.inf, 3), (controller.GHOST_BELOW_K, 2)])
def test_a_find_between_two_fires_goes_once_both_are_found(monkeypatch, ghost_below_k, kept):
    """A find declared where two fires' tails add up (seen in two-fire episodes: one at N 95 E 125,
    56 m from the nearer fire) is dropped once both fires are found, as the joint fit gives it
    almost no strength; kept, it would be a false declaration beside the two true ones."""
    monkeypatch.setattr(controller, "GHOST_BELOW_K", ghost_below_k)
    search = SearchController(Geometry(), make_policy("gig"), SearchConfig(max_fires=None), (0.0, 0.0),
                              np.random.default_rng(0))
    _, search.readings = ghost_readings()
    finds = [(200.0, 120.0, 0.0, 0.0), (200.0, 280.0, 0.0, 0.0), (200.0, 200.0, 0.0, 0.0)]  # the last midway
    search.found = [(object(), spot) for spot in finds]
    search._move_spots(search._fit())
    assert len(search.found) == kept
    assert all(math.hypot(spot[0] - 200.0, spot[1] - e) < 5.0 for (_, spot), e in zip(search.found, (120.0, 280.0)))


def test_the_joint_fit_gives_a_ghost_no_strength():
    _, readings = ghost_readings()
    spots = [(200.0, 120.0, 0.0, 0.0), (200.0, 280.0, 0.0, 0.0), (200.0, 200.0, 0.0, 0.0)]  # the last midway
    _, strengths = fit_hot_spots(Geometry(), readings, spots, 0.5)
    assert strengths[0] == pytest.approx(50.0, abs=3.0) and strengths[1] == pytest.approx(40.0, abs=3.0)
    assert abs(strengths[2]) < controller.GHOST_BELOW_K


def test_the_prior_of_a_further_fire_is_its_own_setting():
    """Before a find the null hypothesis is "no fire at all" (null_prior); after one it is "no
    further fire" (further_prior): the knob that trades ruling a second fire out against missing one."""
    config = EpisodeConfig(max_fires=None, null_prior=0.5, further_prior=0.9)
    geometry = Geometry.from_world(one_fire("R"))
    search = controller.SearchController(geometry, make_policy("gig"), config, (0.0, 0.0), np.random.default_rng(0))
    assert search._belief(()).null_prior == 0.5
    assert search._belief(((250.0, 130.0, 0.0, 0.0),)).null_prior == 0.9
    assert search._belief(((250.0, 130.0, 0.0, 0.0),), null=False).null_prior == 0.0
    for bad in (0.0, 1.0):
        with pytest.raises(ValueError, match="further_prior"):
            EpisodeConfig(further_prior=bad)


@pytest.mark.parametrize("flag, value", [("--further-prior", "1"), ("--further-prior", "0"), ("--clear", "1.5")])
def test_evaluate_refuses_a_prior_or_clear_level_out_of_range_naming_the_option(flag, value, capsys):
    assert cli.main(["evaluate", "--episodes", "1", flag, value]) == 2
    err = capsys.readouterr().err
    assert flag in err and len(err.strip().splitlines()) == 1

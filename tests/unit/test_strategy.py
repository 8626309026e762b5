"""The decision layer's strategy (groundstation/strategy): the belief, the planner, the stopping rule,
the decision-level episodes and `groundstation evaluate`. Fast: no flight, no sockets."""
from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from firefly.groundstation import cli
from firefly.groundstation.evaluation.episodes import EpisodeConfig, run_episode
from firefly.groundstation.strategy import Belief, Geometry, Planner, PlannerConfig, StoppingRule, make_policy
from firefly.groundstation.strategy.belief import PLUME_RISE_M_S, plume_tilts
from firefly.groundstation.strategy.controller import SearchConfig
from firefly.groundstation.strategy.policies import POLICIES, lanes
from firefly.sim.fire import Fire, FireWorld, true_temperature

AREA = 400.0
DEFAULT_SCENARIO = Path(__file__).parents[2] / "scenarios" / "default.toml"


def world(kernel="R", fire=(123.0, 237.0), strength=50.0, ambient=22.0, noise=1.0) -> FireWorld:
    return FireWorld(fires=(Fire(fire[0], fire[1], strength),), kernel=kernel, ambient_c=ambient, noise_k=noise)


def grid_readings(w: FireWorld, spacing=20.0):
    """Noiseless readings on a square grid over the area."""
    ticks = np.arange(spacing / 2, w.area_m, spacing)
    return [(n, e, true_temperature(w, n, e, w.survey_alt_m, 0.0)) for n in ticks for e in ticks]


def belief_from(w: FireWorld, readings, offset=0.0, **kw) -> Belief:
    b = Belief(Geometry.from_world(w), **kw)
    for n, e, z in readings:
        b.update(n, e, z + offset, w.survey_alt_m)
    return b


def random_readings(seed: int, count: int, kernel="R"):
    rng = np.random.default_rng(seed)
    w = world(kernel, fire=tuple(rng.uniform(20, 380, 2)), strength=rng.uniform(20, 80))
    pts = rng.uniform(0, AREA, size=(count, 2))
    return w, [(n, e, true_temperature(w, n, e, 30.0, 0.0) + rng.normal()) for n, e in pts]


# ----- belief ------------------------------------------------------------------------------------
@pytest.mark.parametrize("kernel", ["R", "G"])
@pytest.mark.parametrize("subcells", [1, 3])
def test_belief_concentrates_on_the_true_cell_with_noiseless_readings(kernel, subcells):
    w = world(kernel)
    b = belief_from(w, grid_readings(w), subcells=subcells)
    (n, e), index = b.most_likely()
    assert index == (12, 23)
    assert b.mass_around(index) > 0.99
    assert b.probabilities().shape == (40, 40)
    assert b.probabilities().sum() == pytest.approx(1.0)
    assert b.entropy() < 1.0


def test_uniform_before_any_reading():
    b = Belief(Geometry())
    assert b.entropy() == pytest.approx(math.log(1600))
    assert np.allclose(b.probabilities(), 1 / 1600)


@pytest.mark.parametrize("kernel", ["R", "G"])
@pytest.mark.parametrize("subcells", [1, 3])
def test_belief_is_invariant_to_an_ambient_offset(kernel, subcells):
    w, readings = random_readings(7, 60, kernel)
    a = belief_from(w, readings, subcells=subcells)
    b = belief_from(w, readings, offset=10.0, subcells=subcells)
    assert np.allclose(a.probabilities(), b.probabilities(), rtol=0, atol=1e-9)
    assert a.entropy() == pytest.approx(b.entropy(), abs=1e-9)


def test_centred_evidence_equals_the_2x2_gaussian_integral():
    """log p(z|c) = const + 0.5 eta^T Lambda^-1 eta - 0.5 log det Lambda with raw sums."""
    w, readings = random_readings(3, 40)
    b = belief_from(w, readings)
    s2, sa2, mu = b.s2, b.sa2, b.mu_a
    g = np.array([b.kernel_at(n, e, 30.0) for n, e, _ in readings])  # (readings, cells)
    z = np.array([r[2] for r in readings])
    n, s_z = len(z), z.sum()
    s_g, s_gg, s_gz = g.sum(0), (g * g).sum(0), (g * z[:, None]).sum(0)
    log_ev = np.empty(s_g.size)
    for c in range(s_g.size):
        lam = np.array([[n / s2, s_g[c] / s2], [s_g[c] / s2, 1 / sa2 + s_gg[c] / s2]])
        eta = np.array([s_z / s2, mu / sa2 + s_gz[c] / s2])
        log_ev[c] = 0.5 * eta @ np.linalg.solve(lam, eta) - 0.5 * np.linalg.slogdet(lam)[1]
    p = np.exp(log_ev - log_ev.max())
    p /= p.sum()
    assert np.allclose(p, b.p, rtol=1e-6, atol=1e-12)


def line_readings(w: FireWorld, wild: dict, count: int = 12):
    """Noisy readings every 5 m along the south edge from the corner, some replaced by wild ones."""
    rng = np.random.default_rng(11)
    out = []
    for k in range(count):
        n, e = 5.0, 5.0 + 5.0 * k
        z = true_temperature(w, n, e, w.survey_alt_m, 0.0) + rng.normal()
        out.append((n, e, z + wild.get(k, 0.0)))
    return out


@pytest.mark.parametrize("wild", [{0: 20.0}, {1: 20.0, 2: 20.0}, {5: 20.0, 9: 20.0}, {3: -20.0},
                                  {7: 20.0, 8: 20.0}])
def test_a_wild_reading_or_two_cannot_make_the_robust_belief_certain(wild):
    w = world("R", fire=(300.0, 300.0))  # far from the readings: they all see about the ambient
    readings = line_readings(w, wild)
    robust = belief_from(w, readings, subcells=3, outlier_rate=0.02)
    assert robust.best_block()[1] < 0.5
    if wild in ({0: 20.0}, {7: 20.0, 8: 20.0}):
        # The plain Gaussian model puts the fire under the wild readings and is sure of it: the
        # failure the heavy tail fixes.
        assert belief_from(w, readings, subcells=3).best_block()[1] > 0.99


def test_the_robust_belief_still_finds_the_fire_after_an_outlier_first():
    w = world("R", fire=(123.0, 237.0))
    readings = grid_readings(w, spacing=40.0)
    readings[0] = (readings[0][0], readings[0][1], readings[0][2] + 20.0)
    b = belief_from(w, readings, subcells=3, outlier_rate=0.02)
    assert b.best_block()[0] in {(11, 22), (11, 23), (12, 22), (12, 23), (13, 23), (12, 24)}
    assert b.best_block()[1] > 0.9


def test_told_the_wind_the_belief_finds_the_fire_not_its_leaning_hot_spot():
    w = dataclasses.replace(world("G", fire=(200.0, 150.0)), wind_tilt=0.8, wind_to_deg=90.0)  # 24 m east
    readings = grid_readings(w, spacing=20.0)
    unaware = belief_from(w, readings, subcells=3)
    told = belief_from(w, readings, subcells=3, wind_ne_m_s=(0.0, 4.0))
    (i, j), _ = unaware.best_block()
    assert abs(i - 20) <= 1 and j in (17, 18)  # under the hot spot, 24 m east
    (i, j), _ = told.best_block()
    assert abs(i - 20) <= 1 and abs(j - 15) <= 1
    assert plume_tilts((0.2, 0.1)) == [(0.0, 0.0)]  # calm: upright
    assert len(plume_tilts((0.0, 4.0))) == len(PLUME_RISE_M_S)


@pytest.mark.parametrize("count", [3, 6, 7, 30])
def test_without_outliers_the_robust_machinery_is_the_exact_marginal(count):
    """outlier_rate 0: the burn-in and the filtering give the closed-form evidence (the chain rule
    of the same Gaussian), whatever the number of readings."""
    w, readings = random_readings(9, count)
    b = belief_from(w, readings, subcells=2)
    closed = b._gaussian_log_marginal(*b.sums.as_tuple())
    ev = b._stats()[1]
    assert np.ptp(ev - closed) < 1e-7


def test_entropy_after_a_hypothetical_reading_matches_the_update_and_leaves_the_belief_alone():
    w, readings = random_readings(5, 30)
    b = belief_from(w, readings)
    before = b.probabilities()
    x, z = (200.0, 150.0), 31.5
    predicted = float(b.entropy_after(x[0], x[1], np.array([z]))[0])
    assert np.array_equal(b.probabilities(), before)
    updated = belief_from(w, readings + [(x[0], x[1], z)])
    assert predicted == pytest.approx(updated.entropy(), abs=1e-9)
    mean, var = b.predictive(*x)
    assert mean.shape == var.shape == (1600,) and (var > 0).all()


# ----- planner -----------------------------------------------------------------------------------
@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 10_000), count=st.integers(1, 40),
       pos=st.tuples(st.floats(0, AREA), st.floats(0, AREA)), kernel=st.sampled_from(["R", "G"]),
       d0=st.sampled_from([None, 1.0, 50.0]))
def test_planner_never_leaves_the_area(seed, count, pos, kernel, d0):
    w, readings = random_readings(seed, count, kernel)
    b = belief_from(w, readings)
    planner = Planner(Geometry.from_world(w), PlannerConfig(d0_m=d0), np.random.default_rng(seed))
    assert ((planner.candidates(b, pos) >= 0) & (planner.candidates(b, pos) <= AREA)).all()
    n, e = planner.choose(b, pos)
    assert 0 <= n <= AREA and 0 <= e <= AREA
    assert math.isfinite(n) and math.isfinite(e)


@pytest.mark.parametrize("d0", [None, 50.0])
def test_planner_prefers_the_nearer_of_equally_informative_points(d0):
    w, readings = random_readings(1, 10)
    b = belief_from(w, readings)
    planner = Planner(Geometry.from_world(w), PlannerConfig(d0_m=d0), np.random.default_rng(0))
    pos = (100.0, 100.0)
    near, far = (100.0, 140.0), (100.0, 30.0)  # 40 m and 70 m away
    planner.candidates = lambda belief, position: np.array([far, near])
    planner.gains = lambda belief, pts: np.full(len(pts), 0.7)
    assert planner.choose(b, pos) == near


def test_planner_gain_is_higher_where_the_belief_is_uncertain():
    """After readings along the west edge, a reading far east tells more than one beside them."""
    w = world("G", fire=(300.0, 300.0))
    readings = [(n, 5.0, true_temperature(w, n, 5.0, 30.0, 0.0)) for n in np.arange(0, 400, 5.0)]
    b = belief_from(w, readings)
    planner = Planner(Geometry.from_world(w), PlannerConfig(samples=64), np.random.default_rng(0))
    gains = planner.gains(b, np.array([[200.0, 10.0], [200.0, 250.0]]))
    assert gains[1] > gains[0] >= 0


# ----- stopping ----------------------------------------------------------------------------------
def test_stopping_declares_only_at_the_threshold_and_can_be_forced():
    w = world("R", fire=(125.0, 235.0))
    rule = StoppingRule(threshold=0.95)
    few = belief_from(w, grid_readings(w, 200.0)[:2])
    index = few.most_likely()[1]
    assert few.mass_around(index) < 0.95
    assert rule.confident(few) is None
    forced = rule.force(few, "budget")
    assert forced.forced and forced.reason == "budget"
    assert forced.index == few.best_block()[0]
    many = belief_from(w, grid_readings(w))
    decl = rule.confident(many)
    assert decl is not None and not decl.forced and decl.index == (12, 23) and decl.mass >= 0.95
    strict = StoppingRule(threshold=1.0).confident(many)
    assert (strict is not None) == (many.mass_around((12, 23)) >= 1.0)


def test_stopping_with_confirmation_waits_for_a_reading_over_the_cell():
    w = world("R", fire=(125.0, 235.0))
    readings = [r for r in grid_readings(w) if math.hypot(r[0] - 125.0, r[1] - 235.0) > 30.0]
    b = belief_from(w, readings)
    rule = StoppingRule(threshold=0.95, confirm_m=10.0)
    unconfirmed = StoppingRule(threshold=0.95).confident(b)
    assert unconfirmed is not None and max(abs(unconfirmed.index[0] - 12), abs(unconfirmed.index[1] - 23)) <= 1
    assert rule.confident(b) is None
    n, e = rule.to_confirm(b)
    assert (n, e) == unconfirmed.position
    b.update(n, e, true_temperature(w, n, e, 30.0, 0.0), 30.0)
    assert rule.confident(b) is not None and rule.to_confirm(b) is None


def test_stopping_rule_and_search_settings_reject_bad_values():
    for bad in (dict(threshold=0.0), dict(threshold=1.5), dict(radius_cells=-1), dict(confirm_m=-1.0)):
        with pytest.raises(ValueError):
            StoppingRule(**bad)
    for bad in (dict(budget_m=0.0), dict(speed_m_s=0.0), dict(sample_s=-1.0)):
        with pytest.raises(ValueError):
            SearchConfig(**bad)


# ----- policies and episodes -----------------------------------------------------------------------
def test_lanes_cover_the_area_from_the_nearest_corner():
    pts = lanes(400.0, 30.0, (0.0, 0.0))
    assert len(pts) == 2 * 14
    assert pts[0] == pytest.approx((400 / 28, 400 / 28))
    east = sorted({e for _, e in pts})
    assert max(np.diff(east)) <= 30.0 and east[0] <= 15.0 and east[-1] >= 385.0


def _strip(result):
    d = result.to_dict()
    d.pop("ms_mean")
    d.pop("ms_max")
    return d


@pytest.mark.parametrize("name", ["gig", "lawnmower", "random"])
def test_episode_is_deterministic(name):
    w = FireWorld()
    config = EpisodeConfig(budget_m=600.0)
    a = run_episode(w, 11, 3, make_policy(name), config)
    b = run_episode(w, 11, 3, make_policy(name), config)
    assert _strip(a) == _strip(b)
    c = run_episode(w, 11, 4, make_policy(name), config)
    assert c.fires != a.fires


def test_episode_worlds_follow_the_recipe():
    from firefly.groundstation.evaluation.episodes import episode_world
    base = FireWorld(kernel="G", noise_k=3.0)
    for k in range(50):
        ew = episode_world(base, 5, k)
        (f,) = ew.fires
        assert 10.0 <= f.n_m <= 390.0 and 10.0 <= f.e_m <= 390.0
        assert 20.0 <= f.strength_k <= 80.0 and 15.0 <= ew.ambient_c <= 35.0
        assert ew.kernel == "G" and ew.noise_k == 3.0
    fixed = episode_world(base, 5, 0, EpisodeConfig(fixed_fire=True))
    assert fixed == base


def test_gig_succeeds_on_seeded_default_world_episodes():
    from firefly.sim.scenario import load_scenario
    scenario = load_scenario(DEFAULT_SCENARIO)
    results = [run_episode(scenario.world, scenario.seed, k, make_policy("gig")) for k in range(5)]
    for r in results:
        assert r.success and r.declared_by == "confident", r
        assert r.path_m < 1500.0
        assert r.decisions > 0 and r.ms_mean > 0
    fixed = run_episode(scenario.world, scenario.seed, 0, make_policy("gig"), EpisodeConfig(fixed_fire=True))
    assert fixed.success and fixed.fires == [(290.0, 250.0, 50.0)]


def test_zigzag_covers_everything_and_reports_the_hottest_cell():
    r = run_episode(FireWorld(), 1, 0, make_policy("zigzag"))
    assert r.declared_by == "end" and not r.forced
    assert 5000.0 < r.path_m < 6000.0
    assert r.success


@pytest.mark.parametrize("name", sorted(POLICIES))
def test_every_policy_runs_and_stays_inside(name):
    r = run_episode(FireWorld(), 2, 1, make_policy(name), EpisodeConfig(budget_m=800.0))
    assert r.path_m <= 800.0 + 5.0 or name == "zigzag"
    assert 0 <= r.declared[0] <= AREA and 0 <= r.declared[1] <= AREA


# ----- the command line --------------------------------------------------------------------------
def test_evaluate_writes_table_json_and_plot(tmp_path, capsys):
    out, png = tmp_path / "r.json", tmp_path / "r.png"
    rc = cli.main(["evaluate", "--scenario", str(DEFAULT_SCENARIO), "--episodes", "2", "--policies", "gig,greedy", "--seed", "4",
                   "--json", str(out), "--plot", str(png)])
    assert rc == 0
    text = capsys.readouterr().out
    assert "gig" in text and "greedy" in text and "success" in text
    data = json.loads(out.read_text())
    assert len(data["results"]["gig"]) == 2 and data["summary"]["gig"]["episodes"] == 2
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "path minus gig's" in text and set(data["paired_path_differences"]["policies"]) == {"greedy"}
    from firefly.groundstation.evaluation import report
    assert report.main([str(out)]) == 0
    tables = capsys.readouterr().out
    assert "| gig | " in tables and "| greedy | " in tables and "95 % CI" in tables


@pytest.mark.parametrize("argv,needle", [
    (["evaluate", "--scenario", str(DEFAULT_SCENARIO), "--policies", "gig,nope"], "unknown policy 'nope'"),
    (["evaluate", "--episodes", "0"], "--episodes"),
    (["evaluate", "--kernel", "X"], "--kernel"),
    (["evaluate", "--noise", "-1"], "--noise"),
    (["evaluate", "--scenario", "/nonexistent.toml"], "no such file"),
    (["evaluate", "--scenario", str(DEFAULT_SCENARIO), "--flight", "1", "--start", "centre"], "--start corner"),
    (["evaluate", "--scenario", str(DEFAULT_SCENARIO), "--episodes", "2", "--flight", "3"], "at most --episodes"),
    (["evaluate", "--flight-speedup", "0"], "--flight-speedup"),
    (["evaluate", "--outlier-rate", "1"], "--outlier-rate"),
    (["evaluate", "--scenario", str(DEFAULT_SCENARIO), "--start", "spread"], "--start spread: one vehicle per corner"),
    (["evaluate", "--scenario", str(DEFAULT_SCENARIO), "--vehicles", "3", "--start", "centre"], "--start centre"),
    (["evaluate", "--scenario", str(DEFAULT_SCENARIO), "--vehicles", "3", "--policies", "gig"], "unknown team policy 'gig'"),
    (["evaluate", "--scenario", str(DEFAULT_SCENARIO), "--vehicles", "2", "--fires", "2"], "a team searches for one fire"),
    (["explore", "--vehicles", "2", "--policy", "gig"], "--policy: 'gig' is not a team policy"),
    (["explore", "--vehicles", "2", "--url", "udpin://127.0.0.1:14540"], "--url: 1 URL(s) for --vehicles 2"),
    (["explore", "--vehicles", "7"], "--vehicles: at most 6"),
    (["explore", "--vehicles", "2", "--max-fires", "2"], "--max-fires: a team searches for one fire"),
])
def test_evaluate_errors_are_one_line_exit_2(argv, needle, capsys):
    assert cli.main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("groundstation: error:") and needle in err and "\n" not in err


def test_block_masses_match_mass_around_and_the_declared_cell_holds_the_most():
    w, readings = random_readings(9, 25, "G")
    b = belief_from(w, readings, subcells=3)
    blocks = b.block_masses(1)
    for index in [(0, 0), (0, 39), (39, 17), (20, 20), (5, 38)]:
        assert blocks[index] == pytest.approx(b.mass_around(index, 1), abs=1e-12)
    best, mass = b.best_block(1)
    assert mass == pytest.approx(blocks.max()) and mass >= b.mass_around(b.most_likely()[1])
    forced = StoppingRule().force(b)
    assert forced.index == best and forced.position == Geometry().centre_of(best)


def test_a_flown_episode_scenario_file_keeps_the_scenario_and_loads_back_as_the_episode_world():
    import tomllib
    from firefly.autopilot.cli.scenario import scenario_from_dict
    from firefly.groundstation.evaluation.flown_episodes import scenario_text
    from firefly.groundstation.evaluation.episodes import EpisodeConfig, episode_world
    base = tomllib.loads(DEFAULT_SCENARIO.read_text())
    base |= {"wind": {"speed_m_s": 4.0, "from_direction_deg": 250.0}, "airframe": {"mass_kg": 1.6},
             "script": {"steps": [[0.5, "arm"]]}}
    original = scenario_from_dict(base)
    leaning = scenario_from_dict(base | {"world": base["world"] | {"plume_rise_m_s": 5.0}}).world
    assert leaning.wind_tilt == pytest.approx(0.8)  # the wind leans it
    for index, world in enumerate((original.world, original.world, leaning)):
        ep = episode_world(dataclasses.replace(world, kernel="G", outlier_rate=0.01), 5, index,
                           EpisodeConfig())
        loaded = scenario_from_dict(tomllib.loads(scenario_text(base, 5 + index, ep)))
        assert loaded.world == ep and loaded.seed == 5 + index
        assert loaded.home == original.home and loaded.home_yaw_deg == original.home_yaw_deg
        assert loaded.sim.wind == original.sim.wind and loaded.sim.airframe == original.sim.airframe
        assert loaded.script == []  # the companion flies it


def test_paired_path_differences_pair_by_episode_and_bound_the_mean():
    from firefly.groundstation.evaluation.evaluate import paired_path_differences
    rng = np.random.default_rng(4)
    worlds = rng.uniform(300, 900, 50)  # what the episodes' worlds cost every policy alike
    results = {"gig": [{"episode": k, "path_m": float(w)} for k, w in enumerate(worlds)],
               "other": [{"episode": k, "path_m": float(w + 40 + rng.normal(0, 10))}
                         for k, w in reversed(list(enumerate(worlds)))]}
    d = paired_path_differences(results, "gig")["other"]
    assert d["episodes"] == 50
    assert d["ci95_low_m"] < 40 < d["ci95_high_m"]
    assert d["ci95_high_m"] - d["ci95_low_m"] < 10  # paired: the worlds' spread (600 m) cancels


def test_a_spread_belief_is_planned_on_pooled_blocks_that_keep_its_mass():
    from firefly.groundstation.strategy.planner import coarse_support
    w = FireWorld(fires=(Fire(590.0, 450.0, 50.0),), area_m=800.0)
    b = belief_from(w, [(5.0, 5.0 + 5 * k, 22.0) for k in range(8)], subcells=1)
    cells = b.support()
    assert len(cells) == 6400
    reps, mass = coarse_support(b, cells, 1600)
    assert len(reps) <= 1600 and mass.sum() == pytest.approx(b.p[cells].sum())
    # each block is stood for by its likeliest cell
    assert np.all(b.p[reps] * 4 >= mass - 1e-12)
    planner = Planner(Geometry.from_world(w), PlannerConfig(), np.random.default_rng(0))
    assert len(planner.lattice) == 100  # the lattice widens to 80 m rather than growing
    n, e = planner.choose(b, (5.0, 40.0))
    assert 0 <= n <= 800 and 0 <= e <= 800


def test_episodes_with_several_fires_keep_the_first_and_count_fires_found():
    from firefly.groundstation.evaluation.episodes import episode_world
    from firefly.groundstation.truth import fires_found
    base = FireWorld()
    one = episode_world(base, 2, 5, EpisodeConfig())
    two = episode_world(base, 2, 5, EpisodeConfig(fires=2))
    assert len(two.fires) == 2 and two.fires[0] == one.fires[0] and two.ambient_c == one.ambient_c
    pair = dataclasses.replace(base, fires=(Fire(100.0, 100.0), Fire(100.0, 140.0)))
    assert fires_found(pair, [(100.0, 120.0)]) == 0  # halfway between: neither
    assert fires_found(pair, [(102.0, 98.0)]) == 1
    assert fires_found(pair, [(102.0, 98.0), (100.0, 141.0)]) == 2
    with pytest.raises(ValueError, match="fires must be a positive whole number"):
        EpisodeConfig(fires=0)


def test_evaluate_draws_several_fires_and_reports_fires_found(tmp_path, capsys):
    one, both = tmp_path / "one.json", tmp_path / "both.json"
    assert cli.main(["evaluate", "--scenario", str(DEFAULT_SCENARIO), "--episodes", "2", "--policies", "greedy",
                     "--fires", "2", "--max-fires", "1", "--json", str(one)]) == 0
    assert "2 fires each" in capsys.readouterr().out
    data = json.loads(one.read_text())  # looking for one: one declaration, at most one fire found
    assert all(len(r["fires"]) == 2 and len(r["declarations"]) == 1 and 0 <= r["fires_found"] <= 1
               for r in data["results"]["greedy"])
    assert 0 <= data["summary"]["greedy"]["fires_found_rate"] <= 0.5
    assert cli.main(["evaluate", "--scenario", str(DEFAULT_SCENARIO), "--episodes", "2", "--policies", "greedy",
                     "--fires", "2", "--json", str(both)]) == 0
    assert "not told how many fires" in capsys.readouterr().out
    data = json.loads(both.read_text())  # not told how many (the default): on until clear
    assert all(1 <= len(r["declarations"]) and r["fires_found"] <= min(2, len(r["declarations"]))
               for r in data["results"]["greedy"])
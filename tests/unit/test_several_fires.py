"""Several fires (docs/strategy.md, "Several fires"): the belief with known fires explained away and
a "no further fire" hypothesis, the hot-spot fit, the controller's find-and-go-on search and how
episodes with several fires are judged. Fast: no flight, no sockets."""
from __future__ import annotations

import math

import numpy as np
import pytest

from firefly.groundstation.evaluation.episodes import EpisodeConfig, run_episode
from firefly.groundstation.truth import judge_all
from firefly.groundstation.strategy import Belief, Geometry, make_policy
from firefly.groundstation.strategy.belief import symmetric_inverse
from firefly.groundstation.strategy.refine import fit_hot_spots
from firefly.sim.fire import Fire, FireWorld, true_temperature

FIRE_A = Fire(120.0, 110.0, 50.0)
FIRE_B = Fire(300.0, 280.0, 40.0)


def two_fire_world(fires=(FIRE_A, FIRE_B), noise=1.0) -> FireWorld:
    return FireWorld(fires=tuple(fires), kernel="R", ambient_c=21.0, noise_k=noise)


def noisy_readings(w: FireWorld, count: int, seed: int = 0):
    rng = np.random.default_rng(seed)
    pts = rng.uniform(0, w.area_m, size=(count, 2))
    return [(n, e, true_temperature(w, n, e, w.survey_alt_m, 0.0) + rng.normal(0, w.noise_k)) for n, e in pts]


def brute_force_log_evidence(b: Belief, readings, height: float) -> np.ndarray:
    """log p(z | hypothesis) by the full linear-Gaussian integral over (ambient, known fires' nuisances
    with flat priors, strength ~ N(mu, sA2)), one hypothesis at a time; the last entry is the null."""
    z = np.array([r[2] for r in readings])
    x = np.array([np.concatenate([[1.0], b.known_kernels_at(n, e, height)]) for n, e, _ in readings])
    g = np.array([b.kernel_at(n, e, height) for n, e, _ in readings])
    g = np.column_stack([g, np.zeros(len(readings))])  # the null: no further fire
    out = np.empty(g.shape[1])
    for h in range(g.shape[1]):
        d = np.column_stack([x, g[:, h]])
        lam = d.T @ d / b.s2
        lam[-1, -1] += 1.0 / b.sa2
        eta = d.T @ z / b.s2
        eta[-1] += b.mu_a / b.sa2
        out[h] = 0.5 * eta @ np.linalg.solve(lam, eta) - 0.5 * np.linalg.slogdet(lam)[1]
    return out


def test_evidence_with_a_known_fire_and_the_null_is_the_full_gaussian_integral():
    w = two_fire_world()
    readings = noisy_readings(w, 40)
    b = Belief(Geometry(cell_m=40.0), known=((FIRE_A.n_m + 3.0, FIRE_A.e_m - 2.0, 0.0, 0.0),), null_prior=0.5)
    for n, e, z in readings:
        b.update(n, e, z, 30.0)
    log_ev = b._stats()[1]
    brute = brute_force_log_evidence(b, readings, 30.0)
    assert log_ev.shape == brute.shape
    # equal up to one constant, the null included (to the RIDGE that keeps the first readings invertible)
    assert np.ptp(log_ev - brute) < 1e-3


def test_a_rebuild_taking_every_reading_at_once_is_the_same_full_gaussian_integral():
    """absorb (the rebuild's joint pass) without outliers: the exact evidence, as the filter's."""
    w = two_fire_world()
    readings = noisy_readings(w, 40)
    b = Belief(Geometry(cell_m=40.0), known=((FIRE_A.n_m + 3.0, FIRE_A.e_m - 2.0, 0.0, 0.0),), null_prior=0.5)
    b.absorb([(n, e, z, 30.0) for n, e, z in readings])
    assert b.n == 40
    assert np.ptp(b._stats()[1] - brute_force_log_evidence(b, readings, 30.0)) < 1e-3


def test_a_rebuild_with_wild_readings_agrees_with_the_filter_and_the_filter_goes_on_from_it():
    w = two_fire_world()
    readings = [(n, e, z, 30.0) for n, e, z in noisy_readings(w, 80, seed=5)]
    readings[20] = readings[20][:2] + (readings[20][2] + 25.0, 30.0)  # two wild ones
    readings[50] = readings[50][:2] + (readings[50][2] - 30.0, 30.0)
    known = ((FIRE_A.n_m, FIRE_A.e_m, 0.0, 0.0),)

    def fresh():
        return Belief(Geometry(), subcells=3, outlier_rate=0.02, known=known, null_prior=0.5)
    one_by_one, at_once = fresh(), fresh()
    for reading in readings[:70]:
        one_by_one.update(*reading)
    at_once.absorb(readings[:70])
    for reading in readings[70:]:
        one_by_one.update(*reading)
        at_once.update(*reading)
    assert at_once.n == one_by_one.n == 80
    assert at_once.most_likely()[1] == one_by_one.most_likely()[1]
    assert 0.5 * np.abs(at_once.p - one_by_one.p).sum() < 0.05
    assert at_once.p_fire == pytest.approx(one_by_one.p_fire, abs=0.02)


def test_a_rebuild_spread_over_steps_reaches_the_same_belief():
    """absorbing() yields between chunks of each pass, so a caller can spread a rebuild over
    steps; drained, it is absorb's belief up to rounding, and it yields once per chunk and pass."""
    w = two_fire_world()
    readings = [(n, e, z, 30.0) for n, e, z in noisy_readings(w, 90, seed=6)]
    readings[30] = readings[30][:2] + (readings[30][2] + 25.0, 30.0)

    def fresh():
        return Belief(Geometry(), subcells=3, outlier_rate=0.02, known=((FIRE_A.n_m, FIRE_A.e_m, 0.0, 0.0),),
                      null_prior=0.5)
    whole, spread = fresh(), fresh()
    whole.absorb(readings)
    steps = list(spread.absorbing(readings, chunk=10))
    assert len(steps) == 5 + 2 + 9  # the kernels, the plain sums, the weighted sums: 20, 80, 10 readings a chunk
    assert spread.n == whole.n == 90
    assert np.allclose(spread.log_ev, whole.log_ev, rtol=0, atol=1e-9)
    assert np.abs(spread.p - whole.p).max() < 1e-12 and spread.p_fire == pytest.approx(whole.p_fire, abs=1e-12)


def test_a_rebuild_stays_finite_where_a_reading_is_all_but_surely_no_outlier():
    """A rare outlier prior and a precise sensor: the inlier odds reach the single precision's 1."""
    w = two_fire_world(noise=0.01)
    readings = [(n, e, z, 30.0) for n, e, z in noisy_readings(w, 30)]
    b = Belief(Geometry(cell_m=40.0), sigma_k=0.01, outlier_rate=1e-4,
               known=((FIRE_A.n_m, FIRE_A.e_m, 0.0, 0.0),), null_prior=0.5)
    b.absorb(readings)
    assert np.isfinite(b.log_ev).all() and np.isfinite(b.p).all() and b.p.sum() == pytest.approx(1.0)


def test_the_known_fires_block_holds_no_mass_and_the_other_fire_gets_it():
    w = two_fire_world(noise=0.5)
    g = Geometry()
    b = Belief(g, subcells=3, known=((FIRE_A.n_m, FIRE_A.e_m, 0.0, 0.0),), null_prior=0.5)
    for n, e, z in noisy_readings(w, 300, seed=1):
        b.update(n, e, z, 30.0)
    i, j = g.cell_of(FIRE_A.n_m, FIRE_A.e_m)
    assert b.probabilities()[i - 1:i + 2, j - 1:j + 2].sum() == 0.0
    assert b.p_fire > 0.999
    (_, index), mass = b.most_likely(), None
    assert max(abs(index[0] - g.cell_of(FIRE_B.n_m, FIRE_B.e_m)[0]), abs(index[1] - g.cell_of(FIRE_B.n_m, FIRE_B.e_m)[1])) <= 1
    assert math.isfinite(b.entropy())


def test_with_both_fires_known_the_null_takes_the_mass():
    w = two_fire_world()
    b = Belief(Geometry(), known=((FIRE_A.n_m, FIRE_A.e_m, 0.0, 0.0), (FIRE_B.n_m, FIRE_B.e_m, 0.0, 0.0)),
               null_prior=0.5)
    assert b.p_fire == pytest.approx(0.5)  # the prior, before any reading
    for n, e, z in noisy_readings(w, 800, seed=2):
        b.update(n, e, z, 30.0)
    assert b.p_fire < 0.01


def test_the_hot_spot_fit_puts_a_misplaced_find_right():
    w = two_fire_world(noise=0.3)
    readings = [(n, e, z, 30.0) for n, e, z in noisy_readings(w, 200, seed=3)]
    start = [(FIRE_A.n_m + 6.0, FIRE_A.e_m - 5.0, 0.0, 0.0), (FIRE_B.n_m - 4.0, FIRE_B.e_m + 4.0, 0.0, 0.0)]
    fitted = fit_hot_spots(Geometry(), readings, start, 0.3)[0]
    for spot, fire in zip(fitted, (FIRE_A, FIRE_B)):
        assert math.hypot(spot[0] - fire.n_m, spot[1] - fire.e_m) < 1.5, spot


@pytest.mark.parametrize("m", [3, 6, 9])  # one, two and three known fires
def test_symmetric_inverse_matches_lapack(m):
    rng = np.random.default_rng(4)
    x = rng.normal(size=(50, m, m))
    a = x @ x.transpose(0, 2, 1) + 0.1 * np.eye(m)
    inv, det = symmetric_inverse(a)
    assert np.allclose(inv, np.linalg.inv(a))
    assert np.allclose(det, np.linalg.det(a))


def test_a_declaration_between_two_fires_fails_the_episode():
    w = two_fire_world(fires=(Fire(200.0, 180.0, 50.0), Fire(200.0, 220.0, 50.0)))
    assert judge_all(w, [(205.0, 185.0)])[1]
    assert not judge_all(w, [(205.0, 205.0)])[1]  # halfway: more than a cell from each
    assert not judge_all(w, [(205.0, 185.0), (205.0, 205.0)])[1]  # one good, one between: a failure
    assert not judge_all(w, [])[1]


@pytest.mark.parametrize("policy", ["gig", "greedy"])
def test_the_search_finds_both_fires_and_ends(policy):
    w = two_fire_world()
    config = EpisodeConfig(fixed_fire=True, fires=2, max_fires=2)
    result = run_episode(w, 5, 0, make_policy(policy), config)
    assert len(result.declarations) == 2
    assert result.fires_found == 2 and result.success, result.declarations
    assert result.declared_by == "confident"


def test_looking_for_two_in_a_world_with_one_ends_confident_there_is_no_other():
    w = FireWorld(area_m=200.0, fires=(Fire(130.0, 70.0, 45.0),), kernel="R", ambient_c=18.0, noise_k=1.0,
                  survey_alt_m=25.0)
    config = EpisodeConfig(fixed_fire=True, max_fires=2)
    result = run_episode(w, 6, 0, make_policy("gig"), config)
    assert result.declared_by == "clear"
    assert result.success and len(result.declarations) == 1


def test_one_fire_to_look_for_is_the_plain_search():
    """max_fires 1 (the default) never builds the several-fire machinery: no null, no known fires."""
    from firefly.groundstation.strategy.controller import SearchConfig, SearchController
    c = SearchController(Geometry(), make_policy("gig"), SearchConfig(), (0.0, 0.0), np.random.default_rng(0))
    assert c.belief.null_prior == 0.0 and len(c.belief.known) == 0 and c.belief.p_fire == 1.0
    with pytest.raises(ValueError, match="max_fires"):
        SearchConfig(max_fires=0)


def test_evaluate_refuses_a_fire_spacing_it_cannot_draw_in_one_line(capsys):
    from firefly.groundstation import cli
    assert cli.main(["evaluate", "--episodes", "1", "--fire-spacing", "40"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "needs two fires" in err[0]
    assert cli.main(["evaluate", "--episodes", "1", "--fires", "2", "--fire-spacing", "900"]) == 2
    assert "no room for two fires 900 m apart" in capsys.readouterr().err


def test_twin_fires_are_drawn_at_the_spacing_and_equally_strong():
    from firefly.groundstation.evaluation.episodes import episode_world
    w = FireWorld()
    for index in range(20):
        a, b = episode_world(w, 3, index, EpisodeConfig(fires=2, fire_spacing_m=40.0)).fires
        assert math.hypot(a.n_m - b.n_m, a.e_m - b.e_m) == pytest.approx(40.0)
        assert a.strength_k == b.strength_k
        assert all(w.cell_m <= v <= w.area_m - w.cell_m for v in (b.n_m, b.e_m))


def test_twin_fires_40m_apart_are_each_declared_on_their_own_cell():
    """Two equal fires 40 m apart: no declaration between them, and none pushed beyond a twin
    (the finds are placed by fitting both together at the end)."""
    w = two_fire_world(fires=(Fire(200.0, 180.0, 50.0), Fire(200.0, 220.0, 50.0)))
    result = run_episode(w, 7, 0, make_policy("gig"), EpisodeConfig(fixed_fire=True, fires=2, max_fires=2))
    assert result.success and result.fires_found == 2, result.declarations


def test_the_final_fit_reaches_a_find_declared_two_cells_off():
    w = two_fire_world(fires=(Fire(200.0, 180.0, 50.0), Fire(200.0, 220.0, 50.0)), noise=0.5)
    readings = [(n, e, z, 30.0) for n, e, z in noisy_readings(w, 300, seed=8)]
    start = [(200.0, 185.0, 0.0, 0.0), (205.0, 240.0, 0.0, 0.0)]  # the second pushed 20 m out
    near = fit_hot_spots(Geometry(), readings, start, 0.5)[0]  # the search's reach: one cell
    far = fit_hot_spots(Geometry(), readings, start, 0.5, reach_cells=3.0)[0]
    assert math.hypot(near[1][0] - 200.0, near[1][1] - 220.0) > 5.0
    assert all(math.hypot(s[0] - f.n_m, s[1] - f.e_m) < 2.0 for s, f in zip(far, w.fires)), far

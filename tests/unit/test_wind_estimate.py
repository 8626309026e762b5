"""The wind the search estimates from how the vehicle leans (issue 30): the estimator, the flight's
steady samples, and the controller that rebuilds its belief with the estimate and will not declare
a cell while the lean is unknown."""
import math

import numpy as np
import pytest

from firefly.groundstation.evaluation.episodes import EpisodeConfig, run_episode
from firefly.groundstation.flight.lean_samples import LeanSamples
from firefly.groundstation.strategy import Geometry, make_policy
from firefly.groundstation.strategy.controller import SearchConfig, SearchController
from firefly.groundstation.strategy.wind_estimate import LeanWindEstimator, lean_of_attitude
from firefly.sim.fire import Fire, FireWorld

C = 0.017  # drag over weight, per m/s: of the order of the sim airframe's


def samples(wind, velocities, noise=0.0, seed=0):
    rng = np.random.default_rng(seed)
    for v in velocities:
        yield v, tuple(C * (v[k] - wind[k]) + rng.normal(0.0, noise) for k in range(2))


def test_a_vehicle_flying_north_nose_down_leans_north_and_one_rolled_right_leans_east():
    n, e = lean_of_attitude(0.0, math.radians(-5.0), 0.0)
    assert n == pytest.approx(math.tan(math.radians(5.0))) and e == pytest.approx(0.0, abs=1e-12)
    n, e = lean_of_attitude(math.radians(5.0), 0.0, 0.0)
    assert e == pytest.approx(math.tan(math.radians(5.0))) and n == pytest.approx(0.0, abs=1e-12)
    # yawed to face east, nose down: leans east
    n, e = lean_of_attitude(0.0, math.radians(-5.0), math.pi / 2)
    assert e == pytest.approx(math.tan(math.radians(5.0))) and n == pytest.approx(0.0, abs=1e-12)


def test_hovering_alone_cannot_tell_the_drag_from_the_wind_but_one_leg_more_can():
    est = LeanWindEstimator()
    for v, lean in samples((1.0, -3.0), [(0.0, 0.0)] * 20):
        est.add(v, lean)
    assert est.estimate() is None
    for v, lean in samples((1.0, -3.0), [(5.0, 0.0)] * 10):
        est.add(v, lean)
    found = est.estimate()
    assert found.air_ne_m_s == pytest.approx((1.0, -3.0), abs=1e-6)
    assert found.drag_per_weight == pytest.approx(C)


def test_the_estimate_converges_through_noise_and_ignores_a_wild_sample():
    rng = np.random.default_rng(3)
    headings = rng.uniform(0, 2 * math.pi, 200)
    velocities = [(5 * math.cos(h), 5 * math.sin(h)) for h in headings]
    est = LeanWindEstimator()
    for v, lean in samples((-2.0, 2.5), velocities, noise=0.003, seed=4):
        est.add(v, lean)
    est.add((0.0, 0.0), (0.3, -0.3))  # a lean the link paired with the wrong instant
    est.add((math.nan, 0.0), (0.0, 0.0))  # a mangled sample is dropped
    found = est.estimate()
    assert est.n == 201
    assert math.dist(found.air_ne_m_s, (-2.0, 2.5)) < 0.1
    assert 0.0 < found.sd_m_s < 0.1


def test_steady_samples_wait_to_see_that_the_velocity_stayed_steady():
    leans = LeanSamples(30.0)
    taken = []
    for k in range(60):  # 10 Hz: 3 s north at 5 m/s, then a turn east
        t = 100 * k
        v = (5.0, 0.0) if t < 3000 else (0.0, 5.0)
        leans.add_attitude(t, 0.0, math.radians(-5.0), 0.0)
        got = leans.add_velocity(t, *v, 30.0)
        if got is not None:
            taken.append((t, got))
    instants = [t - 500 for t, _ in taken]  # each judged half a second after its instant
    # none before a whole second of history; none whose window [i - 1 s, i + 0.5 s] holds the turn
    assert instants and min(instants) >= 1000
    assert not any(2500 <= i < 4000 for i in instants) and max(instants) >= 4000
    assert all(sample[0] == ((5.0, 0.0) if i < 3000 else (0.0, 5.0)) for i, (_, sample) in zip(instants, taken))
    assert all(b - a >= 500 for a, b in zip(instants, instants[1:]))  # at most one per half second
    assert leans.add_velocity(7000, 0.0, 5.0, 10.0) is None  # below the survey height


def test_the_controller_rebuilds_its_belief_with_the_estimate_and_holds_back_until_it_has_one():
    g = Geometry()
    controller = SearchController(g, make_policy("gig"), SearchConfig(), (0.0, 0.0), np.random.default_rng(0),
                                  wind_ne_m_s=None)
    assert not controller.lean_known()
    for v, lean in samples((0.0, 4.0), [(0.0, 0.0)] * 5 + [(3.5, 3.5)] * 5):
        controller.observe_lean(v, lean)
    assert controller.wind_rebuilds == 1 and controller.wind_ne_m_s == pytest.approx((0.0, 4.0), abs=1e-6)
    assert not controller.lean_known()  # the rebuild with it runs at the next step
    assert controller.belief.tilts == [(0.0, 0.0)]
    for k in range(30):  # more readings than a step's chunks: the rebuild spans steps
        controller.observe(5.0 * k, 0.0, 20.0, 30.0)
    steps = 0
    while not controller.lean_known():
        assert controller.belief.tilts == [(0.0, 0.0)]  # the old belief steers meanwhile
        controller.step((0.0, 0.0), 0.0)
        steps += 1
    assert 1 < steps <= 3 and controller.belief.n == 30
    assert controller.belief.tilts[0] == pytest.approx((0.0, 1.0))  # 4 m/s over the 4 m/s rise
    told = SearchController(g, make_policy("gig"), SearchConfig(), (0.0, 0.0), np.random.default_rng(0),
                            wind_ne_m_s=(1.0, 0.0))
    told.observe_lean((5.0, 0.0), (0.5, 0.5))  # told: the samples are not used
    assert told.lean_known() and told.wind_ne_m_s == (1.0, 0.0) and told.wind_estimator is None


def test_a_leaning_plume_with_the_wind_unreported_is_found_from_the_vehicles_lean():
    world = FireWorld(fires=(Fire(290.0, 250.0, 50.0),), kernel="G", wind_tilt=0.8, wind_to_deg=90.0)
    told_calm = EpisodeConfig(fixed_fire=True, wind_ne_m_s=(0.0, 0.0), air_ne_m_s=(0.0, 4.0))
    estimating = EpisodeConfig(fixed_fire=True, air_ne_m_s=(0.0, 4.0))
    wrong = run_episode(world, 1, 0, make_policy("gig"), told_calm)
    right = run_episode(world, 1, 0, make_policy("gig"), estimating)
    assert not wrong.success  # taking the air as calm declares the hot spot, 24 m downwind
    assert right.success and right.declared_by == "confident"


def test_evaluate_estimates_the_wind_unless_told_or_told_to_ignore_it():
    from pathlib import Path

    from firefly.groundstation.cli import CliError, build_parser
    from firefly.groundstation.evaluation.evaluate import told_wind
    from firefly.sim.scenario import load_scenario
    scenario = load_scenario(Path(__file__).parents[2] / "scenarios" / "wind_plume.toml")
    parse = build_parser().parse_args
    assert told_wind(parse(["evaluate"]), scenario) is None
    told = told_wind(parse(["evaluate", "--told-wind"]), scenario)
    assert told == pytest.approx((0.0, 4.0), abs=1e-9)  # 4 m/s from the west blows east
    assert told_wind(parse(["evaluate", "--ignore-wind"]), scenario) == (0.0, 0.0)
    with pytest.raises(CliError, match="--ignore-wind: not allowed with argument --told-wind"):
        parse(["evaluate", "--told-wind", "--ignore-wind"])

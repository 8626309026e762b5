"""The search with a thermal camera (issue 32, item 5): a frame's likelihood in the belief
(strategy/frame.py), the camera episodes and `groundstation evaluate --sensor`."""
from __future__ import annotations

import numpy as np
import pytest

from firefly.sim.fire import Fire, FireWorld
from firefly.sim.thermal_camera import ThermalCameraSpec, footprint, footprint_corners, pose_from_attitude, render
from groundstation.cli import main
from groundstation.evaluation.episodes import EpisodeConfig, run_episode
from groundstation.strategy.belief import Belief, Geometry
from groundstation.flight.camera_frames import rotation_of
from groundstation.camera_view import frame_from_image
from groundstation.strategy.frame import frame_log_likelihood, inner_rectangle, reduce_frame
from groundstation.strategy.policies import make_policy
from groundstation.strategy.stopping import StoppingRule

SPEC = ThermalCameraSpec()


def frame_over(world: FireWorld, n: float, e: float, seed: int = 0, alt: float = 30.0):
    pose = pose_from_attitude(n, e, alt)
    image = render(world, SPEC, pose, np.random.default_rng(seed))
    north, east = footprint(SPEC, pose)
    return reduce_frame(image, north, east, footprint_corners(SPEC, pose), SPEC.emission_height_m)


def belief_after(frame) -> Belief:
    b = Belief(Geometry(), subcells=3, outlier_rate=0.02)
    b.add_frame(frame_log_likelihood(b, frame), frame)
    return b


def cell_p(b: Belief, n: float, e: float) -> float:
    i, j = b.geometry.cell_of(n, e)
    return float(b.p[i * b.size + j])


def test_a_fire_in_view_raises_its_cell_and_lowers_the_others_in_view():
    world = FireWorld(fires=(Fire(204.0, 196.0, 30.0),), ambient_c=20.0)
    frame = frame_over(world, 200.0, 200.0)
    assert frame.peak is not None and abs(frame.peak[0] - 204.0) < 0.5 and abs(frame.peak[1] - 196.0) < 0.5
    b = belief_after(frame)
    prior = 1.0 / b.p.size
    assert cell_p(b, 204.0, 196.0) > 100 * prior
    for n, e in ((190.0, 188.0), (210.0, 210.0), (190.0, 210.0)):  # in view, no fire
        assert frame.contains(n, e) and cell_p(b, n, e) < prior


def test_a_frame_without_fire_lowers_the_cells_in_view_and_leaves_the_far_ones_alike():
    world = FireWorld(fires=(Fire(50.0, 350.0, 60.0),), ambient_c=20.0)
    frame = frame_over(world, 200.0, 200.0)
    assert frame.peak is None
    b = belief_after(frame)
    prior = 1.0 / b.p.size
    assert cell_p(b, 205.0, 205.0) < 0.05 * prior
    grid = b.p.reshape(b.size, b.size)
    far = np.ones((b.size, b.size), dtype=bool)
    far[15:26, 15:26] = False  # the frame's cells and a margin of a few cells around them
    values = grid[far]
    assert values.max() == pytest.approx(values.min(), rel=1e-9)  # untouched against each other
    assert values.min() > prior  # (raised only by the renormalisation)


def test_a_frame_moves_no_odds_among_cells_outside_it_when_it_sees_a_fire():
    world = FireWorld(fires=(Fire(200.0, 200.0, 50.0),), ambient_c=20.0)
    b = belief_after(frame_over(world, 200.0, 200.0))
    grid = b.p.reshape(b.size, b.size)
    far = np.ones((b.size, b.size), dtype=bool)
    far[15:26, 15:26] = False
    assert grid[far].max() == pytest.approx(grid[far].min(), rel=1e-9)


def test_a_fire_just_outside_the_frame_is_not_declared_from_one_frame():
    # the frame spans north 200 +- 12.2 m; the fire 3 m beyond its north edge lights the edge
    world = FireWorld(fires=(Fire(215.2, 200.0, 80.0),), ambient_c=20.0)
    frame = frame_over(world, 200.0, 200.0)
    assert not frame.contains(215.2, 200.0)
    b = belief_after(frame)
    rule = StoppingRule(0.99, 1, confirm_m=10.0)
    assert rule.confident(b) is None


def test_frames_and_camera_episodes_are_deterministic_given_the_seed():
    world = FireWorld(fires=(Fire(204.0, 196.0, 30.0),), ambient_c=20.0)
    assert frame_over(world, 200.0, 200.0, seed=3) == frame_over(world, 200.0, 200.0, seed=3)
    small = FireWorld(fires=(Fire(60.0, 60.0, 50.0),), area_m=120.0)
    config = EpisodeConfig(sensor="camera", max_fires=1)
    a = run_episode(small, 5, 0, make_policy("gig"), config).to_dict()
    b = run_episode(small, 5, 0, make_policy("gig"), config).to_dict()
    for r in (a, b):
        for key in ("ms_mean", "ms_max", "frame_ms_mean", "frame_ms_max"):
            r.pop(key)
    assert a == b and a["frames"] == a["readings"] and a["success"]


def test_a_tilted_frame_is_refused():
    world = FireWorld(ambient_c=20.0)
    pose = pose_from_attitude(200.0, 200.0, 30.0, yaw_deg=30.0)
    image = render(world, SPEC, pose, None)
    north, east = footprint(SPEC, pose)
    with pytest.raises(ValueError, match="axis-aligned"):
        reduce_frame(image, north, east, footprint_corners(SPEC, pose))


@pytest.mark.parametrize("roll, pitch, yaw", [(0.0, 0.0, 30.0), (0.0, 0.0, 90.0), (4.0, -7.0, 45.0)])
def test_a_tilted_or_turned_frame_is_judged_on_the_rectangle_inside_its_footprint(roll, pitch, yaw):
    pose = pose_from_attitude(200.0, 200.0, 30.0, roll, pitch, yaw)
    corners = footprint_corners(SPEC, pose)
    n_lo, n_hi, e_lo, e_hi = inner_rectangle(corners)
    assert n_hi - n_lo > 10.0 and e_hi - e_lo > 10.0  # a good part of the 24 m x 33 m footprint
    # every corner of the rectangle is inside the footprint: its pixels' ground points surround it
    north, east = footprint(SPEC, pose)
    for n, e in ((n_lo, e_lo), (n_lo, e_hi), (n_hi, e_lo), (n_hi, e_hi)):
        assert np.min(np.hypot(north - n, east - e)) < 0.5
    # a fire in the rectangle is seen there; the frame claims no more ground than the rectangle
    fire = Fire(0.5 * (n_lo + n_hi) + 2.0, 0.5 * (e_lo + e_hi) - 3.0, 40.0)
    world = FireWorld(fires=(fire,), ambient_c=20.0)
    frame = frame_from_image(render(world, SPEC, pose, np.random.default_rng(1)), SPEC, pose)
    assert (frame.n_lo, frame.n_hi, frame.e_lo, frame.e_hi) == pytest.approx((n_lo, n_hi, e_lo, e_hi))
    assert frame.peak is not None and np.hypot(frame.peak[0] - fire.n_m, frame.peak[1] - fire.e_m) < 1.0


def test_a_level_frame_at_yaw_0_is_judged_whole_and_the_geotag_quaternion_is_its_pose():
    pose = pose_from_attitude(200.0, 200.0, 30.0)
    image = render(FireWorld(ambient_c=20.0), SPEC, pose, np.random.default_rng(2))
    north, east = footprint(SPEC, pose)
    assert frame_from_image(image, SPEC, pose) == reduce_frame(image, north, east, footprint_corners(SPEC, pose))
    # CAMERA_IMAGE_CAPTURED's q for a fixed camera level at yaw 0 (docs/thermal_camera.md)
    assert np.allclose(rotation_of((0.7071068, 0.0, -0.7071068, 0.0)), pose.rotation, atol=1e-6)


def test_the_sensor_option_is_checked(capsys):
    assert main(["evaluate", "--sensor", "sonar", "--episodes", "1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--sensor" in err[0]
    with pytest.raises(ValueError, match="sensor"):
        EpisodeConfig(sensor="sonar")

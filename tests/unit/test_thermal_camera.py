"""The radiometric thermal camera (issue 32, item 4): pinhole geometry over the flat ground, the fire
field it sees (sim/fire.py's model at the burning layer's height, leaning with the wind), its
noise and blur, the footprint helpers and the geotagged float TIFF stills."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from firefly.sim.fire import Fire, FireWorld, temperature_field, true_temperature
from firefly.sim.thermal_camera import (ThermalCameraSpec, footprint, footprint_corners, pose_from_attitude,
                                        render)
from firefly.sim.thermal_still import Geotag, load_radiometric, save_radiometric

FIRE = Fire(200.0, 200.0, 50.0)
WORLD = FireWorld(fires=(FIRE,))
SPEC = ThermalCameraSpec()
SHARP = ThermalCameraSpec(psf_sigma_px=0.0)  # no blur: pixels are the field itself


def hot_spot(image: np.ndarray, world: FireWorld = WORLD) -> tuple[float, float]:
    """(row, col) centroid of the pixels above half the fire's peak: the burning layer's core."""
    excess = image.astype(float) - world.ambient_c
    mask = excess > 0.5 * excess.max()
    rows, cols = np.nonzero(mask)
    weights = excess[mask]
    return float(np.average(rows, weights=weights)), float(np.average(cols, weights=weights))


def test_the_defaults_are_a_lepton_class_core():
    assert (SPEC.width_px, SPEC.height_px, SPEC.hfov_deg, SPEC.frame_rate_hz, SPEC.netd_k) == (160, 120, 57.0, 8.7, 0.05)
    # square pixels: the vertical field follows from the aspect
    assert SPEC.vfov_deg == pytest.approx(math.degrees(2 * math.atan(0.75 * math.tan(math.radians(28.5)))))


def test_nadir_over_a_fire_centres_the_hot_spot():
    image = render(WORLD, SPEC, pose_from_attitude(FIRE.n_m, FIRE.e_m, 30.0), None)
    assert image.dtype == np.float32 and image.shape == (120, 160)
    row, col = hot_spot(image)
    assert (row, col) == (pytest.approx(59.5, abs=0.05), pytest.approx(79.5, abs=0.05))
    assert image.max() == pytest.approx(WORLD.ambient_c + FIRE.strength_k, abs=1.5)  # peak, a little blurred


def test_moving_north_moves_the_hot_spot_down_the_image_by_the_pinhole_figure():
    h, moved = 30.0, 3.0
    here = hot_spot(render(WORLD, SPEC, pose_from_attitude(FIRE.n_m, FIRE.e_m, h), None))
    north = hot_spot(render(WORLD, SPEC, pose_from_attitude(FIRE.n_m + moved, FIRE.e_m, h), None))
    expected = SPEC.focal_px * moved / h  # the fire is now `moved` m south: image bottom is south
    assert expected == pytest.approx(14.73, abs=0.01)
    assert north[0] - here[0] == pytest.approx(expected, abs=0.1)
    assert north[1] == pytest.approx(here[1], abs=0.01)


def test_yaw_turns_the_image_a_nadir_camera_facing_east_has_east_at_the_top():
    pose = pose_from_attitude(FIRE.n_m, FIRE.e_m - 3.0, 30.0, yaw_deg=90.0)
    row, col = hot_spot(render(WORLD, SPEC, pose, None))
    assert row == pytest.approx(59.5 - SPEC.focal_px * 3.0 / 30.0, abs=0.1)
    assert col == pytest.approx(79.5, abs=0.1)


def test_footprint_at_30_m_is_2h_tan_half_fov():
    pose = pose_from_attitude(100.0, 50.0, 30.0)
    corners = footprint_corners(SPEC, pose)
    width = 2 * 30.0 * math.tan(math.radians(SPEC.hfov_deg / 2))
    height = 2 * 30.0 * math.tan(math.radians(SPEC.vfov_deg / 2))
    assert width == pytest.approx(32.57, abs=0.01) and height == pytest.approx(24.43, abs=0.01)
    assert corners[1, 1] - corners[0, 1] == pytest.approx(width)  # top edge, west to east
    assert corners[0, 0] - corners[3, 0] == pytest.approx(height)  # left edge, south to north
    assert corners[0] == pytest.approx([100.0 + height / 2, 50.0 - width / 2])  # top-left is north-west
    n, e = footprint(SPEC, pose)
    assert n.shape == e.shape == (120, 160)
    # pixel centres: half a pixel's ground size inside the corners
    assert e[0, -1] - e[0, 0] == pytest.approx(width * 159 / 160)
    assert n[0, 0] - n[-1, 0] == pytest.approx(height * 119 / 120)


def test_each_pixel_reads_the_field_at_its_footprint():
    world = FireWorld(fires=(FIRE, Fire(210.0, 195.0, 30.0, growth_k_per_s=0.5)), wind_tilt=1.5, wind_to_deg=40.0)
    pose = pose_from_attitude(205.0, 198.0, 25.0, roll_deg=5.0, pitch_deg=-8.0, yaw_deg=30.0, gimbal_pitch_deg=-70.0)
    image = render(world, SHARP, pose, None, t_s=20.0)
    n, e = footprint(SHARP, pose)
    assert np.allclose(image, temperature_field(world, n, e, SHARP.emission_height_m, 20.0), atol=1e-4)
    for row, col in ((0, 0), (60, 80), (119, 159), (17, 101)):
        assert image[row, col] == pytest.approx(
            true_temperature(world, n[row, col], e[row, col], SHARP.emission_height_m, 20.0), abs=1e-4)


def test_the_plume_leaning_with_the_wind_shifts_the_hot_spot_downwind():
    h, tilt = 30.0, 2.0
    pose = pose_from_attitude(FIRE.n_m, FIRE.e_m, h)
    still = hot_spot(render(WORLD, SPEC, pose, None))
    east_wind = FireWorld(fires=(FIRE,), wind_tilt=tilt, wind_to_deg=90.0)  # the plume leans east
    leaning = hot_spot(render(east_wind, SPEC, pose, None), east_wind)
    downwind_m = tilt * SPEC.emission_height_m  # fire.py: tilt * height, at the burning layer's height
    assert leaning[1] - still[1] == pytest.approx(SPEC.focal_px * downwind_m / h, abs=0.1)
    assert leaning[0] == pytest.approx(still[0], abs=0.01)
    north_wind = FireWorld(fires=(FIRE,), wind_tilt=tilt, wind_to_deg=0.0)  # leans north: up the image
    assert hot_spot(render(north_wind, SPEC, pose, None), north_wind)[0] - still[0] == pytest.approx(
        -SPEC.focal_px * downwind_m / h, abs=0.1)


def test_a_scenarios_wind_leans_the_plume_the_camera_sees():
    from firefly.sim.scenario import scenario_from_dict
    scenario = scenario_from_dict({"wind": {"speed_m_s": 5.0, "from_direction_deg": 270.0},  # from the west
                                   "world": {"plume_rise_m_s": 2.0},
                                   "fire": [{"n_m": FIRE.n_m, "e_m": FIRE.e_m, "strength_k": FIRE.strength_k}]})
    pose = pose_from_attitude(FIRE.n_m, FIRE.e_m, 30.0)
    row, col = hot_spot(render(scenario.world, SPEC, pose, None), scenario.world)
    downwind_m = 5.0 / 2.0 * SPEC.emission_height_m  # 5 m east
    assert (row, col) == (pytest.approx(59.5, abs=0.1), pytest.approx(79.5 + SPEC.focal_px * downwind_m / 30.0, abs=0.1))


def test_tilted_toward_the_horizon_it_sees_sky_above_it():
    pitch = -10.0
    image = render(WORLD, SHARP, pose_from_attitude(0.0, 0.0, 30.0, gimbal_pitch_deg=pitch), None)
    horizon_row = SHARP.height_px / 2 - SHARP.focal_px * math.tan(math.radians(-pitch))  # 33.98
    sky = np.arange(SHARP.height_px) + 0.5 < horizon_row
    assert sky.sum() == 34
    assert np.all(image[sky] == np.float32(SHARP.sky_c))
    assert np.all(image[~sky] == pytest.approx(WORLD.ambient_c, abs=0.1))  # the fire is far off
    n, _ = footprint(SHARP, pose_from_attitude(0.0, 0.0, 30.0, gimbal_pitch_deg=pitch))
    assert np.all(np.isnan(n[sky])) and np.all(np.isfinite(n[~sky]))
    level = render(WORLD, SHARP, pose_from_attitude(0.0, 0.0, 30.0, gimbal_pitch_deg=0.0), None)
    assert np.all(level[:60] == np.float32(SHARP.sky_c)) and np.all(level[60:] > 20.0)


def test_noise_over_a_uniform_scene_has_sigma_netd():
    uniform = FireWorld(fires=())
    image = render(uniform, SPEC, pose_from_attitude(200.0, 200.0, 30.0), np.random.default_rng(7))
    assert float(image.mean()) == pytest.approx(uniform.ambient_c, abs=0.003)  # 3 standard errors
    assert float(image.std()) == pytest.approx(SPEC.netd_k, rel=0.03)
    assert np.all(render(uniform, SPEC, pose_from_attitude(200.0, 200.0, 30.0), None) == np.float32(22.0))


def test_a_seed_gives_the_same_frame():
    pose = pose_from_attitude(FIRE.n_m + 5.0, FIRE.e_m, 30.0)
    first = render(WORLD, SPEC, pose, np.random.default_rng(3))
    assert np.array_equal(first, render(WORLD, SPEC, pose, np.random.default_rng(3)))
    assert not np.array_equal(first, render(WORLD, SPEC, pose, np.random.default_rng(4)))


def test_the_blur_is_scipys_gaussian_filter():
    ndimage = pytest.importorskip("scipy.ndimage")
    pose = pose_from_attitude(FIRE.n_m + 2.0, FIRE.e_m - 1.0, 20.0, gimbal_pitch_deg=-20.0)
    sharp = render(WORLD, SHARP, pose, None).astype(float)
    for sigma in (1.0, 0.6, 2.3):
        spec = ThermalCameraSpec(psf_sigma_px=sigma)
        assert np.allclose(render(WORLD, spec, pose, None), ndimage.gaussian_filter(sharp, sigma), atol=1e-3)


def test_a_still_round_trips_its_temperatures_and_geotag(tmp_path):
    image = render(WORLD, SPEC, pose_from_attitude(FIRE.n_m, FIRE.e_m, 30.0), np.random.default_rng(1))
    tag = Geotag(-35.3610, 149.1675, 614.0, 1.5, -2.0, 87.0, -90.0, 0.0, 1_764_550_000.25)
    path = tmp_path / "still.tif"
    save_radiometric(path, image, tag)
    back, back_tag = load_radiometric(path)
    assert back.dtype == np.float32 and np.array_equal(back, image)
    assert back_tag == tag
    import tifffile  # what any other reader sees: a float32 plane, the geotag as text, the time
    with tifffile.TiffFile(path) as tif:
        page = tif.pages[0]
        assert page.dtype == np.float32 and page.shape == (120, 160)
        assert json.loads(page.description)["lat_deg"] == -35.3610
        assert page.tags["DateTime"].value == "2025:12:01 00:46:40"


def test_a_tiff_without_a_geotag_is_refused(tmp_path):
    import tifffile
    tifffile.imwrite(tmp_path / "plain.tif", np.zeros((4, 4), np.float32), description="hello", metadata=None)
    with pytest.raises(ValueError, match="geotag"):
        load_radiometric(tmp_path / "plain.tif")
    with pytest.raises(ValueError, match="time_unix_s"):
        Geotag(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, math.nan)


@pytest.mark.parametrize("field, value", [
    ("width_px", 0), ("width_px", -160), ("height_px", 0), ("height_px", 12.5), ("hfov_deg", 0.0),
    ("hfov_deg", -10.0), ("hfov_deg", 180.0), ("hfov_deg", 200.0), ("hfov_deg", math.nan), ("netd_k", -0.01),
    ("psf_sigma_px", -1.0), ("frame_rate_hz", 0.0), ("emission_height_m", -1.0), ("sky_c", math.inf),
    ("width_px", 4097), ("height_px", 70000),  # a frame that would not fit in memory or in MAVLink's fields
])
def test_a_bad_spec_names_its_field(field, value):
    with pytest.raises(ValueError, match=field):
        ThermalCameraSpec(**{field: value})


def test_a_camera_on_the_ground_still_renders():
    image = render(WORLD, SPEC, pose_from_attitude(FIRE.n_m, FIRE.e_m, -1.0), None)
    assert np.all(np.isfinite(image)) and image.max() > 60.0


def test_a_stabilised_gimbal_ignores_the_vehicles_roll_and_pitch():
    steady = pose_from_attitude(10.0, 20.0, 30.0, yaw_deg=45.0)
    tilted = pose_from_attitude(10.0, 20.0, 30.0, roll_deg=12.0, pitch_deg=-9.0, yaw_deg=45.0, stabilised=True)
    assert np.allclose(steady.rotation, tilted.rotation)
    leaning = pose_from_attitude(10.0, 20.0, 30.0, roll_deg=12.0, pitch_deg=-9.0, yaw_deg=45.0)
    assert not np.allclose(steady.rotation, leaning.rotation)

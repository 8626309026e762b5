"""Precision landing: SITL's beacon (sim/precland.py), AC_PrecLand's estimator and LAND's use of it
(autopilot/precland.py), a companion's LANDING_TARGET. The reference's answers are in the parity
area precland; these pin the rules between them."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.modes import ModeNumber
from firefly.autopilot.params import ParamStore
from firefly.autopilot.precland import BODY_FRD, LOCAL_FRD, PrecLand, line_of_sight
from firefly.sim.precland import CONE, CYLINDER, SPHERE, Beacon, quantised_e7

from ._util import altitude, fly_until, hovering_vehicle

HOME_LAT, HOME_LON = 43.5615, 1.4838  # VehicleConfig's default home


def store(**values) -> ParamStore:
    params = ParamStore()
    for name, value in values.items():
        params.set(name, value)
    return params


def test_the_beacon_sees_the_vehicle_above_it_within_its_shape():
    cylinder = Beacon(0.0, 0.0, 0.0, 15.0, 10.0, CYLINDER)
    assert cylinder.sees(3.0, 4.0, -10.0) == (3.0, 4.0, -10.0)
    assert cylinder.sees(3.0, 4.0, 0.0) is None  # on its plane: not above it
    assert cylinder.sees(3.0, 4.0, -16.0) is None and cylinder.sees(11.0, 0.0, -5.0) is None
    assert Beacon(0, 0, 0, 15.0, 10.0, CONE).sees(6.0, 0.0, -6.0) is None  # the cone is 4 m wide there
    assert Beacon(0, 0, 0, 15.0, 10.0, CONE).sees(3.0, 0.0, -6.0) is not None
    assert Beacon(0, 0, 0, 15.0, 10.0, SPHERE).sees(6.0, 0.0, -9.0) is None
    assert Beacon(0, 0, 0, 0.0, 10.0, CYLINDER).sees(0.0, 0.0, -5.0) is None  # SITL's switch-off values


def test_the_beacon_is_placed_through_float32s_as_sitl_places_it():
    # -35.36322507 (4 m north of SITL's home) reads as -353632256 in SITL, 0.65 m south
    assert quantised_e7(-35.36322507) == -353632256 and quantised_e7(149.16518594) == 1491651968


def feed(pl: PrecLand, start_s: float, end_s: float, every_s: float, notify, height_m: float = 8.0):
    t = start_s
    while t < end_s - 1e-9:
        pl.heard((0.0, 0.0, 1.0), 0.0, t)
        pl.update(t, notify, (0.0, 0.0, -height_m), height_m)
        t += every_s


def test_the_estimator_acquires_after_two_seconds_of_readings_and_loses_after_two_without():
    said = []
    pl = PrecLand(store(PLND_ENABLED=1, PLND_TYPE=4))
    notify = lambda text, severity=0: said.append(text)  # noqa: E731
    feed(pl, 0.0, 1.0, 0.1, notify)
    for t in (1.2, 1.4, 1.6):  # a gap before it has settled, with the 100 Hz updates going on
        pl.update(t, notify, (0.0, 0.0, -8.0), 8.0)
    feed(pl, 1.7, 3.0, 0.1, notify)
    assert said == ["PrecLand: Target Found", "PrecLand: Init Failed", "PrecLand: Target Found"] and not pl.acquired
    feed(pl, 3.0, 4.0, 0.1, notify)
    assert pl.acquired and said[-1] == "PrecLand: Init Complete"
    assert pl.target_ne == (0.0, 0.0) and pl.target_height_m == pytest.approx(8.0)
    for t in (5.0, 6.2):
        pl.update(t, notify, (0.0, 0.0, -8.0), 8.0)
    assert not pl.acquired and said[-1] == "PrecLand: Target Lost"


def test_without_a_rangefinder_or_a_distance_nothing_is_placed():
    pl = PrecLand(store(PLND_ENABLED=1, PLND_TYPE=4, PLND_EST_TYPE=0))
    pl.heard((0.6, 0.0, 0.8), 0.0, 1.0)
    pl.update(1.0, lambda *a: None, (0.0, 0.0, -8.0), None)
    assert pl.target_ne is None
    pl.heard((0.6, 0.0, 0.8), 10.0, 1.1)  # the sensor's own distance: 6 m north
    pl.update(1.1, lambda *a: None, (0.0, 0.0, -8.0), None)
    assert pl.acquired and pl.target_ne == pytest.approx((6.0, 0.0))


@pytest.mark.parametrize("frame, yaw, want", [(LOCAL_FRD, 0.0, (0.6, 0.0, 0.8)),
                                              (LOCAL_FRD, math.pi / 2, (0.0, 0.6, 0.8)),
                                              (BODY_FRD, math.pi / 2, (0.0, 0.6, 0.8))])
def test_a_landing_target_position_is_turned_into_ned(frame, yaw, want):
    unit, distance = line_of_sight(frame, 0.0, 0.0, 10.0, (6.0, 0.0, 8.0), True, (0.0, 0.0, yaw))
    assert unit == pytest.approx(want) and distance == 10.0


def test_landing_target_angles_and_hostile_values():
    unit, distance = line_of_sight(BODY_FRD, math.atan2(3.0, 4.0), 0.0, 0.0, (0, 0, 0), False, (0.0, 0.0, 0.0))
    assert unit == pytest.approx((0.0, 0.6, 0.8)) and distance == 0.0  # angle_x: towards the right
    assert line_of_sight(BODY_FRD, 0.0, 0.0, 0.0, (1, 0, 0), True, (0, 0, 0)) is None  # a position needs a distance
    assert line_of_sight(BODY_FRD, math.nan, 0.0, 0.0, (0, 0, 0), False, (0, 0, 0)) is None
    assert line_of_sight(BODY_FRD, 0.0, 0.0, math.inf, (1, 0, 0), True, (0, 0, 0)) is None


def beacon_vehicle(north_m: float, east_m: float, **params):
    v = hovering_vehicle(10.0, boot_params={"PLND_ENABLED": 1, "PLND_TYPE": 4, "RNGFND1_TYPE": 100,
                                            "RNGFND1_MAX": 30, **params})
    lat = HOME_LAT + north_m / 111319.5
    lon = HOME_LON + east_m / (111319.5 * math.cos(math.radians(HOME_LAT)))
    for name, value in (("SIM_PLD_LAT", lat), ("SIM_PLD_LON", lon), ("SIM_PLD_ENABLE", 1)):
        v.params.set(name, value)
    v.run_until(v.time_s + 3.0)
    return v


def test_land_comes_down_on_the_beacon():
    v = beacon_vehicle(4.0, -4.0)
    assert v.precland.acquired
    beacon = v.sim.beacon
    assert v.set_mode(ModeNumber.LAND).name == "ACCEPTED"
    v.run_until(v.time_s + 1.0)
    assert altitude(v) > 9.8  # holding its height while farther than PLND_XY_DIST_MAX
    assert fly_until(v, lambda x: not x.armed, 60.0)
    assert math.hypot(v.body.n_m - beacon.n_m, v.body.e_m - beacon.e_m) < 0.1


def test_a_beacon_out_of_view_is_the_failsafe_then_a_landing_where_it_is():
    v = beacon_vehicle(30.0, 0.0)
    said = []
    v.text_listener = lambda severity, text: said.append(text)
    v.set_mode(ModeNumber.LAND)
    assert fly_until(v, lambda x: not x.armed, 90.0)
    assert "PrecLand: Failsafe Measures" in [t for _, t in v.drain_events()] + said
    assert math.hypot(v.body.n_m, v.body.e_m) < 0.3

"""Terrain in the world and in the vehicle: a scenario's hills (sim/terrain.py) under the sim's
rangefinder and ground contact; the vehicle's terrain database (autopilot/terrain_grid.py,
autopilot/terrain.py) filled by a ground station's tile server (groundstation/terrain_tiles.py)
through the vehicle's own TERRAIN_REQUEST / TERRAIN_DATA / TERRAIN_REPORT / TERRAIN_CHECK."""
from __future__ import annotations

import dataclasses
import random

import pytest

from firefly.autopilot.location import Loc, loc_of
from firefly.autopilot.mavlink import terrain as terrain_messages
from firefly.autopilot.mission import MissionItem
from firefly.autopilot.modes import Guided
from firefly.autopilot.results import Result
from firefly.autopilot.terrain_grid import FULL_MASK, TerrainGrid, blocks_around, grid_info
from firefly.groundstation.terrain_tiles import answer, hills_amsl, tiles
from firefly.sim.rigid_body import BodyState
from firefly.sim.scenario import ScenarioError, scenario_from_dict
from firefly.sim.terrain import Hill, Terrain
from firefly.sim.vehicle import SimConfig, SimVehicle

from ._util import client_codec, ready_vehicle

HILL = {"north_m": 120.0, "east_m": 0.0, "height_m": 20.0, "radius_m": 60.0}


def test_a_hill_is_a_smooth_bump_that_adds_where_hills_overlap():
    t = scenario_from_dict({"terrain": [HILL, {**HILL, "east_m": 30.0}]}).sim.terrain
    assert t.height_m(0.0, 0.0) == 0.0
    assert Terrain((Hill(**HILL),)).height_m(120.0, 0.0) == pytest.approx(20.0)
    assert Terrain((Hill(**HILL),)).height_m(90.0, 0.0) == pytest.approx(10.0)
    assert t.height_m(120.0, 15.0) > 20.0


@pytest.mark.parametrize("tables, words", [
    ({"terrain": {"north_m": 1}}, "s.toml: terrain is given as [[terrain]] tables"),
    ({"terrain": [{**HILL, "slope": 1}]}, "s.toml: [[terrain]] 1 unknown key 'slope'"),
    ({"terrain": [{"north_m": 100.0}]}, "s.toml: [[terrain]] 1 missing 'east_m'"),
    ({"terrain": [{**HILL, "height_m": "tall"}]}, "s.toml: [[terrain]] 1.height_m: expected a finite number"),
    ({"terrain": [HILL, {**HILL, "north_m": 20.0}]}, "s.toml: [[terrain]] 2.radius_m: the hill reaches home"),
    ({"terrain": [{**HILL, "radius_m": 0}]}, "s.toml: [[terrain]] 1.radius_m: must be above 0"),
])
def test_bad_terrain_tables_are_one_line_naming_table_and_key(tables, words):
    with pytest.raises(ScenarioError) as caught:
        scenario_from_dict(tables, "s.toml")
    assert str(caught.value).startswith(words) and "\n" not in str(caught.value)


def test_the_rangefinder_sees_the_hill_and_a_body_rests_on_it():
    sim = SimVehicle(SimConfig(terrain=Terrain((Hill(**HILL),))))
    sim.state = sim.state._replace(body=BodyState(n_m=120.0, d_m=-30.0), on_ground=False)
    assert sim.read_sonar() == pytest.approx(10.0)
    sim.state = sim.state._replace(body=BodyState(n_m=120.0, d_m=-19.0, vd_m_s=1.0), on_ground=False)
    sim.step((0.0, 0.0, 0.0, 0.0))
    assert sim.state.on_ground and sim.state.body.d_m == pytest.approx(-20.0)


def test_tiles_follow_the_grid_block_and_its_sub_grids():
    here = (-353632610, 1491652299)
    info = grid_info(*here, 100)
    served = dict(tiles(info.block_lat_e7, info.block_lon_e7, 100, 0b101, lambda lat, lon: 584.0))
    assert sorted(served) == [0, 2] and served[0] == [584] * 16
    grid = TerrainGrid()
    block = grid.want(info, 100)
    for bit, data in tiles(block.lat_e7, block.lon_e7, 100, FULL_MASK, lambda lat, lon: 600.0):
        assert grid.store(block.lat_e7, block.lon_e7, 100, bit, data, 100)
    assert grid.statistics(100) == (0, 56)
    assert grid.height_amsl(*here, 100) == pytest.approx(600.0)
    assert not grid.store(block.lat_e7, block.lon_e7, 30, 0, [0] * 16, 100)  # another spacing: ignored
    assert not grid.store(block.lat_e7, block.lon_e7, 100, 56, [0] * 16, 100)  # past the last sub-grid


def _serve_until_loaded(v, height, rounds: int = 40) -> None:
    """The vehicle's TERRAIN_REQUESTs answered, one every 2 s as ArduCopter asks, until none is left."""
    codec = client_codec()
    for _ in range(rounds):
        v.run_until(v.time_s + 2.0)
        request = terrain_messages.terrain_request(v, codec)
        if request is None:
            return
        for data in answer(request, height, codec):
            terrain_messages.on_terrain_data(v, data)
    raise AssertionError("the vehicle kept asking for terrain")


def _with_terrain_mission(v) -> None:
    home = loc_of(v.position_global())
    wp = home.offset(200.0, 0.0)
    v.mission.replace(0, [MissionItem(22, 3, 0, 0, 0, 0, 0, 0, 10.0),
                          MissionItem(16, 10, 0, 0, 0, 0, wp.lat_e7, wp.lon_e7, 15.0)])


def test_a_served_database_reports_loaded_answers_checks_and_lets_a_terrain_mission_arm():
    v = ready_vehicle()
    _with_terrain_mission(v)
    assert v.set_mode(Guided.number) == Result.ACCEPTED
    assert v.arm() == Result.FAILED  # nothing served yet
    codec = client_codec()
    report = terrain_messages.terrain_report(v, codec)
    assert report.spacing == 0 and report.pending > 0 and report.loaded == 0
    home = loc_of(v.position_global())
    ground_m = v.home.alt_m
    wide = Hill(north_m=600.0, east_m=0.0, height_m=50.0, radius_m=400.0)  # broad against the 100 m grid
    height = hills_amsl(v.home, Terrain((wide,)))
    _serve_until_loaded(v, height)
    report = terrain_messages.terrain_report(v, codec)
    assert report.spacing == 100 and report.pending == 0 and report.loaded >= 56
    assert report.terrain_height == pytest.approx(ground_m, abs=1.0)  # served in whole metres
    assert abs(report.current_height) < 1.0  # on the ground
    top = home.offset(600.0, 0.0)
    checked = terrain_messages.terrain_check_reply(v, codec, dataclasses.make_dataclass("C", ["lat", "lon"])(top.lat_e7, top.lon_e7))
    assert checked.spacing == 100 and checked.terrain_height == pytest.approx(ground_m + 50.0, abs=5.0)
    v.run_until(v.time_s + 1.0)
    assert v.arm() == Result.ACCEPTED and v.armed
    far = home.offset(50_000.0, 0.0)  # not held: no height, and no extrapolation for a check
    checked = terrain_messages.terrain_check_reply(v, codec, dataclasses.make_dataclass("C", ["lat", "lon"])(far.lat_e7, far.lon_e7))
    assert checked.spacing == 0 and checked.terrain_height == 0.0
    assert checked.pending == report.pending + 56  # asked about, its block is now wanted (as AP_Terrain's)


def test_an_auto_leg_above_terrain_follows_the_hill():
    """Takeoff to 15 m, then a waypoint 15 m above terrain 500 m north across a 15 m hill: the
    vehicle climbs over the hill and down again, holding its height above the ground. (The hill
    is gentle enough that its slope at 10 m/s asks for less than WPNAV_SPEED_DN's 1.5 m/s: a
    steeper one is followed late, as ArduCopter's vertical limits make it too.)"""
    hill = Hill(north_m=250.0, east_m=0.0, height_m=15.0, radius_m=200.0)
    v = ready_vehicle({"TERRAIN_SPACING": 30}, sim=SimConfig(terrain=Terrain((hill,))))
    home = loc_of(v.home)
    wp = home.offset(500.0, 0.0)
    v.mission.replace(0, [MissionItem(22, 3, 0, 0, 0, 0, 0, 0, 15.0),
                          MissionItem(16, 10, 0, 0, 0, 0, wp.lat_e7, wp.lon_e7, 15.0)])
    _serve_until_loaded(v, hills_amsl(v.home, Terrain((hill,))))
    assert v.set_mode(Guided.number) == Result.ACCEPTED
    assert v.arm() == Result.ACCEPTED
    assert v.mission_start() == Result.ACCEPTED
    codec = client_codec()
    above = []
    while v.time_s < 120.0:
        v.run_until(v.time_s + 0.5)
        if v.time_s > 5.0 and v.time_s % 2.0 < 0.5:  # the leg needs the tiles ahead as it flies
            request = terrain_messages.terrain_request(v, codec)
            for data in ([] if request is None else answer(request, hills_amsl(v.home, Terrain((hill,))), codec)):
                terrain_messages.on_terrain_data(v, data)
        b = v.sim.state.body
        if 50.0 < b.n_m < 450.0:
            above.append(-b.d_m - hill.height_at(b.n_m, b.e_m))
        if b.n_m > 490.0:
            break
    assert len(above) > 40  # the leg was sampled over the hill
    assert max(abs(h - 15.0) for h in above) < 3.0, (min(above), max(above))


def test_with_a_rangefinder_the_leg_follows_the_ground_it_sees_and_needs_no_database():
    """WPNAV_RFND_USE (on by default) with a downward rangefinder: the terrain mission arms with no
    tiles served (ArduCopter's terrain_database_required) and the leg holds its height above what
    the rangefinder sees (the offset low-passed with SURFTRAK_TC)."""
    hill = Hill(north_m=250.0, east_m=0.0, height_m=15.0, radius_m=200.0)
    v = ready_vehicle({"RNGFND1_TYPE": 100, "RNGFND1_MAX": 40.0}, sim=SimConfig(terrain=Terrain((hill,))))
    wp = loc_of(v.home).offset(500.0, 0.0)
    v.mission.replace(0, [MissionItem(22, 3, 0, 0, 0, 0, 0, 0, 15.0),
                          MissionItem(16, 10, 0, 0, 0, 0, wp.lat_e7, wp.lon_e7, 15.0)])
    v.run_until(v.time_s + 1.0)
    assert v.set_mode(Guided.number) == Result.ACCEPTED
    assert v.arm() == Result.ACCEPTED
    assert v.mission_start() == Result.ACCEPTED
    above = []
    while v.time_s < 120.0 and v.sim.state.body.n_m < 490.0:
        v.run_until(v.time_s + 0.5)
        b = v.sim.state.body
        if 50.0 < b.n_m < 450.0:
            above.append(-b.d_m - hill.height_at(b.n_m, b.e_m))
    assert len(above) > 40
    assert max(abs(h - 15.0) for h in above) < 3.0, (min(above), max(above))


def test_the_fire_sensor_reads_from_its_height_above_the_hill():
    """The downward radiometric sensor's height is above the ground under it: over a 20 m hill,
    30 m above home's ground reads as 10 m above the fire would on the flat field."""
    hill = Hill(**HILL)
    flat, hilly = SimVehicle(SimConfig()), SimVehicle(SimConfig(terrain=Terrain((hill,))))
    for sim, d in ((flat, -10.0), (hilly, -30.0)):
        sim.state = sim.state._replace(body=BodyState(n_m=120.0, d_m=d), on_ground=False)
    assert hilly.read_temperature(0.0) == pytest.approx(flat.read_temperature(0.0))


def test_terrain_off_quiet_and_odd_inputs_answered_without_fault():
    v = ready_vehicle()
    codec = client_codec()
    Check = dataclasses.make_dataclass("Check", ["lat", "lon"])
    for lat, lon in ((900_000_000, 1_800_000_000), (-900_000_000, -1_800_000_000), (2**31 - 1, -(2**31))):
        assert terrain_messages.terrain_check_reply(v, codec, Check(lat, lon)).spacing == 0
    v.params.set("TERRAIN_SPACING", 0)  # no grid at all: nothing asked, nothing held
    v.run_until(v.time_s + 1.0)
    assert terrain_messages.terrain_request(v, codec) is None
    assert terrain_messages.terrain_report(v, codec).spacing == 0
    v.params.set("TERRAIN_SPACING", 100)
    v.params.set("TERRAIN_OPTIONS", 1)  # DisableDownload: reports, never asks
    v.run_until(v.time_s + 1.0)
    assert terrain_messages.terrain_request(v, codec) is None
    assert terrain_messages.terrain_report(v, codec).pending > 0
    v.params.set("TERRAIN_ENABLE", 0)  # off: neither
    assert terrain_messages.terrain_request(v, codec) is None and terrain_messages.terrain_report(v, codec) is None


@pytest.mark.parametrize("lat_e7, lon_e7, spacing, keeps", [
    (-353632610, 1491652300, 30, True), (-353632610, 1491652300, 100, True),
    (-359995000, 1499995000, 30, False),  # beside a whole degree: points in the next degree's grid
    (795000000, 105000000, 30, True)])  # far north, where moving north changes the east scale most
def test_the_blocks_kept_around_a_wandering_vehicle_are_those_worked_out_afresh(lat_e7, lon_e7, spacing, keeps):
    # The grid keeps the 9 surrounding blocks while the vehicle stays inside what keeps them; a
    # walk of steps up to 4 m over block edges must want exactly the blocks a fresh look finds.
    rng = random.Random(7)
    grid, kept = TerrainGrid(), 0
    for _ in range(5000):
        lat_e7 += rng.randint(-400, 400)
        lon_e7 += rng.randint(-400, 400)
        before = grid._around
        grid.want_around(Loc(lat_e7, lon_e7, 0), None, [], spacing)
        kept += grid._around is before
        assert grid._around.corners == blocks_around(lat_e7, lon_e7, spacing)
    assert (kept > 1000) == keeps  # kept and used, but where the next degree's grid is near

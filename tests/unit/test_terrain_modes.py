"""Terrain outside AUTO (measured: tests/parity/recorded/terrain_modes.json): RTL above terrain
(RTL_ALT_TYPE 1) and its pre-arm checks, GUIDED's targets in a terrain frame, and the terrain
failsafe when a mode that needs the terrain has none."""
from __future__ import annotations

from firefly.autopilot.location import loc_of
from firefly.autopilot.mavlink import terrain as terrain_messages
from firefly.autopilot.mission import MissionItem
from firefly.autopilot.modes import Guided
from firefly.autopilot.modes.numbers import ModeNumber
from firefly.autopilot.results import Result
from firefly.groundstation.terrain_tiles import answer, hills_amsl
from firefly.sim.terrain import Hill, Terrain
from firefly.sim.vehicle import SimConfig

from ._util import client_codec, ready_vehicle

HILL = Hill(north_m=150.0, east_m=0.0, height_m=12.0, radius_m=100.0)
WORLD = Terrain((HILL,))


def said(v) -> list[str]:
    return [text for _, text in v.events]


def _serve(v) -> None:
    """Answer the vehicle's TERRAIN_REQUEST, if it has one."""
    codec = client_codec()
    request = terrain_messages.terrain_request(v, codec)
    for data in ([] if request is None else answer(request, hills_amsl(v.home, WORLD), codec)):
        terrain_messages.on_terrain_data(v, data)


def _loaded(params=None, world=WORLD):
    v = ready_vehicle({"TERRAIN_SPACING": 30, "RTL_ALT_TYPE": 1, **(params or {})}, sim=SimConfig(terrain=world))
    for _ in range(40):
        v.run_until(v.time_s + 2.0)
        _serve(v)
    return v


def _fly(v, until, limit_s: float, serve: bool = True) -> list[float]:
    """Run until `until(body)`; the heights above the hill while over it."""
    above, end = [], v.time_s + limit_s
    while v.time_s < end:
        v.run_until(v.time_s + 0.5)
        if serve and v.time_s % 2.0 < 0.5:
            _serve(v)
        b = v.sim.state.body
        if 60.0 < b.n_m < 240.0:
            above.append(-b.d_m - HILL.height_at(b.n_m, b.e_m))
        if until(b):
            return above
    raise AssertionError(f"not there after {limit_s} s: {v.sim.state.body}")


def test_rtl_above_terrain_needs_a_terrain_source_and_its_data_to_arm():
    v = ready_vehicle({"RTL_ALT_TYPE": 1, "TERRAIN_ENABLE": 0})
    assert v.set_mode(Guided.number) == Result.ACCEPTED
    assert v.arm() == Result.FAILED
    assert "Arm: RTL_ALT_TYPE is above-terrain but no terrain data" in said(v)
    v.params.set("TERRAIN_ENABLE", 1)
    assert v.arm() == Result.FAILED and "Arm: waiting for terrain data" in said(v)
    ranged = ready_vehicle({"RTL_ALT_TYPE": 1, "RNGFND1_TYPE": 100, "RNGFND1_MAX": 10.0})  # RTL_ALT 15 m
    ranged.run_until(ranged.time_s + 1.0)
    assert ranged.set_mode(Guided.number) == Result.ACCEPTED
    assert ranged.arm() == Result.FAILED
    assert "Arm: RTL_ALT_TYPE is above-terrain but RTL_ALT (in cm) above RNGFND_MAX (in metres)" in said(ranged)
    assert _loaded().arm() == Result.ACCEPTED


def test_guided_terrain_target_then_rtl_above_terrain_follow_the_hill():
    v = _loaded()
    assert v.set_mode(Guided.number) == Result.ACCEPTED and v.arm() == Result.ACCEPTED
    assert v.takeoff(15.0) == Result.ACCEPTED
    v.run_until(v.time_s + 12.0)
    far = loc_of(v.home).offset(300.0, 0.0)
    n, e, _ = v.ned_of(far.lat_e7 * 1e-7, far.lon_e7 * 1e-7, v.origin.alt_m)
    assert v.guided_target((n, e, -15.0), None, None, terrain=True) == Result.ACCEPTED
    above = _fly(v, lambda b: b.n_m > 298.0 and abs(b.vn_m_s) < 0.5, 80.0)
    assert len(above) > 20 and max(abs(h - 15.0) for h in above) < 2.5, (min(above), max(above))
    assert v.guided_goto(n, e, -25.0, terrain=True) == Result.ACCEPTED
    v.run_until(v.time_s + 10.0)
    assert v.set_mode(ModeNumber.RTL) == Result.ACCEPTED
    above = _fly(v, lambda b: b.n_m < 20.0, 80.0)
    # back at 25 m above the terrain (RTL_ALT 15 m, but not below where it was): over the hill too
    assert len(above) > 20 and max(abs(h - 25.0) for h in above) < 2.5, (min(above), max(above))


def test_no_terrain_in_guided_is_the_terrain_failsafe_and_rtl_goes_home_above_it():
    v = _loaded()
    assert v.set_mode(Guided.number) == Result.ACCEPTED and v.arm() == Result.ACCEPTED
    assert v.takeoff(15.0) == Result.ACCEPTED
    v.run_until(v.time_s + 12.0)
    b = v.sim.state.body
    assert v.guided_target((b.n_m + 20.0, b.e_m, -15.0), None, None, terrain=True) == Result.ACCEPTED
    v.run_until(v.time_s + 2.0)
    v.params.set("TERRAIN_ENABLE", 0)
    v.run_until(v.time_s + 1.0)
    assert "Failsafe: Terrain data missing" in said(v)
    assert v.mode.number == ModeNumber.RTL
    # no terrain now: a terrain target is refused and stops the vehicle
    assert v.set_mode(Guided.number) == Result.ACCEPTED
    assert v.guided_target((b.n_m, b.e_m, -15.0), None, None, terrain=True) == Result.DENIED


def test_rtl_without_terrain_data_says_so_and_returns_above_home():
    for terrain_enable in (0, 1):  # off, or on with no tile served
        v = ready_vehicle({"RTL_ALT_TYPE": 1, "ARMING_CHECK": 0})
        assert v.set_mode(Guided.number) == Result.ACCEPTED and v.arm() == Result.ACCEPTED
        assert v.takeoff(10.0) == Result.ACCEPTED
        v.run_until(v.time_s + 10.0)
        v.params.set("TERRAIN_ENABLE", terrain_enable)
        assert v.set_mode(ModeNumber.RTL) == Result.ACCEPTED
        assert "RTL: no terrain data, using alt-above-home" in said(v)
        v.run_until(v.time_s + 5.0)
        assert v.mode.number == ModeNumber.RTL and not v.failsafes.terrain


def test_with_no_tile_served_a_terrain_target_is_taken_above_0_m_amsl():
    """AP_Terrain extrapolates from its last height, 0 before any: ArduCopter takes the target
    (measured: DO_REPOSITION ACCEPTED) as that far above sea level."""
    v = ready_vehicle()
    assert v.set_mode(Guided.number) == Result.ACCEPTED
    assert v.terrain_offset_m() == -v.origin.alt_m
    assert v.guided_target((0.0, 0.0, -15.0), None, None, terrain=True) == Result.ACCEPTED


def test_an_rtl_leg_without_terrain_for_5_s_is_the_failsafe_and_restarts_above_home():
    v = _loaded()
    assert v.set_mode(Guided.number) == Result.ACCEPTED and v.arm() == Result.ACCEPTED
    assert v.takeoff(25.0) == Result.ACCEPTED
    v.run_until(v.time_s + 15.0)
    assert v.guided_goto(120.0, 0.0, v.home_ned[2] - 25.0) == Result.ACCEPTED
    _fly(v, lambda b: b.n_m > 118.0 and abs(b.vn_m_s) < 0.5, 40.0)
    assert v.set_mode(ModeNumber.RTL) == Result.ACCEPTED
    v.run_until(v.time_s + 5.0)
    v.params.set("TERRAIN_ENABLE", 0)
    n0 = v.sim.state.body.n_m
    v.run_until(v.time_s + 4.5)
    assert "Failsafe: Terrain data missing" not in said(v)
    stopped_n = v.sim.state.body.n_m
    assert abs(v.sim.state.body.vn_m_s) < 1.0 and n0 - stopped_n < 20.0  # its target held: it stopped
    v.run_until(v.time_s + 1.5)
    assert said(v)[-2:] == ["Failsafe: Terrain data missing", "Restarting RTL - Terrain data missing"]
    assert v.mode.number == ModeNumber.RTL and not v.failsafes.terrain
    v.run_until(v.time_s + 5.0)
    assert v.sim.state.body.n_m < stopped_n - 10.0  # home again, above home


def test_an_auto_terrain_leg_without_terrain_for_5_s_goes_to_rtl():
    v = _loaded()
    home = loc_of(v.home)
    wp = home.offset(300.0, 0.0)
    v.mission.replace(0, [MissionItem(22, 3, 0, 0, 0, 0, 0, 0, 15.0),
                          MissionItem(16, 10, 0, 0, 0, 0, wp.lat_e7, wp.lon_e7, 15.0)])
    assert v.set_mode(Guided.number) == Result.ACCEPTED and v.arm() == Result.ACCEPTED
    assert v.mission_start() == Result.ACCEPTED
    _fly(v, lambda b: b.n_m > 60.0, 60.0)
    v.params.set("TERRAIN_ENABLE", 0)
    v.run_until(v.time_s + 4.5)
    assert v.mode.number == ModeNumber.AUTO and "Failsafe: Terrain data missing" not in said(v)
    v.run_until(v.time_s + 1.0)
    assert "Failsafe: Terrain data missing" in said(v) and v.mode.number == ModeNumber.RTL

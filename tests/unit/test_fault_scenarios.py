"""Faults from a scenario file: the [faults] table (from the start), [script] "param" steps (at a
sim time), the wind of [wind] as SIM_WIND_*; every mistake one line naming table and key."""
from __future__ import annotations

import pytest

from firefly.autopilot.cli import main as cli
from firefly.autopilot.cli.script import Script, ScriptError, parse_steps
from firefly.autopilot.cli.scenario import ScenarioError, scenario_from_dict
from firefly.autopilot.vehicle import Vehicle, VehicleConfig
from ._util import no_sockets


def one_line_error(data: dict) -> str:
    with pytest.raises(ScenarioError) as info:
        scenario_from_dict(data, "test.toml")
    message = str(info.value)
    assert "\n" not in message and message.startswith("test.toml")
    return message


def test_faults_table_is_read_and_checked_against_the_parameter_table():
    sc = scenario_from_dict({"faults": {"SIM_ENGINE_MUL": 0.7, "SIM_GPS_NUMSATS": 5, "SIM_LINK_LOSS": 10}})
    assert sc.faults == {"SIM_ENGINE_MUL": 0.7, "SIM_GPS_NUMSATS": 5.0, "SIM_LINK_LOSS": 10.0}


@pytest.mark.parametrize("faults,words", [
    ({"SIM_ENGINE_MULT": 0.5}, ["[faults].SIM_ENGINE_MULT", "unknown fault", "SIM_ENGINE_MUL"]),
    ({"RTL_ALT": 2000}, ["[faults].RTL_ALT", "unknown fault"]),  # only SIM_* belong here
    ({"SIM_ENGINE_MUL": 1.5}, ["[faults].SIM_ENGINE_MUL", "out of range 0..1"]),
    ({"SIM_GPS_DISABLE": True}, ["[faults].SIM_GPS_DISABLE", "expected a number"]),
    ({"SIM_WIND_SPD": 5.0}, ["[faults].SIM_WIND_SPD", "[wind].speed_m_s"]),
])
def test_faults_mistakes_name_the_table_and_key(faults, words):
    message = one_line_error({"faults": faults})
    for word in words:
        assert word in message


def test_faults_must_be_a_table():
    assert "[faults] must be a table" in one_line_error({"faults": [1, 2]})


def test_params_table_is_read_and_checked_against_the_parameter_table():
    sc = scenario_from_dict({"params": {"EK3_DRAG_BCOEF_X": 9.5, "CAM1_TYPE": 1}})
    assert sc.params == {"EK3_DRAG_BCOEF_X": 9.5, "CAM1_TYPE": 1.0}


@pytest.mark.parametrize("params,words", [
    ({"EK3_DRAG_BCOEF": 9.5}, ["[params].EK3_DRAG_BCOEF", "unknown parameter"]),
    ({"SIM_WIND_SPD": 3.0}, ["[params].SIM_WIND_SPD", "[faults]"]),
    ({"CAM1_TYPE": "servo"}, ["[params].CAM1_TYPE", "expected a number"]),
    ({"WPNAV_SPEED": 5}, ["[params].WPNAV_SPEED", "out of range"]),
])
def test_params_mistakes_name_the_table_and_key(params, words):
    message = one_line_error({"params": params})
    for word in words:
        assert word in message


def test_a_wind_the_parameters_cannot_hold_is_refused():
    assert "[wind].speed_m_s" in one_line_error({"wind": {"speed_m_s": -3.0}})


def test_script_param_steps_set_a_parameter_at_their_time():
    steps = parse_steps([[2.0, "param", "SIM_GPS_DISABLE", 1], [0.5, "mode", 4]], "test.toml")
    assert steps[1] == (2.0, "param", ("SIM_GPS_DISABLE", 1.0))
    v = Vehicle(VehicleConfig())
    v.script = Script(steps)
    v.run_until(1.9)
    assert v.has_position()
    v.run_until(2.2)
    assert v.params["SIM_GPS_DISABLE"] == 1 and v.gps.fix_type < 3
    assert (2.0, "param", 0) in v.script.results


def test_script_goto_is_in_the_vehicles_own_local_frame():
    """Vehicle k of a --count process runs the same script: its goto is from its own start."""
    steps = parse_steps([[0.5, "mode", 4], [0.5, "arm"], [1.0, "takeoff", 5], [8.0, "goto", 10, 0, 5]], "test.toml")
    v = Vehicle(VehicleConfig(offset_ne_m=(3.0, 5.0)))
    v.script = Script(steps)
    v.run_until(8.2)
    assert v.mode.target_ne == (13.0, 5.0)


@pytest.mark.parametrize("step,words", [
    ([1.0, "param", "NO_SUCH", 1], ["steps[0]", "unknown parameter NO_SUCH"]),
    ([1.0, "param", "SIM_ENGINE_MUL", 3], ["steps[0]", "out of range"]),
    ([1.0, "param", 5, 1], ["steps[0]", "param takes a parameter name and a number"]),
    ([1.0, "param", "SIM_ENGINE_MUL"], ["steps[0]", "param takes"]),
])
def test_script_param_mistakes_are_found_when_the_file_is_read(step, words):
    with pytest.raises(ScriptError) as info:
        parse_steps([step], "test.toml")
    for word in words:
        assert word in str(info.value)


def test_the_command_line_flies_the_scenario_faults(monkeypatch, tmp_path):
    no_sockets(monkeypatch)
    path = tmp_path / "faulty.toml"
    path.write_text("[wind]\nspeed_m_s = 5.0\n[faults]\nSIM_GPS_DISABLE = 1\nSIM_LINK_LOSS = 20\n")
    node, _ = cli.build(cli.build_parser().parse_args(["--scenario", str(path), "--state-dir", str(tmp_path)]))[0]
    params = node.vehicle.params
    assert (params["SIM_GPS_DISABLE"], params["SIM_LINK_LOSS"], params["SIM_WIND_SPD"]) == (1, 20, 5.0)
    node.vehicle.run_until(0.5)
    assert not node.vehicle.has_position()
    assert node.link_faults.active

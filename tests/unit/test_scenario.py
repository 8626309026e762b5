"""Scenario files and the command line: every mistake is one ScenarioError/CliError line naming
what is wrong. No sockets: the UDP endpoint is replaced by a stand-in."""
from __future__ import annotations

import math
from pathlib import Path

import pytest

from firefly.autopilot.cli import main as cli
from firefly.autopilot.cli.scenario import (DEFAULT_HOME, Scenario, ScenarioError, load_scenario, parse_home,
                                scenario_from_dict)
from firefly.sim.airframe import Airframe

from ._util import no_sockets as stand_ins


def one_line_error(data: dict) -> str:
    with pytest.raises(ScenarioError) as info:
        scenario_from_dict(data, "test.toml")
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith("test.toml")
    return message


# ----- scenario_from_dict -----------------------------------------------------------------------
def test_empty_scenario_is_the_default():
    sc = scenario_from_dict({})
    default = Scenario()
    assert sc.home == default.home
    assert (sc.home.lat_deg, sc.home.lon_deg, sc.home.alt_m) == DEFAULT_HOME[:3]
    assert sc.seed == 0
    assert sc.sim.airframe == Airframe()
    assert sc.sim.physics_rate_hz == 400


def test_full_scenario_is_applied():
    sc = scenario_from_dict({
        "seed": 42,
        "home": {"lat": 48.0, "lon": 2.0, "alt": 100, "yaw": 90},
        "airframe": {"mass_kg": 2.0, "battery_cells": 6},
        "wind": {"speed_m_s": 3.0, "from_direction_deg": 270.0},
        "noise": {"gps_horizontal_m": 0.0},
        "sim": {"physics_rate_hz": 800},
    })
    assert sc.seed == 42 and sc.sim.seed == 42
    assert (sc.home.lat_deg, sc.home.lon_deg, sc.home.alt_m) == (48.0, 2.0, 100.0)
    assert sc.home_yaw_deg == 90
    assert sc.sim.airframe.mass_kg == 2.0 and sc.sim.airframe.battery_cells == 6
    assert sc.sim.wind.speed_m_s == 3.0
    assert sc.sim.noise.gps_horizontal_m == 0.0
    assert sc.sim.physics_rate_hz == 800


def test_unknown_top_level_key_is_named():
    message = one_line_error({"windd": {}})
    assert "'windd'" in message and "unknown key" in message


@pytest.mark.parametrize("table,key", [("airframe", "mass"), ("wind", "speed"), ("noise", "gps"),
                                       ("home", "altitude"), ("sim", "rate")])
def test_unknown_key_in_a_table_is_named(table, key):
    base = {"home": {"lat": 1.0, "lon": 2.0, "alt": 3.0}} if table == "home" else {}
    data = {**base, table: {**base.get(table, {}), key: 1.0}}
    message = one_line_error(data)
    assert f"'{key}'" in message and table in message


@pytest.mark.parametrize("data,key", [
    ({"wind": {"speed_m_s": "fast"}}, "speed_m_s"),
    ({"airframe": {"mass_kg": True}}, "mass_kg"),
    ({"airframe": {"mass_kg": [1.5]}}, "mass_kg"),
    ({"home": {"lat": "north", "lon": 2.0, "alt": 3.0}}, "lat"),
    ({"seed": "abc"}, "seed"),
    ({"noise": {"baro_m": math.nan}}, "baro_m"),
])
def test_non_numbers_are_named(data, key):
    message = one_line_error(data)
    assert key in message


@pytest.mark.parametrize("data,key", [
    ({"seed": 1.5}, "seed"),
    ({"airframe": {"battery_cells": 4.0}}, "battery_cells"),
    ({"sim": {"physics_rate_hz": 400.0}}, "physics_rate_hz"),
])
def test_integers_are_required_where_the_field_is_an_integer(data, key):
    message = one_line_error(data)
    assert key in message and "integer" in message


@pytest.mark.parametrize("missing", ["lat", "lon", "alt"])
def test_missing_home_coordinate_is_named(missing):
    home = {"lat": 1.0, "lon": 2.0, "alt": 3.0}
    del home[missing]
    message = one_line_error({"home": home})
    assert f"missing '{missing}'" in message


def test_home_out_of_range_is_reported():
    message = one_line_error({"home": {"lat": 91.0, "lon": 2.0, "alt": 3.0}})
    assert "latitude" in message


def test_table_that_is_not_a_table():
    assert "[wind]" in one_line_error({"wind": 5})


@pytest.mark.parametrize("field, value", [("mass_kg", -1.0), ("battery_internal_resistance_ohm", 0.0)])
def test_airframe_that_cannot_fly_names_the_field(field, value):
    """A pack without internal resistance is refused too: the sag model divides by it."""
    message = one_line_error({"airframe": {field: value}})
    assert field in message and "[airframe]" in message


@pytest.mark.parametrize("rate", [50, 150, 0, -400])
def test_physics_rate_must_be_a_multiple_of_100(rate):
    assert "physics_rate_hz" in one_line_error({"sim": {"physics_rate_hz": rate}})


@pytest.mark.parametrize("data", [{"seed": 10 ** 400}, {"airframe": {"mass_kg": 10 ** 400}}])
def test_absurdly_large_integer_is_a_scenario_error(data):
    one_line_error(data)


# ----- load_scenario ------------------------------------------------------------------------------
def test_load_scenario_reads_a_toml_file(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text('seed = 7\n[home]\nlat = 10.5\nlon = -20.25\nalt = 30\n[wind]\nspeed_m_s = 2\n')
    sc = load_scenario(path)
    assert sc.seed == 7
    assert (sc.home.lat_deg, sc.home.lon_deg, sc.home.alt_m) == (10.5, -20.25, 30.0)
    assert sc.sim.wind.speed_m_s == 2


def test_bad_toml_is_one_line_naming_the_file(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text("[home\nlat = \n")
    with pytest.raises(ScenarioError) as info:
        load_scenario(path)
    message = str(info.value)
    assert "\n" not in message
    assert str(path) in message and "TOML" in message


def test_missing_file_is_one_line_naming_the_file(tmp_path):
    path = tmp_path / "nope.toml"
    with pytest.raises(ScenarioError) as info:
        load_scenario(path)
    message = str(info.value)
    assert "\n" not in message and str(path) in message and "no such file" in message


def test_errors_inside_a_file_name_the_file_and_key(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text("[airframe]\nmass_kg = \"heavy\"\n")
    with pytest.raises(ScenarioError) as info:
        load_scenario(path)
    message = str(info.value)
    assert str(path) in message and "mass_kg" in message and "\n" not in message


# ----- --home -------------------------------------------------------------------------------------
def test_parse_home():
    home, yaw = parse_home("48.5,2.25,120")
    assert (home.lat_deg, home.lon_deg, home.alt_m, yaw) == (48.5, 2.25, 120.0, 0.0)
    assert parse_home("1,2,3,45")[1] == 45.0


@pytest.mark.parametrize("text", ["1,2", "a,b,c", "1,2,3,4,5", "100,0,0", "0,200,0", "0,0,nan",
                                  "0,0,0,inf"])
def test_parse_home_errors_are_one_line(text):
    with pytest.raises(ScenarioError) as info:
        parse_home(text)
    assert "\n" not in str(info.value) and "--home" in str(info.value)


# ----- command line (no sockets: the endpoint is a stand-in) ----------------------------------------
@pytest.fixture
def no_sockets(monkeypatch):
    stand_ins(monkeypatch)


def build(*argv):
    """The first (only) vehicle of a one-vehicle build: (node, outs)."""
    return cli.build(cli.build_parser().parse_args(list(argv)))[0]


def test_parse_udp():
    assert cli.parse_udp("udp:127.0.0.1:14550", "--out") == ("127.0.0.1", 14550)
    assert cli.parse_udp("10.0.0.2:5760", "--out") == ("10.0.0.2", 5760)
    for bad in ("udp:127.0.0.1", "udp::14550", "udp:host:port", "udp:host:70000"):
        with pytest.raises(cli.CliError, match="--out"):
            cli.parse_udp(bad, "--out")


def test_parse_speedup():
    assert cli.parse_speedup("10") == 10.0
    assert cli.parse_speedup("inf") == math.inf
    for bad in ("0", "-1", "nan", "fast"):
        with pytest.raises(cli.CliError, match="--speedup"):
            cli.parse_speedup(bad)


@pytest.mark.parametrize("speedup,reads", [("1", 1.0), ("0.5", 0.5), ("37", 37.0), ("inf", cli.FLAT_OUT_SPEEDUP)])
def test_sim_speedup_reads_the_process_speedup(no_sockets, tmp_path, speedup, reads):
    """As ArduPilot's SITL keeps its --speedup in SIM_SPEEDUP; flat out, a finite stand-in."""
    node, _ = build("--speedup", speedup, "--state-dir", str(tmp_path))
    assert node.vehicle.params["SIM_SPEEDUP"] == reads


def test_unknown_flag_is_a_cli_error_not_an_exit():
    with pytest.raises(cli.CliError):
        cli.build_parser().parse_args(["--bogus"])


def test_instance_sets_system_id_ports_and_state_dir(no_sockets, tmp_path):
    node, outs = build("--instance", "2", "--state-dir", str(tmp_path))
    assert node.vehicle.system_id == 3
    assert node.session.system_id == 3
    assert node.endpoint.udp.bind == ("0.0.0.0", 5780)
    assert [s.bind for s in node.endpoint.tcp_servers] == [("0.0.0.0", 5780)]  # SERIAL0, as SITL's -I2
    assert outs == [("127.0.0.1", 14570), ("127.0.0.1", 14560)]
    assert node.vehicle.params.path == tmp_path / "instance-2" / "params.json"


def test_scenario_home_and_seed_override(no_sockets, tmp_path):
    path = tmp_path / "s.toml"
    path.write_text("seed = 3\n[home]\nlat = 10\nlon = 20\nalt = 30\n")
    node, _ = build("--scenario", str(path), "--state-dir", str(tmp_path), "--seed", "9")
    assert node.vehicle.config.sim.seed == 9
    assert node.vehicle.origin.lat_deg == 10.0
    node, _ = build("--scenario", str(path), "--state-dir", str(tmp_path), "--home", "1,2,3,90")
    assert node.vehicle.origin.lat_deg == 1.0
    assert node.vehicle.config.home_yaw_deg == 90.0


@pytest.mark.parametrize("argv", [("--instance", "5000"), ("--scenario", "/nonexistent/x.toml"),
                                  ("--home", "0,0"), ("--out", "nowhere")])
def test_build_errors_are_cli_or_scenario_errors(no_sockets, tmp_path, argv):
    from firefly.autopilot.cli.scenario import ScenarioError as SE
    with pytest.raises((cli.CliError, SE)) as info:
        build(*argv, "--state-dir", str(tmp_path))
    assert "\n" not in str(info.value)


@pytest.mark.parametrize("rate", [500, 1000])
def test_every_scenario_physics_rate_builds_a_vehicle(no_sockets, tmp_path, rate):
    path = tmp_path / "s.toml"
    path.write_text(f"[sim]\nphysics_rate_hz = {rate}\n")
    try:
        node, _ = build("--scenario", str(path), "--state-dir", str(tmp_path))
    except (cli.CliError, ScenarioError):
        return  # refusing with a one-line error is also acceptable
    node.vehicle.run_until(0.1)
    assert node.vehicle.sim.steps == pytest.approx(0.1 * rate, abs=1)


def test_every_multiple_of_400_builds(no_sockets, tmp_path):
    for rate in (400, 800, 1200):
        path = tmp_path / f"s{rate}.toml"
        path.write_text(f"[sim]\nphysics_rate_hz = {rate}\n")
        node, _ = build("--scenario", str(path), "--state-dir", str(tmp_path))
        assert node.vehicle.sim.dt == pytest.approx(1.0 / rate)


def test_scenario_path_type(tmp_path):
    # load_scenario accepts str as well as Path (the CLI passes a Path).
    path = tmp_path / "s.toml"
    path.write_text("seed = 1\n")
    assert load_scenario(Path(str(path))).seed == load_scenario(str(path)).seed == 1


def test_default_scenario_file_matches_the_built_in_defaults():
    """`autopilot` without --scenario and scenarios/default.toml describe the same world."""
    from pathlib import Path

    from firefly.autopilot.cli.scenario import Scenario, load_scenario
    from_file = load_scenario(Path(__file__).resolve().parents[2] / "scenarios" / "default.toml")
    built_in = Scenario()
    assert from_file.world == built_in.world
    assert from_file.home == built_in.home


def test_a_plume_rise_speed_leans_the_plume_with_the_wind():
    sc = scenario_from_dict({"wind": {"speed_m_s": 4.0, "from_direction_deg": 270.0},
                             "world": {"plume_rise_m_s": 5.0}})
    assert sc.world.wind_tilt == pytest.approx(0.8) and sc.world.wind_to_deg == pytest.approx(90.0)
    calm = scenario_from_dict({"world": {"plume_rise_m_s": 5.0}})
    assert calm.world.wind_tilt == 0.0


def test_a_plume_leaned_both_ways_is_refused():
    with pytest.raises(ScenarioError, match="plume_rise_m_s leans the plume with \\[wind\\]"):
        scenario_from_dict({"world": {"plume_rise_m_s": 5.0, "wind_tilt": 0.5}}, "sc")


@pytest.mark.parametrize("path", sorted((Path(__file__).parents[2] / "scenarios").glob("*.toml")), ids=lambda p: p.name)
def test_every_shipped_scenario_loads(path):
    sc = load_scenario(path)  # the autopilot's reading, which includes the world's
    sc.world.validate()


def test_a_thermal_camera_table_fits_one_and_bad_values_are_named():
    from firefly.autopilot.cli.scenario import scenario_from_dict
    assert scenario_from_dict({}).thermal_camera is None
    spec = scenario_from_dict({"thermal_camera": {"hfov_deg": 45.0}}).thermal_camera
    assert spec is not None and spec.hfov_deg == 45.0 and spec.width_px == 160
    for table, key in (({"width_px": 0}, "width_px"), ({"hfov_deg": 200.0}, "hfov_deg"),
                       ({"width_px": 1.5}, "width_px"), ({"lens": 1}, "lens"), ({"netd_k": math.nan}, "netd_k")):
        with pytest.raises(ScenarioError) as err:
            scenario_from_dict(table and {"thermal_camera": table}, "s.toml")
        text = str(err.value)
        assert "\n" not in text and "[thermal_camera]" in text and key in text, text


def test_the_thermal_camera_option_fits_the_default_camera(tmp_path, no_sockets):
    node, _ = build("--thermal-camera", "--state-dir", str(tmp_path))
    component = node.session.camera_component
    assert component is not None and component.camera.spec.width_px == 160
    node, _ = build("--state-dir", str(tmp_path))
    assert node.session.camera_component is None  # off unless asked for


def test_the_thermal_video_port_from_the_option_or_the_scenario(tmp_path, no_sockets):
    def uri(*argv):
        video = build(*argv, "--state-dir", str(tmp_path))[0].session.camera_component.video
        return None if video is None else video.uri
    assert uri("--thermal-camera") == "udp://127.0.0.1:5600"
    assert uri("--thermal-camera", "--instance", "2") == "udp://127.0.0.1:5620"  # +10 per instance
    assert uri("--thermal-camera", "--video-port", "6000") == "udp://127.0.0.1:6000"
    assert uri("--thermal-camera", "--video-port", "0") is None  # the camera without its video
    scenario = tmp_path / "video.toml"
    scenario.write_text("[thermal_camera]\nvideo_port = 7000\n")
    assert uri("--scenario", str(scenario)) == "udp://127.0.0.1:7000"
    assert uri("--scenario", str(scenario), "--video-port", "7100") == "udp://127.0.0.1:7100"  # the option wins
    with pytest.raises(cli.CliError, match="--video-port: 65535 \\+ 10 per instance"):
        build("--thermal-camera", "--video-port", "65535", "--instance", "1", "--state-dir", str(tmp_path))


@pytest.mark.parametrize("value", [-1, 70000, 1.5, "5600", True])
def test_a_bad_video_port_is_refused_in_one_line_naming_the_key(value):
    from firefly.autopilot.cli.scenario import scenario_from_dict
    with pytest.raises(ScenarioError) as err:
        scenario_from_dict({"thermal_camera": {"video_port": value}}, "s.toml")
    text = str(err.value)
    assert "\n" not in text and "s.toml: [thermal_camera].video_port" in text, text


@pytest.mark.parametrize("text", ["-1", "65536", "abc", "1.5"])
def test_a_bad_video_port_option_is_refused(text):
    with pytest.raises(cli.CliError, match="^argument --video-port: expected a UDP port 1..65535 .*[^\n]$"):
        cli.build_parser().parse_args(["--video-port", text])

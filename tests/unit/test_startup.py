"""The realistic start-up (autopilot/startup.py): ArduCopter's stages from power-on, on a real
vehicle in sim time; its scenario table and command-line flag."""
from __future__ import annotations

import pytest

from firefly.autopilot.cli import main as cli
from firefly.autopilot.cli.scenario import ScenarioError, scenario_from_dict
from firefly.autopilot.mavlink import telemetry
from firefly.autopilot.modes import ModeNumber
from firefly.autopilot.results import Result
from firefly.autopilot.startup import StartupTimeline
from firefly.autopilot.vehicle import Vehicle, VehicleConfig

from ._util import client_codec, mav, no_sockets

CODEC = client_codec()


def refusals(v, mode: int) -> list[str]:
    v.set_mode(mode)
    v.drain_events()
    assert v.arm() == Result.FAILED and not v.armed
    return [text for _, text in v.drain_events()]


def test_a_realistic_start_goes_through_arducopters_stages_in_order():
    tl = StartupTimeline()
    v = Vehicle(VehicleConfig(startup=tl))
    # from power-on, before the first GPS sample: the telemetry of the first tick says no fix
    assert v.gps.fix_type == 0 and telemetry.gps_raw_int(v, CODEC).fix_type == 0
    v.run_until(1.0)
    assert refusals(v, ModeNumber.STABILIZE) == ["Arm: System not initialised"]
    assert telemetry.ekf_status_report(v, CODEC).flags == mav.EKF_UNINITIALIZED
    v.run_until(tl.ekf_started_s - 0.5)
    assert refusals(v, ModeNumber.STABILIZE) == ["Arm: Accels inconsistent", "Arm: EKF attitude is bad",
                                                 "Arm: AHRS: not using configured AHRS type"]
    v.run_until(tl.gps_fix_s - 0.5)
    assert v.gps.fix_type == 0 and v.home is None
    assert refusals(v, ModeNumber.STABILIZE) == ["Arm: Accels inconsistent"]
    assert refusals(v, ModeNumber.GUIDED) == ["Arm: Accels inconsistent", "Arm: AHRS: waiting for home"]
    v.run_until(tl.gps_fix_s + 0.5)
    assert v.gps.fix_type >= 3 and v.home is None and not v.has_position()
    v.run_until(tl.origin_s + 0.5)
    assert v.home is not None and not v.has_position()
    assert refusals(v, ModeNumber.STABILIZE) == ["Arm: Gyros inconsistent"]
    assert refusals(v, ModeNumber.GUIDED) == ["Arm: Gyros inconsistent", "Arm: Need Position Estimate"]
    v.run_until(tl.gyros_consistent_s + 0.5)
    assert refusals(v, ModeNumber.GUIDED) == ["Arm: Need Position Estimate"]
    assert not telemetry.ekf_status_report(v, CODEC).flags & mav.EKF_POS_HORIZ_ABS
    v.set_mode(ModeNumber.STABILIZE)
    assert v.arm() == Result.ACCEPTED
    v.disarm()
    v.run_until(tl.gps_in_use_s + 0.5)
    assert v.has_position() and v.is_armable()
    assert telemetry.ekf_status_report(v, CODEC).flags & mav.EKF_POS_HORIZ_ABS
    assert v.set_mode(ModeNumber.GUIDED) == Result.ACCEPTED and v.arm() == Result.ACCEPTED


def test_the_start_up_is_announced_once_each_in_order():
    tl = StartupTimeline(gps_in_use_s=30.0)
    v = Vehicle(VehicleConfig(startup=tl))
    v.run_until(31.0)
    said = [text for _, text in v.drain_events()]
    assert said[:3] == ["Barometer 1 calibration complete", "Barometer 2 calibration complete", "ArduPilot Ready"]
    assert said[-2:] == ["EKF3 IMU0 is using GPS", "EKF3 IMU1 is using GPS"]
    assert len(said) == len(set(said))
    v.run_until(40.0)
    assert v.drain_events() == []


def test_the_default_is_armable_at_once():
    v = Vehicle(VehicleConfig())
    v.run_until(0.1)
    assert v.has_position() and v.home is not None and v.is_armable()


def test_the_startup_table_sets_stages_and_refuses_mistakes():
    assert scenario_from_dict({"startup": {}}).startup == StartupTimeline()
    assert scenario_from_dict({"startup": {"gps_in_use_s": 25}}).startup.gps_in_use_s == 25.0
    assert scenario_from_dict({"startup": {"realistic": False}}).startup is None
    assert scenario_from_dict({}).startup is None


@pytest.mark.parametrize("table, words", [
    ({"gps_fix": 3}, "[startup].gps_fix: unknown key"),
    ({"gps_fix_s": "soon"}, "[startup].gps_fix_s: expected seconds"),
    ({"realistic": "yes"}, "[startup].realistic: expected true or false"),
    ({"origin_s": 1.0}, "[startup]: start-up stages must come in order"),
    ({"gps_fix_s": -1}, "[startup]: start-up times must not be negative"),
])
def test_startup_mistakes_name_the_table_and_key(table, words):
    with pytest.raises(ScenarioError, match=f"^sc: {words}".replace("[", r"\[").replace("]", r"\]")):
        scenario_from_dict({"startup": table}, "sc")


def test_the_command_line_flag_chooses_the_startup(monkeypatch, tmp_path):
    no_sockets(monkeypatch)
    path = tmp_path / "slow.toml"
    path.write_text("[startup]\ngps_in_use_s = 30\n")
    build = lambda *flags: cli.build(cli.build_parser().parse_args(  # noqa: E731
        [*flags, "--state-dir", str(tmp_path)]))[0][0].vehicle
    assert build("--startup", "realistic").startup.timeline == StartupTimeline()
    assert build("--scenario", str(path)).startup.timeline.gps_in_use_s == 30.0
    assert build("--scenario", str(path), "--startup", "instant").startup.timeline is None
    assert build().startup.timeline is None

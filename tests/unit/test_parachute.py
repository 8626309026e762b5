"""The parachute (autopilot/payload/parachute.py), SITL's simulated one (payload/sitl_parachute.py)
and the sim's canopy (sim/parachute.py), driven through the vehicle in sim time, as ArduCopter SITL
was measured doing them (tests/parity/probes/payload_outputs.py)."""
from __future__ import annotations

import pytest

from firefly.autopilot.mavlink.dialect import mavlink as mav
from firefly.autopilot.mission import MissionItem
from firefly.autopilot.results import Result
from firefly.sim.airframe import GRAVITY_M_S2
from firefly.sim.parachute import Canopy, slowed
from firefly.sim.scenario import ScenarioError, scenario_from_dict

from ._session_link import Link
from ._util import altitude, fly_until, hovering_vehicle, ready_vehicle
from .test_auto import REL, takeoff, wp_at

SERVO_CHUTE = {"CHUTE_ENABLED": 1, "CHUTE_TYPE": 10, "SERVO9_FUNCTION": 27}


def texts(v) -> list[str]:
    return [text for _, text in v.drain_events() if not text.startswith("PreArm")]


def with_chute(v, **extra):
    for name, value in {**SERVO_CHUTE, **extra}.items():
        v.params.set(name, value)
    v.run_until(v.time_s + 0.1)
    return v


def climb_to(v, alt_m: float):
    v.guided_goto(v.body.n_m, v.body.e_m, v.home_ned[2] - alt_m)
    assert fly_until(v, lambda x: abs(altitude(x) - alt_m) < 0.2 and abs(x.body.vd_m_s) < 0.1, 40.0)


def test_disabled_a_release_is_accepted_and_nothing_moves():
    v = hovering_vehicle(15.0)
    v.params.set("SERVO9_FUNCTION", 27)
    v.drain_events()
    assert v.parachute_action(2) == Result.ACCEPTED
    v.run_until(v.time_s + 1.0)
    assert v.armed and texts(v) == [] and v.servo_pwm[8] == 0  # never set while disabled


def test_enabled_the_output_rests_off_and_the_actions_set_chute_enabled():
    v = with_chute(ready_vehicle())
    assert v.servo_pwm[8] == 1100  # CHUTE_SERVO_OFF
    assert v.parachute_action(0) == Result.ACCEPTED and v.params["CHUTE_ENABLED"] == 0
    assert v.parachute_action(1) == Result.ACCEPTED and v.params["CHUTE_ENABLED"] == 1
    assert v.parachute_action(3) == Result.FAILED


def test_on_the_ground_and_too_low_it_says_why_and_stays_packed():
    v = with_chute(ready_vehicle())
    v.drain_events()
    assert v.parachute_action(2) == Result.ACCEPTED
    assert texts(v) == ["Parachute: Landed"]
    v = with_chute(hovering_vehicle(5.0))  # CHUTE_ALT_MIN 10
    v.drain_events()
    assert v.parachute_action(2) == Result.ACCEPTED
    v.run_until(v.time_s + 1.0)
    assert texts(v) == ["Parachute: Too low"] and v.armed and v.servo_pwm[8] == 1100


def test_a_release_disarms_fires_the_output_after_the_delay_for_two_seconds_and_blocks_arming():
    v = with_chute(hovering_vehicle(15.0))
    v.drain_events()
    t0 = v.time_s
    assert v.parachute_action(2) == Result.ACCEPTED
    assert not v.armed
    changes: list[tuple[float, int]] = []

    def watch(x) -> bool:
        if not changes or changes[-1][1] != x.servo_pwm[8]:
            changes.append((x.time_s - t0, x.servo_pwm[8]))
        return False
    fly_until(v, watch, 4.0, step_s=0.01)
    assert [pwm for _, pwm in changes] == [1100, 1300, 1100]
    assert changes[1][0] == pytest.approx(0.5, abs=0.02) and changes[2][0] == pytest.approx(2.5, abs=0.02)
    assert texts(v)[:2] == ["Parachute: Released", "Disarming motors"]
    fly_until(v, lambda x: x.landed, 20.0)
    assert v.arm() == Result.FAILED and texts(v) == ["Arm: Chute is released"]
    assert v.parachute_action(0) == Result.ACCEPTED and v.arm() == Result.ACCEPTED  # disabled: not checked


def test_hold_open_keeps_the_output_fired_and_skip_disarm_keeps_flying():
    v = with_chute(hovering_vehicle(15.0), CHUTE_OPTIONS=3, CHUTE_DELAY_MS=0)
    v.parachute_action(2)
    v.run_until(v.time_s + 4.0)
    assert v.armed and v.servo_pwm[8] == 1300


def test_sinking_faster_than_chute_crt_sink_for_a_second_releases_it():
    v = with_chute(hovering_vehicle(30.0), CHUTE_CRT_SINK=2)
    v.params.set("WPNAV_SPEED_DN", 300)
    v.drain_events()
    v.guided_goto(v.body.n_m, v.body.e_m, v.home_ned[2] - 12.0)
    fast_since: list[float] = []
    assert fly_until(v, lambda x: (x.body.vd_m_s > 2 and not fast_since and fast_since.append(x.time_s))
                     or not x.armed, 20.0, step_s=0.01)
    assert v.time_s - fast_since[0] == pytest.approx(1.0, abs=0.05)
    assert texts(v)[:2] == ["Parachute: Released", "Disarming motors"]


def test_a_relay_parachute_needs_a_relay_with_the_parachute_function():
    v = with_chute(ready_vehicle(), CHUTE_TYPE=0)
    assert v.prearm_failure() == "Chute has no relay"  # SITL's relay 1 is a plain relay
    v.params.set("RELAY1_FUNCTION", 3)
    assert v.prearm_failure() is None
    v = with_chute(ready_vehicle())
    v.params.set("SERVO9_FUNCTION", 0)
    assert v.prearm_failure() == "Chute has no channel"


def test_a_mission_releases_it_below_chute_alt_min_and_goes_on_to_the_next_item():
    """Measured: takeoff to 8 m, a waypoint, DO_PARACHUTE 2: released, disarmed, "Mission: 4 WP"."""
    v = with_chute(ready_vehicle())
    v.mission.replace(0, [takeoff(8.0), wp_at(v, 0.5, 0, 8.0), MissionItem(208, REL, 2), wp_at(v, 30, 0, 8.0),
                          MissionItem(21, REL)])
    v.set_mode(4)
    v.arm()
    v.set_mode(3)
    v.run_until(v.time_s + 1.0)
    v.drain_events()
    assert v.mission_start() == Result.ACCEPTED
    assert fly_until(v, lambda x: not x.armed, 60.0)
    said = texts(v)
    assert said[said.index("Mission: 3 Parachute"):][:4] == ["Mission: 3 Parachute", "Parachute: Released",
                                                            "Disarming motors", "Mission: 4 WP"]
    assert v.mission_progress.current_seq() == 4


def test_sitls_parachute_fires_at_1250_us_and_its_canopy_slows_the_fall():
    v = with_chute(hovering_vehicle(40.0), SIM_PARA_ENABLE=1, SIM_PARA_PIN=9)
    v.drain_events()
    v.parachute_action(2)
    fly_until(v, lambda x: x.sitl_parachute.fired, 1.0, step_s=0.01)
    assert texts(v) == ["Parachute: Released", "Disarming motors", "BANG!  Parachute deployed"]
    v.run_until(v.time_s + 4.0)
    steady = Canopy().sink_rate_m_s(v.sim.airframe.mass_kg, GRAVITY_M_S2)
    assert 4.0 < steady < 6.0
    assert v.body.vd_m_s == pytest.approx(steady, abs=0.6)  # the body's own drag takes a little more
    assert v.accel_body[2] == pytest.approx(-GRAVITY_M_S2, abs=0.5)  # steady under the canopy: 1 g of drag


def test_the_command_cuts_its_action_to_a_uint16():
    link = Link()
    assert link.command(mav.MAV_CMD_DO_PARACHUTE, 2.9)[0].result == mav.MAV_RESULT_ACCEPTED  # 2: release
    for action in (3, -1):
        assert link.command(mav.MAV_CMD_DO_PARACHUTE, action)[0].result == mav.MAV_RESULT_FAILED


def test_quadratic_drag_is_integrated_without_overshoot_and_the_scenario_sizes_the_canopy():
    vn, ve, vd = slowed((0.0, 0.0, 60.0), (0.0, 0.0, 0.0), 0.95, 1.5, 1.0)  # a huge step
    assert 0.0 < vd < 60.0 and vn == ve == 0.0
    assert slowed((3.0, 0.0, 0.0), (3.0, 0.0, 0.0), 0.95, 1.5, 0.01) == (3.0, 0.0, 0.0)  # drifting with the wind
    assert Canopy(inflation_s=0.5).drag_area_at(0.25) == pytest.approx(0.475)
    sc = scenario_from_dict({"parachute": {"drag_area_m2": 2.0}})
    assert sc.sim.canopy.drag_area_m2 == 2.0
    with pytest.raises(ScenarioError):
        scenario_from_dict({"parachute": {"drag_area_m2": -1.0}})

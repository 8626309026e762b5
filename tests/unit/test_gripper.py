"""The gripper (autopilot/payload/gripper.py), SITL's simulated one (payload/sitl_gripper.py) and the
load it hangs on the sim (sim/slung_load.py), driven through the vehicle in sim time, as ArduCopter
SITL was measured doing them (tests/parity/probes/payload_outputs.py)."""
from __future__ import annotations

import pytest

from firefly.autopilot.mavlink.dialect import mavlink as mav
from firefly.autopilot.mission import MissionItem
from firefly.autopilot.results import Result
from firefly.sim.airframe import GRAVITY_M_S2
from firefly.sim.slung_load import carried

from ._session_link import Link
from ._util import altitude, fly_until, hovering_vehicle, ready_vehicle
from .test_auto import REL, wp_at

GRIPPER = {"GRIP_ENABLE": 1, "GRIP_TYPE": 1, "SERVO9_FUNCTION": 28}
SITL_GRIPPER = {"SIM_GRPS_ENABLE": 1, "SIM_GRPS_PIN": 9}


def texts(v) -> list[str]:
    return [text for _, text in v.drain_events() if not text.startswith("PreArm")]


def act(v, action: int, settle_s: float = 1.0) -> tuple[Result, list[str], int]:
    result = v.gripper_action(action)
    v.run_until(v.time_s + settle_s)
    return result, texts(v), v.servo_pwm[8]


def test_made_at_boot_it_rests_neutral_and_answers_each_action_as_measured():
    v = ready_vehicle(GRIPPER)
    v.drain_events()
    assert v.servo_pwm[8] == 1500  # GRIP_NEUTRAL
    assert act(v, 0) == (Result.ACCEPTED, ["Gripper load releasing", "Gripper load released"], 1100)
    assert act(v, 0) == (Result.ACCEPTED, ["Gripper load released"], 1100)
    assert act(v, 2) == (Result.FAILED, [], 1100)
    assert act(v, 1) == (Result.ACCEPTED, ["Gripper load grabbing", "Gripper load grabbed"], 1900)
    assert act(v, 1) == (Result.ACCEPTED, ["Gripper load grabbed"], 1900)


def test_grabbed_only_after_the_servos_half_second_and_released_again_by_autoclose():
    v = ready_vehicle(GRIPPER)
    v.params.set("GRIP_AUTOCLOSE", 2.0)
    v.drain_events()
    v.gripper_action(1)
    v.run_until(v.time_s + 0.45)
    assert texts(v) == ["Gripper load grabbing"]
    v.run_until(v.time_s + 0.2)
    assert texts(v) == ["Gripper load grabbed"]
    v.gripper_action(0)
    assert fly_until(v, lambda x: x.servo_pwm[8] == 1900, 3.0)  # grabbing again on its own
    assert texts(v) == ["Gripper load releasing", "Gripper load released", "Gripper load grabbing"]


def test_disabled_it_fails_and_enabled_after_boot_nothing_was_made():
    v = ready_vehicle()
    assert v.gripper_action(0) == Result.FAILED
    v.params.set("GRIP_ENABLE", 1)
    v.params.set("GRIP_TYPE", 1)
    v.params.set("SERVO9_FUNCTION", 28)
    v.drain_events()
    assert act(v, 0) == (Result.ACCEPTED, [], 0)  # made at boot: there is none to move


def test_sitls_jaws_take_up_the_load_on_the_ground_and_the_hover_needs_more_thrust():
    v = ready_vehicle({**GRIPPER, **SITL_GRIPPER})
    v.gripper_action(1)
    v.run_until(v.time_s + 2.0)
    assert v.sitl_gripper.holding and v.sim.load is not None
    v.set_mode(4)
    v.arm()
    v.takeoff(10.0)
    assert fly_until(v, lambda x: abs(altitude(x) - 10.0) < 0.1 and abs(x.body.vd_m_s) < 0.05, 40.0)
    v.run_until(v.time_s + 3.0)
    weight = v.sim.airframe.weight_n
    assert v.thrust_demand_n == pytest.approx(weight + GRAVITY_M_S2, rel=0.03)  # 1 kg more
    v.gripper_action(0)
    v.run_until(v.time_s + 4.0)
    assert not v.sitl_gripper.holding and v.sim.load is None
    assert v.thrust_demand_n == pytest.approx(weight, rel=0.03)
    assert abs(altitude(v) - 10.0) < 1.5  # lighter by 40 %, it jumps up and comes back
    v.gripper_action(1)  # shut in the air: nothing to take up
    v.run_until(v.time_s + 3.0)
    assert v.sim.load is None


def test_the_load_hangs_only_above_its_string_and_scales_everything_but_gravity():
    assert carried((0.0, 0.0, 0.0), (1.0, 0.0, 0.2), 0.1, 1.5, 1.5) == pytest.approx((0.5, 0.0, 0.15))
    v = ready_vehicle({**GRIPPER, **SITL_GRIPPER})
    v.gripper_action(1)
    v.run_until(v.time_s + 2.0)
    v.set_mode(4)
    v.arm()
    v.takeoff(1.5)  # below the 2 m string: the load stays on the ground
    assert fly_until(v, lambda x: abs(altitude(x) - 1.5) < 0.1 and abs(x.body.vd_m_s) < 0.05, 40.0)
    v.run_until(v.time_s + 3.0)
    assert v.thrust_demand_n == pytest.approx(v.sim.airframe.weight_n, rel=0.03)


def test_the_mission_item_acts_then_says_ap_missions_words():
    """Measured: "Mission: 2 Gripper", "Gripper load releasing", "Gripper Released", "Mission: 3 WP",
    then "Gripper load released" once the servo is there."""
    v = hovering_vehicle(10.0)
    v.mission.replace(0, [wp_at(v, 0, 0), MissionItem(211, REL, 1, 0), wp_at(v, 10, 0), MissionItem(17, REL)])
    for name, value in GRIPPER.items():
        v.params.set(name, value)
    v.gripper.fitted = True  # as if made at boot
    v.gripper.grab(v.time_s)
    v.run_until(v.time_s + 1.0)
    v.drain_events()
    v.set_mode(3)
    assert fly_until(v, lambda x: x.mission_progress.current_seq() == 4, 30.0)
    said = texts(v)
    start = said.index("Mission: 2 Gripper")
    assert said[start:start + 5] == ["Mission: 2 Gripper", "Gripper load releasing", "Gripper Released",
                                     "Mission: 3 WP", "Gripper load released"]


def test_the_command_reads_the_action_from_param_2():
    link = Link()
    assert link.command(mav.MAV_CMD_DO_GRIPPER, 1, 0)[0].result == mav.MAV_RESULT_FAILED  # GRIP_ENABLE 0
    link.vehicle.params.set("GRIP_ENABLE", 1)
    assert link.command(mav.MAV_CMD_DO_GRIPPER, 1, 1)[0].result == mav.MAV_RESULT_ACCEPTED
    assert link.command(mav.MAV_CMD_DO_GRIPPER, 1, 258)[0].result == mav.MAV_RESULT_FAILED  # as a uint8: 2
    assert link.command(mav.MAV_CMD_DO_GRIPPER, 1, 256)[0].result == mav.MAV_RESULT_ACCEPTED  # as a uint8: 0

"""The sprayer (autopilot/payload/sprayer.py) driven through the vehicle in sim time, as ArduCopter
SITL was measured running AC_Sprayer (tests/parity/probes/payload_outputs.py)."""
from __future__ import annotations

from firefly.autopilot.mavlink.dialect import mavlink as mav
from firefly.autopilot.mission import MissionItem

from ._session_link import Link
from ._util import fly_until, hovering_vehicle, ready_vehicle
from .test_auto import REL, wp_at

PUMP, SPINNER = 9, 10


def sprayer_outputs(v) -> tuple[int, int]:
    return v.servo_pwm[PUMP - 1], v.servo_pwm[SPINNER - 1]


def fitted(v, enable: bool = True):
    v.params.set("SERVO9_FUNCTION", 22)
    v.params.set("SERVO10_FUNCTION", 23)
    v.params.set("SPRAY_ENABLE", 1 if enable else 0)
    return v


def test_switched_on_standing_still_both_outputs_go_to_their_minimum_even_disabled():
    v = fitted(ready_vehicle(), enable=False)
    assert sprayer_outputs(v) == (0, 0)  # never set
    v.run_sprayer(True)
    assert sprayer_outputs(v) == (1100, 1100) and not v.sprayer.running
    v = fitted(ready_vehicle())
    v.run_sprayer(True)
    v.run_until(v.time_s + 1.0)
    assert v.sprayer.running and not v.sprayer.spraying and sprayer_outputs(v) == (1100, 1100)


def test_flying_the_pump_follows_the_ground_speed_and_stops_a_second_after_slowing():
    v = fitted(hovering_vehicle(10.0))
    v.params.set("SERVO9_REVERSED", 0)
    v.run_sprayer(True)
    v.guided_velocity(6.0, 0.0, 0.0)
    assert fly_until(v, lambda x: abs(x.body.vn_m_s - 6.0) < 0.05, 20.0)
    v.run_until(v.time_s + 1.0)
    assert v.sprayer.spraying
    # 60 % of 1100-1900 at 6 m/s; read as GUIDED's 3 s velocity timeout starts its stop
    assert abs(sprayer_outputs(v)[0] - 1580) <= 8 and sprayer_outputs(v)[1] == 1300
    v.guided_velocity(0.0, 0.0, 0.0)
    assert fly_until(v, lambda x: x.body.vn_m_s < 1.0, 10.0, step_s=0.01)
    slow_at = v.time_s
    assert fly_until(v, lambda x: sprayer_outputs(x) == (1100, 1100), 3.0, step_s=0.01)
    assert 1.0 < v.time_s - slow_at < 1.0 + 2 / 3 + 0.02  # a second, counted in 3 Hz updates
    v.params.set("SERVO9_REVERSED", 1)  # reversed: its minimum is SERVO9_MAX
    v.run_sprayer(False)
    assert sprayer_outputs(v) == (1900, 1100)


def test_the_pump_minimum_and_the_top_of_its_range():
    v = fitted(hovering_vehicle(10.0))
    v.params.set("SPRAY_PUMP_MIN", 50)
    v.params.set("SPRAY_SPEED_MIN", 0)
    v.run_sprayer(True)
    v.run_until(v.time_s + 1.0)
    assert sprayer_outputs(v) == (1500, 1300)  # at least half the range, hovering
    v.params.set("SPRAY_PUMP_RATE", 100)
    v.guided_velocity(3.0, 0.0, 0.0)
    v.run_until(v.time_s + 4.0)
    assert sprayer_outputs(v)[0] == 1900
    v.params.set("SPRAY_ENABLE", 0)  # off at the next update
    v.run_until(v.time_s + 0.5)
    assert sprayer_outputs(v) == (1100, 1100) and not v.sprayer.running


def test_the_mission_item_switches_it_on_and_anything_but_1_off():
    v = fitted(hovering_vehicle(10.0))
    v.mission.replace(0, [wp_at(v, 0, 0), MissionItem(216, REL, 1), wp_at(v, 100, 0), MissionItem(216, REL, 2),
                          wp_at(v, 100, 10), MissionItem(17, REL)])
    v.set_mode(3)
    top = [0]
    assert fly_until(v, lambda x: top.__setitem__(0, max(top[0], sprayer_outputs(x)[0])) or
                     x.mission_progress.current_seq() == 5, 60.0)
    assert top[0] >= 1880 and sprayer_outputs(v) == (1100, 1100) and not v.sprayer.running


def test_the_command_takes_exactly_1_and_exactly_0():
    link = Link()
    v = fitted(link.vehicle)
    assert link.command(mav.MAV_CMD_DO_SPRAYER, 2)[0].result == mav.MAV_RESULT_ACCEPTED
    assert not v.sprayer.running
    assert link.command(mav.MAV_CMD_DO_SPRAYER, 1)[0].result == mav.MAV_RESULT_ACCEPTED
    assert v.sprayer.running
    assert link.command(mav.MAV_CMD_DO_SPRAYER, 0.5)[0].result == mav.MAV_RESULT_ACCEPTED
    assert v.sprayer.running
    assert link.command(mav.MAV_CMD_DO_SPRAYER, 0)[0].result == mav.MAV_RESULT_ACCEPTED
    assert not v.sprayer.running

"""DO_SET_SERVO and DO_REPEAT_SERVO as ArduPilot's ServoRelayEvents (autopilot/servo_relay.py),
driven by sim time through the vehicle, as ArduCopter SITL was measured doing them
(tests/parity/probes/surface_commands.py and surface_mission.py)."""
from __future__ import annotations

from firefly.autopilot.mission import MissionItem
from firefly.autopilot.results import Result

from ._util import fly_until, ready_vehicle
from .test_auto import REL, takeoff, wp_at


def outputs_seen(v, channel: int, seconds: float) -> list[int]:
    """Output `channel` as it changes over `seconds` of flight (each value once per change)."""
    seen: list[int] = []

    def watch(x) -> bool:
        value = x.servo_pwm[channel - 1]
        if not seen or seen[-1] != value:
            seen.append(value)
        return False
    fly_until(v, watch, seconds)
    return seen


def test_a_free_output_takes_the_pwm_and_a_motor_refuses_with_arducopters_words():
    v = ready_vehicle()
    assert v.servo_pwm[8] == 0  # never set
    assert v.set_servo(9, 1700) == Result.ACCEPTED and v.servo_pwm[8] == 1700
    v.drain_events()
    assert v.set_servo(1, 1200) == Result.FAILED  # SERVO1_FUNCTION 33: motor 1
    assert [t for _, t in v.drain_events()] == ["ServoRelayEvent: Channel 1 is already in use"]
    assert v.set_servo(17, 1500) == Result.FAILED and v.set_servo(0, 1500) == Result.FAILED


def test_a_repeat_toggles_between_the_pwm_and_trim_then_ends_at_trim():
    v = ready_vehicle()
    v.params.set("SERVO8_TRIM", 1450)
    assert v.repeat_servo(8, 1900, 2, 1.0) == Result.ACCEPTED
    assert outputs_seen(v, 8, 5.0) == [1900, 1450, 1900, 1450]


def test_setting_the_output_again_ends_its_repeat():
    v = ready_vehicle()
    assert v.repeat_servo(8, 1900, -1, 0.4) == Result.ACCEPTED  # for ever
    assert len(outputs_seen(v, 8, 2.0)) >= 8
    assert v.set_servo(8, 1600) == Result.ACCEPTED
    assert outputs_seen(v, 8, 2.0) == [1600]


def test_a_mission_sets_the_servo_and_does_not_report_the_item_reached():
    """Measured: DO_SET_SERVO between two waypoints: MISSION_ITEM_REACHED 1, 2, 4, no "Skipping"."""
    v = ready_vehicle()
    v.mission.replace(0, [takeoff(), wp_at(v, 20, 0), MissionItem(183, 0, 9, 1700), wp_at(v, 20, 20),
                          MissionItem(21, REL)])
    v.set_mode(4)
    v.arm()
    v.set_mode(3)
    v.run_until(v.time_s + 1.0)
    assert v.mission_start() == Result.ACCEPTED
    reached: list[int] = []

    def until_landed(x) -> bool:
        reached.extend(x.mission_progress.drain_reached())
        return not x.armed
    assert fly_until(v, until_landed, 120.0)
    assert reached[:3] == [1, 2, 4] and v.servo_pwm[8] == 1700
    assert not any("Skipping" in text for _, text in v.events)


def test_relay_0_is_sitls_relay_and_toggles_the_others_are_not_relays():
    v = ready_vehicle()
    assert v.set_relay(0, 1) == Result.ACCEPTED and v.servo_relay.relays[0]
    assert v.set_relay(0, 2) == Result.ACCEPTED and not v.servo_relay.relays[0]  # any other state toggles
    assert v.set_relay(1, 1) == Result.FAILED  # RELAY2_FUNCTION 0
    assert v.repeat_relay(0, 2, 1.0) == Result.ACCEPTED
    states = []
    fly_until(v, lambda x: (not states or states[-1] != x.servo_relay.relays[0]) and states.append(
        x.servo_relay.relays[0]) and False, 5.0)
    assert states == [True, False, True, False]


def test_relay_status_names_each_relay_with_a_function_and_the_ones_on():
    v = ready_vehicle()
    present, _ = v.relay_masks()
    assert present & 1  # SITL's relay 1
    v.params.set("RELAY2_FUNCTION", 1)  # no pin: present, but DO_SET_RELAY refuses it
    v.params.set("RELAY3_FUNCTION", 99)  # no such function: absent
    assert v.set_relay(0, 1) == Result.ACCEPTED and v.set_relay(1, 1) == Result.FAILED
    assert v.relay_masks() == (present | 0b010, 0b001)
    assert v.set_relay(0, 2) == Result.ACCEPTED and v.relay_masks()[1] == 0  # toggled off

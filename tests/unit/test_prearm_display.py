"""The pre-arm reports ArduCopter says unasked while disarmed (autopilot/safety/prearm_display.py):
every 30 s, and at the next second's update once passing checks start to fail."""
from __future__ import annotations

import math

from pymavlink.dialects.v20 import ardupilotmega as mav

from firefly.autopilot.mavlink import telemetry
from firefly.autopilot.modes import ModeNumber
from firefly.autopilot.results import Result
from firefly.autopilot.safety.prearm_display import DISABLE_PREARM_DISPLAY, PrearmDisplay

from ._util import fly_until, ready_vehicle
from .test_external_nav import EXTNAV, speak

CODEC = mav.MAVLink(None)


def run(display: PrearmDisplay, failing_from_s: dict[float, list[str]], until_s: float, armed=False,
        options: int = 0) -> list[tuple[float, str]]:
    """Once a second from 1 s to until_s; failing_from_s: from that second on, those reasons."""
    said, reasons = [], []
    for t in range(1, int(until_s) + 1):
        reasons = failing_from_s.get(float(t), reasons)
        said += [(t, r) for r in display.update(float(t), armed, lambda: reasons, options)]
    return said


def test_failing_from_boot_is_first_said_after_30_s_then_every_30_s():
    assert run(PrearmDisplay(), {1.0: ["AHRS: waiting for home"]}, 95) == \
        [(31, "AHRS: waiting for home"), (62, "AHRS: waiting for home"), (93, "AHRS: waiting for home")]


def test_a_check_that_starts_failing_is_said_at_the_next_update():
    said = run(PrearmDisplay(), {40.0: ["GPS: Bad fix"]}, 75)
    assert said[0] == (41, "GPS: Bad fix") and said[1] == (72, "GPS: Bad fix")


def test_a_new_failure_waits_4_s_after_the_last_report():
    said = run(PrearmDisplay(), {1.0: ["A"], 32.0: [], 33.0: ["B"]}, 40)
    assert said == [(31, "A"), (36, "B")]


def test_nothing_while_armed_or_with_the_display_off():
    assert run(PrearmDisplay(), {1.0: ["A"]}, 70, armed=True) == []
    assert run(PrearmDisplay(), {1.0: ["A"]}, 70, options=DISABLE_PREARM_DISPLAY) == []


def test_the_vehicle_says_them_once_a_mode_it_cannot_arm_in_is_chosen():
    v = ready_vehicle(EXTNAV)  # navigating on a pose, no origin: no home
    speak(v, 10.0)
    assert v.arming.armed is False and [t for _, t in v.drain_events() if t.startswith("PreArm")] == []
    assert v.set_mode(ModeNumber.LOITER) == Result.ACCEPTED
    speak(v, 11.95)
    assert [t for _, t in v.drain_events() if t.startswith("PreArm")] == ["PreArm: AHRS: waiting for home"]
    speak(v, 42.95)  # 31 s on: "more than 30 s" at a once-a-second update
    assert [t for _, t in v.drain_events() if t.startswith("PreArm")] == ["PreArm: AHRS: waiting for home"]


def test_arming_options_bit_1_silences_the_arming_texts():
    v = ready_vehicle()
    assert v.set_mode(ModeNumber.GUIDED) == Result.ACCEPTED
    v.drain_events()
    assert v.arm() == Result.ACCEPTED and v.disarm() == Result.ACCEPTED
    assert [t for _, t in v.drain_events()] == ["Arming motors", "Disarming motors"]
    v.params.set("ARMING_OPTIONS", 2)
    assert v.arm() == Result.ACCEPTED and v.disarm() == Result.ACCEPTED
    assert v.drain_events() == []


def _prearm_healthy(v) -> bool:
    return bool(telemetry.sys_status(v, CODEC).onboard_control_sensors_health & mav.MAV_SYS_STATUS_PREARM_CHECK)


def test_sys_status_shows_the_last_once_a_second_verdict_not_a_check_per_message():
    v = ready_vehicle()
    assert fly_until(v, _prearm_healthy, 1.0)
    v.run_until(math.floor(v.time_s) + 1.5)  # between two updates
    v.params.set("BATT_LOW_VOLT", 20.0)  # a check that fails at once
    assert v.prearm_failure() is not None and _prearm_healthy(v)  # not yet looked at
    assert fly_until(v, lambda x: not _prearm_healthy(x), 1.0)
    v.params.set("BATT_LOW_VOLT", 0.0)
    assert not _prearm_healthy(v)
    assert fly_until(v, _prearm_healthy, 1.0)


def test_an_arm_refused_or_accepted_updates_the_verdict_at_once():
    v = ready_vehicle()
    assert fly_until(v, _prearm_healthy, 1.0)
    v.params.set("BATT_LOW_VOLT", 20.0)
    assert v.set_mode(ModeNumber.GUIDED) == Result.ACCEPTED
    assert v.arm() == Result.FAILED and not _prearm_healthy(v)
    v.params.set("BATT_LOW_VOLT", 0.0)
    assert v.arm() == Result.ACCEPTED and _prearm_healthy(v)

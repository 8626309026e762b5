"""The pre-arm reports ArduCopter says unasked while disarmed (autopilot/safety/prearm_display.py):
every 30 s, and at the next second's update once passing checks start to fail."""
from __future__ import annotations

from firefly.autopilot.modes import ModeNumber
from firefly.autopilot.results import Result
from firefly.autopilot.safety.prearm_display import DISABLE_PREARM_DISPLAY, PrearmDisplay

from ._util import ready_vehicle
from .test_external_nav import EXTNAV, speak


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

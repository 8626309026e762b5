"""The stick-flown and refusing modes (ACRO, DRIFT, FLIP, THROW, AUTOTUNE, FLOWHOLD, FOLLOW,
SYSTEMID, TURTLE), flown through the real vehicle: entry rules and texts as ArduCopter's, and
what each does in the air with the sticks a pilot would hold."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.control import compiled
from firefly.autopilot.mavlink import sensor_messages
from firefly.autopilot.modes import ModeNumber
from firefly.autopilot.results import Result
from firefly.autopilot.vehicle import Vehicle

from ._util import altitude, fly_until, hovering_vehicle, ready_vehicle
from .test_compiled_cascade import lockstep, twins


def hold_sticks(v: Vehicle, roll=0.0, pitch=0.0, yaw=0.0, throttle=0.5, seconds=0.0, until=None) -> bool:
    """Fly `seconds` (or until `until(v)`) with the pilot's sticks held so."""
    def held(x: Vehicle) -> bool:
        x.rc.hold_sticks(roll, pitch, yaw, throttle, x.time_s)
        return until is not None and until(x)
    return fly_until(v, held, seconds or 10.0)


def said(v: Vehicle) -> list[str]:
    return [text for _, text in v.drain_events()]


@pytest.mark.parametrize("mode, texts", [
    (ModeNumber.FLIP, []), (ModeNumber.AUTOTUNE, []), (ModeNumber.FLOWHOLD, []), (ModeNumber.TURTLE, []),
    (ModeNumber.SYSTEMID, ["No axis selected, SID_AXIS = 0"]), (ModeNumber.FOLLOW, ["Set FOLL_ENABLE = 1"]),
])
def test_refused_disarmed_with_arducopters_words(mode, texts):
    v = ready_vehicle()
    said(v)
    assert v.set_mode(mode) == Result.FAILED
    assert said(v) == texts + [f"Mode change to {mode.name} failed: init failed"]
    assert v.mode_number == ModeNumber.STABILIZE


def test_entered_disarmed_and_throw_refused_armed():
    v = ready_vehicle()
    for mode in (ModeNumber.ACRO, ModeNumber.DRIFT, ModeNumber.THROW):
        assert v.set_mode(mode) == Result.ACCEPTED
    v.set_mode(ModeNumber.GUIDED)
    assert v.arm() == Result.ACCEPTED
    said(v)
    assert v.set_mode(ModeNumber.THROW) == Result.FAILED
    assert said(v) == ["Mode change to THROW failed: init failed"]


def test_follow_enabled_holds_and_systemid_says_why_it_refuses():
    v = hovering_vehicle()
    v.params.set("SID_AXIS", 1)
    said(v)
    assert v.set_mode(ModeNumber.SYSTEMID) == Result.FAILED  # from GUIDED: not a manual-throttle mode
    assert said(v)[0] == "Axis requires manual throttle"
    v.params.set("FOLL_ENABLE", 1)
    assert v.set_mode(ModeNumber.FOLLOW) == Result.ACCEPTED
    start = (v.body.n_m, v.body.e_m, altitude(v))
    v.run_until(v.time_s + 5.0)
    assert math.hypot(v.body.n_m - start[0], v.body.e_m - start[1]) < 1.0 and abs(altitude(v) - start[2]) < 0.5


def test_autotune_enters_from_alt_hold_only_with_the_throttle_off_the_bottom():
    v = hovering_vehicle()
    v.set_mode(ModeNumber.ALT_HOLD)
    hold_sticks(v, throttle=0.0, seconds=0.2)
    said(v)
    assert v.set_mode(ModeNumber.AUTOTUNE) == Result.FAILED
    hold_sticks(v, throttle=0.5, seconds=0.2)
    assert v.set_mode(ModeNumber.AUTOTUNE) == Result.ACCEPTED
    assert "AutoTune: Started" in said(v)


def test_flip_rolls_over_and_hands_back_to_alt_hold():
    v = hovering_vehicle()
    assert v.set_mode(ModeNumber.FLIP) == Result.FAILED  # from GUIDED: never
    v.set_mode(ModeNumber.ALT_HOLD)
    hold_sticks(v, seconds=1.0)
    start = v.time_s
    assert v.set_mode(ModeNumber.FLIP) == Result.ACCEPTED
    rolled = [0.0]

    def back(x: Vehicle) -> bool:
        rolled[0] = max(rolled[0], abs(x.attitude[0]))
        return x.mode_number == ModeNumber.ALT_HOLD
    assert hold_sticks(v, until=back)
    assert rolled[0] > math.radians(150.0)  # over the top (sampled each step, at 400 deg/s)
    # The rate builds at ATC_ACCEL_R_MAX: ArduCopter SITL is back level 1.26 s after the ACK,
    # a rate asked for at once would hand back in 0.95 s. Recovered, not timed out.
    assert 1.05 < v.time_s - start < 2.5
    assert abs(v.attitude[0]) < math.radians(6.0) and altitude(v) > 6.0


def test_acro_trainer_limits_the_lean_and_levels_when_let_go():
    v = hovering_vehicle(alt_m=30.0)
    assert v.set_mode(ModeNumber.ACRO) == Result.ACCEPTED
    leans = []
    hold_sticks(v, roll=1.0, seconds=1.0, until=lambda x: leans.append(abs(x.attitude[0])) and False)
    # Held at full stick it leans past ANGLE_MAX but no further than ArduCopter's limiter lets it
    # (its square-root pull-back balances 360 deg/s some 50 degrees beyond): it never rolls over.
    angle_max = math.radians(v.params["ANGLE_MAX"] / 100.0)
    assert angle_max < max(leans) < math.radians(90.0)
    hold_sticks(v, seconds=4.0)
    assert abs(v.attitude[0]) < math.radians(3.0)


def test_acro_without_trainer_rolls_right_over():
    v = hovering_vehicle(alt_m=30.0)
    v.params.set("ACRO_TRAINER", 0)
    v.set_mode(ModeNumber.ACRO)
    assert hold_sticks(v, roll=1.0, seconds=1.0, until=lambda x: abs(x.attitude[0]) > math.radians(120.0))


def test_drift_flies_forward_on_the_stick_and_brakes_when_let_go():
    v = hovering_vehicle()
    assert v.set_mode(ModeNumber.DRIFT) == Result.ACCEPTED
    hold_sticks(v, pitch=0.5, seconds=3.0)
    assert v.body.vn_m_s > 3.0  # heading north: forward is north
    hold_sticks(v, seconds=6.0)
    assert math.hypot(v.body.vn_m_s, v.body.ve_m_s) < 1.0
    yaw = v.attitude[2]
    hold_sticks(v, roll=0.5, seconds=1.0)
    assert v.attitude[2] - yaw > math.radians(20.0)  # the roll stick turns it


def test_throw_waits_armed_detects_the_throw_and_climbs():
    v = ready_vehicle()
    v.params.set("DISARM_DELAY", 1)
    assert v.set_mode(ModeNumber.THROW) == Result.ACCEPTED and v.arm() == Result.ACCEPTED
    v.run_until(v.time_s + 3.0)
    assert v.armed  # THROW never auto-disarms
    said(v)
    for name, value in (("SIM_SHOVE_Z", -30), ("SIM_SHOVE_X", -20), ("SIM_SHOVE_TIME", 500)):
        v.params.set(name, value)
    assert v.params["SIM_SHOVE_TIME"] == 0  # back to 0 as SITL's, the push goes on
    texts: list[str] = []
    fly_until(v, lambda x: texts.extend(said(x)) or "height achieved - controlling position" in texts, 15.0)
    assert texts == ["throw detected - spooling motors", "throttle is unlimited - uprighting",
                     "uprighted - controlling height", "height achieved - controlling position"]
    assert altitude(v) > 5.0 and v.armed and v.mode_number == ModeNumber.THROW


def fly_until_said(v: Vehicle, text: str, timeout_s: float) -> bool:
    heard: list[str] = []
    return fly_until(v, lambda x: heard.extend(said(x)) or text in heard, timeout_s)


def throw_armed(motor_start: int) -> Vehicle:
    v = ready_vehicle()
    v.params.set("THROW_MOT_START", motor_start)
    assert v.set_mode(ModeNumber.THROW) == Result.ACCEPTED and v.arm() == Result.ACCEPTED
    v.run_until(v.time_s + 1.0)
    return v


def test_throw_waits_with_the_motors_stopped_unless_told_to_idle():
    stopped, idling = throw_armed(0), throw_armed(1)
    assert stopped.armed and sensor_messages.motor_pwm(stopped) == [1000] * 4
    assert stopped.motor_commands == (0.0, 0.0, 0.0, 0.0)
    # idling at ArduCopter's ground idle (MOT_SPIN_ARM): THROW skips the 2 s arming delay
    assert idling.armed and sensor_messages.motor_pwm(idling) == [1100] * 4
    assert all(omega > 0.0 for omega in idling.motor_commands)


def test_throw_hands_over_as_soon_as_the_height_is_reached():
    v = throw_armed(0)
    v.params.set("THROW_NEXTMODE", ModeNumber.LOITER)
    said(v)
    for name, value in (("SIM_SHOVE_Z", -30), ("SIM_SHOVE_X", -20), ("SIM_SHOVE_TIME", 500)):
        v.params.set(name, value)
    assert fly_until_said(v, "height achieved - controlling position", 10.0)
    reached_s, speed = v.time_s, math.hypot(v.body.vn_m_s, v.body.ve_m_s)
    assert fly_until(v, lambda x: x.mode_number == ModeNumber.LOITER, 0.1)
    # ArduCopter's position stage starts its target on the vehicle: no wait to stop first
    assert v.time_s - reached_s <= 0.06 and speed > 2.0


def test_throw_climbs_from_the_climb_rate_it_has_when_upright():
    v = throw_armed(0)
    for name, value in (("SIM_SHOVE_Z", -30), ("SIM_SHOVE_TIME", 500)):
        v.params.set(name, value)
    assert fly_until_said(v, "uprighted - controlling height", 10.0)
    start = altitude(v)
    heights: list[float] = []
    fly_until(v, lambda x: heights.append(altitude(x)) and False, 5.0)
    peak = max(heights)
    # THROW_ALT_ACSND (3 m) above, and no wild overshoot from a stale climb-rate target
    assert 2.5 < peak - start < 4.5


@pytest.mark.skipif(not compiled.available(), reason="compiled cascade not built")
def test_rate_setpoints_fly_the_same_bits_compiled_and_in_python():
    a, b = twins()
    for v in (a, b):
        v.run_until(0.5)
        v.set_mode(ModeNumber.GUIDED)
        v.arm()
        v.takeoff(5.0)
    lockstep(a, b, 4.0)
    for v in (a, b):
        v.set_mode(ModeNumber.ACRO)
        v.rc.hold_sticks(0.6, -0.3, 0.2, 0.55, v.time_s)
    lockstep(a, b, 1.0)


def test_a_drop_handed_to_guided_is_stopped_where_it_comes_to_rest():
    v = throw_armed(0)
    for name, value in (("THROW_TYPE", 1), ("THROW_NEXTMODE", ModeNumber.GUIDED), ("SIM_SHOVE_Z", -11),
                        ("SIM_SHOVE_TIME", 8000)):
        v.params.set(name, value)
    assert fly_until(v, lambda x: x.mode_number == ModeNumber.GUIDED, 20.0)
    handed_over, falling = altitude(v), v.body.vd_m_s
    heights: list[float] = []
    fly_until(v, lambda x: heights.append(altitude(x)) and False, 6.0)
    # ArduCopter's GUIDED starts from a velocity of zero: it stops some metres lower and holds
    # there (measured: 6.3 m below, handed over at 7.5 m/s down); it does not climb back
    assert falling > 5.0 and 4.0 < handed_over - min(heights) < 9.0
    assert abs(heights[-1] - min(heights)) < 0.5 and abs(v.body.vd_m_s) < 0.2

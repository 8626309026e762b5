"""The winch (autopilot/payload/winch.py) and its command, message, aux switch, mission item and
pre-arm check, driven through the vehicle in sim time, as ArduCopter SITL was measured running
AP_Winch's PWM winch (tests/parity/probes/winch.py)."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.mavlink.dialect import mavlink as mav
from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.mavlink.winch_messages import winch_status
from firefly.autopilot.mission import MissionItem
from firefly.autopilot.payload.winch import Winch
from firefly.autopilot.params import ParamStore
from firefly.autopilot.results import Result
from firefly.autopilot.rc.aux import run_aux_function
from firefly.autopilot.safety.arming import prearm_failures

from ._session_link import Link
from ._util import fly_until, hovering_vehicle, ready_vehicle
from .test_auto import REL, wp_at

PWM_WINCH = {"WINCH_TYPE": 1, "SERVO9_FUNCTION": 88}
RELAX, LENGTH, RATE = 0, 1, 2


class Radio:
    """Every channel's PWM and whether the radio is to be trusted, as the vehicle gives them."""

    def __init__(self):
        self.channels, self.valid = [0] * 16, True

    def __call__(self) -> tuple[list[int], bool]:
        return self.channels, self.valid


def winch_alone(radio: Radio | None = None, **params) -> tuple[Winch, list[int], list[str]]:
    store = ParamStore()
    for name, value in {**PWM_WINCH, **params}.items():
        store.set(name, value)
    pwm = [0] * 16
    said: list[str] = []
    return Winch(store, pwm, lambda text, severity: said.append(text), lambda: None, radio or Radio()), pwm, said


def run(winch: Winch, from_s: float, seconds: float) -> float:
    """The 50 Hz update from `from_s` for `seconds`; the time reached."""
    t = from_s
    while t < from_s + seconds - 1e-9:
        winch.update(t)
        t = round(t + 0.02, 6)
    return t


def test_made_relaxed_it_outputs_nothing_and_the_line_stays_at_zero():
    winch, pwm, _ = winch_alone()
    run(winch, 0.0, 1.0)
    assert winch.fitted and winch.healthy
    assert (pwm[8], winch.line_m, winch.rate_desired_m_s) == (0, 0.0, 0.0)


def test_rate_control_ramps_the_output_and_lets_out_the_rate_asked():
    winch, pwm, _ = winch_alone()
    run(winch, 0.0, 0.1)
    winch.set_rate(0.5)
    t = run(winch, 0.1, 0.1)
    assert 1500 < pwm[8] < 1700  # ramping at 2 m/s/s: 0.2 m/s of 1 after 0.1 s
    run(winch, t, 2.0)
    assert pwm[8] == 1700  # SERVO9_TRIM + 0.5 / WINCH_RATE_MAX of (MAX - TRIM)
    assert winch.line_m == pytest.approx(1.05, abs=0.01)  # 2.1 s at the rate asked, not the ramped one


@pytest.mark.parametrize("rate, pwm_out, speed", [(3.0, 1900, 1.0), (-0.5, 1300, -0.5), (0.0, 1500, 0.0),
                                                  (math.inf, 1900, 1.0), (math.nan, 1500, 0.0)])
def test_a_rate_is_held_to_the_maximum_and_nan_is_zero(rate, pwm_out, speed):
    winch, pwm, _ = winch_alone()
    winch.set_rate(rate)
    run(winch, 0.0, 2.0)
    assert (pwm[8], winch.rate_desired_m_s) == (pwm_out, speed)


def test_length_control_runs_at_most_flat_out_then_closes_in_by_pos_p():
    winch, pwm, said = winch_alone()
    winch.release_length(2.0)
    assert said == ["Winch: lowering  2.0m to  2.0m"]  # WINCH_OPTIONS bit 1, as ArduPilot's "%4.1f"
    t = run(winch, 0.0, 1.0)
    assert winch.line_m == pytest.approx(1.0, abs=0.03)  # 1 m short: WINCH_RATE_MAX until then
    t = run(winch, t, 1.0)
    assert winch.line_m == pytest.approx(2.0 - math.exp(-1.0), abs=0.03)
    run(winch, t, 10.0)
    assert winch.line_m == pytest.approx(2.0, abs=1e-3) and pwm[8] == 1500
    winch.release_length(-1.0)
    assert said[-1] == "Winch: raising  1.0m to  1.0m"


def test_relaxing_stops_the_output_and_keeps_the_line_and_the_rate_reported():
    winch, pwm, _ = winch_alone()
    winch.set_rate(-0.5)
    t = run(winch, 0.0, 1.0)
    line = winch.line_m
    winch.relax()
    run(winch, t, 1.0)
    assert (pwm[8], winch.line_m, winch.rate_desired_m_s) == (0, line, -0.5)


def test_without_its_output_it_is_unhealthy_and_the_line_never_moves():
    winch, _, _ = winch_alone(SERVO9_FUNCTION=0)
    winch.set_rate(0.5)
    run(winch, 0.0, 2.0)
    assert not winch.healthy and winch.line_m == 0.0 and winch.rate_desired_m_s == 0.5
    assert winch.prearm_failure() == "winch unhealthy"


def test_options_without_bit_0_start_it_held_at_rate_zero():
    winch, pwm, _ = winch_alone(WINCH_OPTIONS=0)
    run(winch, 0.0, 0.5)
    assert pwm[8] == 1500
    winch.release_length(1.0)
    run(winch, 0.5, 0.1)
    assert pwm[8] > 1500


def test_the_command_answers_as_measured_with_no_winch_one_set_live_and_one_made():
    link = Link()
    for action in (RELAX, LENGTH, RATE, 3):
        assert link.command(mav.MAV_CMD_DO_WINCH, 1, action, 1.0, 0.5)[0].result == mav.MAV_RESULT_FAILED
    link.vehicle.params.set("WINCH_TYPE", 1)  # not made until a reboot: still FAILED, and unhealthy
    assert link.command(mav.MAV_CMD_DO_WINCH, 1, RATE, 0, 0.5)[0].result == mav.MAV_RESULT_FAILED
    assert "winch unhealthy" in prearm_failures(link.vehicle)
    link = Link(ready_vehicle(PWM_WINCH))
    assert "winch unhealthy" not in prearm_failures(link.vehicle)
    results = {action: link.command(mav.MAV_CMD_DO_WINCH, 5, action, 0.5, 0.25)[0].result
               for action in (RELAX, LENGTH, RATE, 3, 7, 255, 258, math.nan)}
    assert results == {RELAX: mav.MAV_RESULT_ACCEPTED, LENGTH: mav.MAV_RESULT_ACCEPTED, RATE: mav.MAV_RESULT_ACCEPTED,
                       3: mav.MAV_RESULT_FAILED, 7: mav.MAV_RESULT_FAILED, 255: mav.MAV_RESULT_FAILED,
                       258: mav.MAV_RESULT_ACCEPTED,  # as a uint8: 2, rate control
                       math.nan: mav.MAV_RESULT_ACCEPTED}  # NaN as a uint8: 0, relax


def test_winch_status_reports_the_line_the_rate_asked_and_health():
    codec = new_codec(1)
    assert winch_status(ready_vehicle(), codec) is None  # none made: nothing sent
    v = ready_vehicle(PWM_WINCH)
    assert v.winch_action(RATE, 0.0, 0.5) == Result.ACCEPTED
    v.run_until(v.time_s + 2.0)
    m = winch_status(v, codec)
    assert m.line_length == pytest.approx(1.0, abs=0.03) and m.speed == 0.5
    assert all(math.isnan(x) for x in (m.tension, m.voltage, m.current))
    assert (m.temperature, m.status) == (32767, mav.MAV_WINCH_STATUS_HEALTHY)
    assert v.servo_pwm[8] == 1700


def test_the_aux_switch_holds_it_at_high_and_relaxes_it_otherwise():
    v = ready_vehicle(PWM_WINCH)
    run_aux_function(v, 44, 2)
    v.run_until(v.time_s + 1.0)
    assert v.servo_pwm[8] == 1500
    run_aux_function(v, 44, 1)
    v.run_until(v.time_s + 1.0)
    assert v.servo_pwm[8] == 0


def test_the_mission_item_runs_the_winch_as_it_starts():
    v = hovering_vehicle(10.0)
    v.params.set("SERVO9_FUNCTION", 88)
    v.params.set("WINCH_TYPE", 1)
    v.winch = v.ctx.winch = Winch(v.params, v.servo_pwm, v.notify, v.constraining_nan,  # as if made at boot
                                  lambda: (v.rc.radio_in, True))
    v.mission.replace(0, [wp_at(v, 0, 0), MissionItem(42600, REL, 1, RATE, 0, 0.5), wp_at(v, 0, 0),
                          MissionItem(17, REL)])
    v.set_mode(3)
    assert fly_until(v, lambda x: x.winch.rate_desired_m_s == 0.5, 20.0)
    v.run_until(v.time_s + 1.0)
    assert v.servo_pwm[8] == 1700


def test_a_stick_on_winch_control_runs_it_past_its_dead_zone_until_a_command_takes_over():
    """Measured with RC9_OPTION 45: RC9_DZ reads 30; 1800 us lowers at 0.73 m/s (1791 us out), 1200
    raises at 0.73; a command holds until the stick moves more than 30 us; a channel given back
    to a silent receiver (0 us) winds in flat out."""
    radio = Radio()
    winch, pwm, _ = winch_alone(radio, RC9_OPTION=45)
    assert winch.params["RC9_DZ"] == 30
    t = run(winch, 0.0, 0.5)
    assert (winch.mode, pwm[8]) == (0, 0)  # the stick at 0 where first read: not moved
    radio.channels[8] = 1800
    t = run(winch, t, 1.0)
    assert (round(winch.rate_desired_m_s, 3), pwm[8]) == (0.73, 1791)
    radio.channels[8] = 1200
    t = run(winch, t, 1.0)
    assert (round(winch.rate_desired_m_s, 3), pwm[8]) == (-0.73, 1209)
    winch.set_rate(0.2)
    radio.channels[8] = 1220
    t = run(winch, t, 1.0)
    assert (winch.rate_desired_m_s, pwm[8]) == (pytest.approx(0.2), 1580)
    radio.channels[8] = 1700
    t = run(winch, t, 1.0)
    assert round(winch.rate_desired_m_s, 3) == 0.459
    radio.valid = False
    run(winch, t, 0.1)
    assert winch.rate_desired_m_s == 0.0


def test_the_sticks_dead_zone_default_is_not_saved_and_a_set_one_stands(tmp_path):
    path = tmp_path / "params.json"
    store = ParamStore(path)
    store.set("RC9_OPTION", 45)
    store.set("WINCH_TYPE", 1)
    Winch(store, [0] * 16, lambda text, severity: None, lambda: None, Radio())
    assert store["RC9_DZ"] == 30
    store.save_all()
    assert ParamStore(path)["RC9_DZ"] == 0  # back to ArduPilot's own default at the next boot
    store.set("RC9_DZ", 12)
    assert ParamStore(path)["RC9_DZ"] == 12
    store.set("RC9_DZ", 30)  # set to the moved default: not saved, as ArduPilot saves no default
    Winch(ParamStore(path), [0] * 16, lambda text, severity: None, lambda: None, Radio())
    assert ParamStore(path)["RC9_DZ"] == 0

"""AUTOTUNE's dance: the rules and the twitch on their own, then the whole roll tune flown by the
real vehicle (its compiled loops), with ArduCopter's texts, the pilot's pause, leaving the mode and
saving by a disarm in AUTOTUNE."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.modes import ModeNumber
from firefly.autopilot.results import Result
from firefly.autopilot.tuning.axes import PITCH, ROLL, SEQUENCE, YAW, YAW_D, TuneType, completed_names, enabled_axes
from firefly.autopilot.tuning.rules import MIN_D_TEXT, RD_MAX, AxisGains, Rules, back_off
from firefly.autopilot.tuning.twitch import Outcome, Twitch
from firefly.autopilot.vehicle import Vehicle

from ._session_link import Link
from ._util import altitude, fly_until, hovering_vehicle

DT = 0.01


def rate_twitch(target=10000.0, abort=1500.0) -> Twitch:
    return Twitch(False, target, 1500.0, abort, 0.075, 0.0, 1000.0, 0.0, target)


def measured(rate_max: float, rate_min: float, target=10000.0, angle_max=0.0, target_angle=1500.0) -> Twitch:
    t = Twitch(False, target, target_angle, 1500.0, 0.075, 0.0, 40.0, 0.0, target)
    t.rate_max, t.rate_min, t.angle_max = rate_max, rate_min, angle_max
    return t


def gains() -> AxisGains:
    return AxisGains(rp=0.135, rd=0.0036, sp=4.5, accel=110000.0)


# ----- the axes ----------------------------------------------------------------------------------
def test_axes_come_in_arducopters_order_and_name_themselves_as_its_texts_do():
    assert enabled_axes(7) == (ROLL, PITCH, YAW)
    assert enabled_axes(15) == (ROLL, PITCH, YAW, YAW_D)
    assert enabled_axes(1) == (ROLL,) and enabled_axes(0) == ()
    assert completed_names((ROLL, PITCH, YAW)) == "Roll Pitch Yaw(E)"  # as "Saved gains for %s%s%s%s"
    assert completed_names((ROLL,)) == "Roll "
    assert [t.value for t in SEQUENCE] == ["Rate D Up", "Rate D Down", "Rate P Up", "Angle P Down", "Angle P Up"]


# ----- one twitch --------------------------------------------------------------------------------
def test_a_rate_twitch_ends_past_its_target_or_when_it_falls_back():
    t = rate_twitch()
    assert t.update(100.0, 5000.0, 0.05, DT) is Outcome.RUNNING
    assert t.update(200.0, 10500.0, 0.06, DT) is Outcome.UPDATE_GAINS
    t = rate_twitch()
    t.update(100.0, 8000.0, 0.05, DT)
    assert t.update(200.0, 7000.0, 0.06, DT) is Outcome.UPDATE_GAINS  # fell back 12.5 % > 7.5 %
    assert (t.rate_max, t.rate_min) == pytest.approx((8000.0, 7000.0), rel=0.03)  # through its filter


def test_a_rate_twitch_times_out_at_three_times_its_rise_and_shrinks_when_out_of_room():
    t = rate_twitch()
    assert t.update(10.0, 1000.0, 0.1, DT) is Outcome.RUNNING  # below 63 %: time-out 0.3 s
    assert t.update(20.0, 7000.0, 0.2, DT) is Outcome.RUNNING
    assert t.update(30.0, 7100.0, 0.31, DT) is Outcome.UPDATE_GAINS
    t = rate_twitch()  # still rising when the lean limit comes: the step was too big
    t.update(1000.0, 5000.0, 0.1, DT)
    assert t.update(1600.0, 5500.0, 0.12, DT) is Outcome.SHRINK


def test_an_angle_twitch_ends_past_its_angle():
    t = Twitch(True, 10000.0, 1500.0, 1500.0, 0.075, 0.0, 1000.0, 0.0, 1500.0 * 1.0375)
    assert t.update(1000.0, 8000.0, 0.1, DT) is Outcome.RUNNING
    assert t.update(1600.0, 3000.0, 0.15, DT) is Outcome.UPDATE_GAINS
    assert t.accel_max == pytest.approx(8000.0 / 0.1, rel=0.03)  # the peak rate over its time


# ----- the rules ---------------------------------------------------------------------------------
def test_rate_d_up_raises_d_until_the_twitch_bounces_back():
    rules, g = Rules(0.075, 0.0005), gains()
    assert rules.apply(TuneType.RATE_D_UP, ROLL, g, measured(9500.0, 9400.0)) == []
    assert g.rd == pytest.approx(0.0036 * 1.1) and rules.success == 0
    rules.apply(TuneType.RATE_D_UP, ROLL, g, measured(9500.0, 8000.0))  # bounced: a success
    assert rules.success == 1 and rules.ignore_next
    rules.apply(TuneType.RATE_D_UP, ROLL, g, measured(9500.0, 9400.0))  # the one after is ignored
    assert rules.success == 1 and g.rd == pytest.approx(0.0036 * 1.1)
    g.rd = RD_MAX * 0.99
    rules.apply(TuneType.RATE_D_UP, ROLL, g, measured(9500.0, 9400.0))
    assert g.rd == RD_MAX and rules.done  # at the ceiling: done


def test_short_of_the_target_rate_p_rises_and_past_it_p_falls():
    rules, g = Rules(0.075, 0.0005), gains()
    rules.apply(TuneType.RATE_D_DOWN, ROLL, g, measured(7000.0, 7000.0))
    assert g.rp == pytest.approx(0.135 * 1.05)
    rules.apply(TuneType.RATE_D_DOWN, ROLL, g, measured(11000.0, 11000.0))
    assert g.rp == pytest.approx(0.135 * 1.05 * 0.95)


def test_rate_d_down_lowers_d_while_it_bounces_and_says_when_it_reaches_the_floor():
    rules, g = Rules(0.075, 0.0005), gains()
    rules.apply(TuneType.RATE_D_DOWN, ROLL, g, measured(9500.0, 8000.0))
    assert g.rd == pytest.approx(0.0036 * 0.95)
    g.rd = 0.00051
    assert rules.apply(TuneType.RATE_D_DOWN, ROLL, g, measured(9500.0, 8000.0)) == [MIN_D_TEXT]
    assert g.rd == 0.0005 and rules.done


def test_yaw_e_tunes_its_error_filter_in_place_of_d():
    rules, g = Rules(0.075, 0.0005), AxisGains(rp=1.0, rd=0.0, sp=4.5, accel=27000.0, flte=2.5)
    rules.apply(TuneType.RATE_D_UP, YAW, g, measured(9500.0, 9400.0))
    assert g.flte == pytest.approx(2.75) and g.rd == 0.0


def test_angle_p_up_until_it_overshoots_then_keeps_90_percent_and_the_acceleration_reached():
    rules, g = Rules(0.075, 0.0005), gains()
    rules.apply(TuneType.ANGLE_P_UP, ROLL, g, measured(5000.0, 0.0, angle_max=1400.0))
    assert g.sp == pytest.approx(4.5 * 1.05)
    for _ in range(8):
        rules.apply(TuneType.ANGLE_P_UP, ROLL, g, measured(5000.0, 0.0, angle_max=1600.0))
    assert rules.done
    t = measured(5000.0, 0.0)
    t.accel_max = 300000.0
    back_off(TuneType.ANGLE_P_UP, ROLL, g, t)
    assert g.sp == pytest.approx(4.5 * 1.05 * 0.9) and g.accel == 300000.0


# ----- the dance, flown --------------------------------------------------------------------------
def hold_centred(v: Vehicle, seconds: float, until=None, texts: list | None = None, roll: float = 0.0) -> bool:
    def held(x: Vehicle) -> bool:
        x.rc.hold_sticks(roll, 0.0, 0.0, 0.5, x.time_s)
        if texts is not None:
            texts.extend(text for _, text in x.drain_events())
        return until is not None and until(x)
    return fly_until(v, held, seconds, step_s=0.1)


def tuning_vehicle() -> Vehicle:
    v = hovering_vehicle()
    v.params.set("AUTOTUNE_AXES", 1)
    v.set_mode(ModeNumber.ALT_HOLD)
    hold_centred(v, 1.0)
    v.drain_events()
    return v


def rate_p(v: Vehicle) -> float:
    return v.cascade.attitude_ctl.rate_pids[0].kp


@pytest.fixture(scope="module")
def tuned() -> tuple[Vehicle, list[str], float]:
    """A vehicle that has tuned roll (AUTOTUNE_AXES 1) and the texts it said on the way."""
    v = tuning_vehicle()
    start = v.time_s
    texts: list[str] = []
    assert v.set_mode(ModeNumber.AUTOTUNE) == Result.ACCEPTED
    assert hold_centred(v, 400.0, lambda x: "AutoTune: Success" in texts or "Failed" in " ".join(texts), texts)
    return v, texts, v.time_s - start


def test_roll_is_tuned_in_arducopters_sequence_with_its_texts(tuned):
    v, texts, took = tuned
    stages = []
    for text in texts:
        if text.startswith("AutoTune: Roll ") and text.endswith("%"):
            stage = text[len("AutoTune: Roll "):].rsplit(" ", 1)[0]
            if not stages or stages[-1] != stage:
                stages.append(stage)
    assert stages == [t.value for t in SEQUENCE]
    done = [t for t in texts if not t.endswith("%")]
    assert done[0] == "AutoTune: Started" and done[-1] == "AutoTune: Success"
    assert done[1] == "AutoTune: Roll complete"
    assert done[2].startswith("AutoTune: Roll Rate: P:") and done[3].startswith("AutoTune: Roll Angle P:")
    assert 30.0 < took < 400.0
    hold_centred(v, 2.0)
    assert abs(v.attitude[0]) < math.radians(5.0) and abs(altitude(v) - 10.0) < 1.5  # held its height
    assert v.mode_number == ModeNumber.AUTOTUNE
    assert rate_p(v) == v.params["ATC_RAT_RLL_P"] == 0.135  # done: the original gains fly


def test_out_and_back_flies_the_tuned_gains_and_a_disarm_in_autotune_saves_them(tuned):
    v, _, _ = tuned
    assert v.set_mode(ModeNumber.ALT_HOLD) == Result.ACCEPTED
    assert [t for _, t in v.drain_events()] == ["AutoTune: Stopped"]
    hold_centred(v, 1.0)
    assert v.set_mode(ModeNumber.AUTOTUNE) == Result.ACCEPTED
    hold_centred(v, 1.0)
    assert [t for _, t in v.drain_events()] == ["AutoTune: Pilot Testing gains for Roll "]
    tuned_p = rate_p(v)
    assert tuned_p != 0.135 and v.params["ATC_RAT_RLL_P"] == 0.135  # flown, not yet saved
    landed = fly_until(v, lambda x: x.rc.hold_sticks(0.0, 0.0, 0.0, 0.0, x.time_s) or not x.armed, 120.0)
    assert landed
    assert [t for _, t in v.drain_events() if t.startswith(("AutoTune", "Disarming"))] == [
        "Disarming motors", "AutoTune: Saved gains for Roll "]
    assert v.params["ATC_RAT_RLL_P"] == tuned_p and v.params["ATC_RAT_RLL_I"] == tuned_p
    assert "ATC_RAT_RLL_P" in v.params.vehicle_saved  # for the ground stations, as ArduCopter sends it


def test_the_pilots_sticks_pause_the_dance_on_the_original_gains():
    v = tuning_vehicle()
    assert v.set_mode(ModeNumber.AUTOTUNE) == Result.ACCEPTED
    hold_centred(v, 3.0)
    texts: list[str] = []
    hold_centred(v, 2.0, texts=texts, roll=0.3)
    assert "AutoTune: pilot overrides active" in texts
    dance = v.modes[ModeNumber.AUTOTUNE]._dance
    assert dance.twitch is None and rate_p(v) == v.params["ATC_RAT_RLL_P"]
    assert v.attitude[0] > math.radians(5.0)  # the pilot's lean, flown
    texts.clear()
    hold_centred(v, 3.0, texts=texts)
    assert any(t.startswith("AutoTune: Roll Rate D Up") for t in texts)  # resumed


def test_leaving_mid_tune_restores_the_gains_and_a_disarm_elsewhere_saves_nothing():
    v = tuning_vehicle()
    assert v.set_mode(ModeNumber.AUTOTUNE) == Result.ACCEPTED
    twitched = hold_centred(v, 10.0, lambda x: rate_p(x) != 0.135 or x.cascade.attitude_ctl.rate_pids[0].ki != 0.135)
    assert twitched  # a trial set was flown
    assert v.set_mode(ModeNumber.ALT_HOLD) == Result.ACCEPTED
    pid = v.cascade.attitude_ctl.rate_pids[0]
    assert (pid.kp, pid.ki, pid.kd, pid.d_on_error) == (0.135, 0.135, 0.0036, 0.0)
    assert fly_until(v, lambda x: x.rc.hold_sticks(0.0, 0.0, 0.0, 0.0, x.time_s) or not x.armed, 120.0)
    assert v.params["ATC_RAT_RLL_P"] == 0.135 and v.params.vehicle_saved == []


def test_with_no_axis_to_tune_it_holds_and_touching_down_disarms():
    v = tuning_vehicle()
    v.params.set("AUTOTUNE_AXES", 0)
    assert v.set_mode(ModeNumber.AUTOTUNE) == Result.ACCEPTED
    hold_centred(v, 5.0)
    assert abs(v.attitude[0]) < math.radians(2.0) and v.mode_number == ModeNumber.AUTOTUNE
    start = v.time_s
    assert fly_until(v, lambda x: x.rc.hold_sticks(0.0, 0.0, 0.0, 0.0, x.time_s) or not x.armed, 60.0)
    assert v.time_s - start < 9.0  # on touching down, not after DISARM_DELAY


def test_gains_the_vehicle_saves_are_announced_to_every_link():
    link = Link()
    link.vehicle.params.set("ATC_ANG_RLL_P", 36.0, in_range=False)  # beyond the documented 3..12
    link.poll()
    announced = link.session.take_announced()
    assert [(asker, m.param_id, m.param_value) for asker, m in announced] == [(None, "ATC_ANG_RLL_P", 36.0)]
    link.poll()
    assert link.session.take_announced() is None  # once

"""The pilot's radio (autopilot/rc/): channel normalisation, the ground station's system id,
override lifetimes and field values, the flight-mode switch's bands, the aux functions and
DO_AUX_FUNCTION, and what a closed throttle does to ALT_HOLD."""
from __future__ import annotations

import pytest

from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.modes import ModeNumber as M
from firefly.autopilot.rc.aux import AUX_FUNCTIONS, announcement
from firefly.autopilot.rc.channels import (HIGH, LOW, MIDDLE, Calibration, mode_switch_position, stick, stick_pwm,
                                           switch_position, throttle, throttle_mid, throttle_pwm)
from firefly.autopilot.rc.switches import Debounced
from firefly.autopilot.results import Result

from ._session_link import SYSTEM_ID, Link
from ._util import altitude, command_long, fly_until, hovering_vehicle, mav, ready_vehicle, statustexts, wire

STICK = Calibration(1000, 1500, 2000, 20)
THROTTLE = Calibration(1000, 1500, 2000, 30)
RELEASE, LEAVE = 0, 65535


def test_a_stick_reads_zero_inside_its_dead_zone_and_full_scale_at_its_ends():
    assert stick(1500, STICK) == stick(1520, STICK) == stick(1480, STICK) == 0.0
    assert stick(2000, STICK) == 1.0 and stick(1000, STICK) == -1.0
    assert stick(2100, STICK) == 1.0  # held within RCn_MIN..MAX
    assert stick(1760, STICK) == pytest.approx(240 / 480)
    assert stick(1760, Calibration(1000, 1500, 2000, 20, reversed=True)) == pytest.approx(-0.5)
    for value in (-1.0, -0.3, 0.0, 0.25, 1.0):
        assert stick(stick_pwm(value, STICK), STICK) == pytest.approx(value, abs=2e-3)


def test_the_throttle_reads_from_the_top_of_its_bottom_dead_zone():
    assert throttle(1000, THROTTLE) == throttle(1030, THROTTLE) == 0.0
    assert throttle(2000, THROTTLE) == 1.0
    assert throttle(1515, THROTTLE) == pytest.approx(485 / 970)
    assert throttle_mid(THROTTLE) == 0.484  # ArduCopter's get_control_mid(): 484 of 1000
    assert throttle(throttle_pwm(0.7, THROTTLE), THROTTLE) == pytest.approx(0.7, abs=2e-3)


def test_switch_positions_follow_arducopters_pwm_bands():
    assert [switch_position(p) for p in (800, 801, 1199, 1200, 1800, 1801, 2199, 2200)] == \
        [None, LOW, LOW, MIDDLE, MIDDLE, HIGH, HIGH, None]
    assert switch_position(1000, reversed_switch=True) == HIGH
    edges = [(1230, 0), (1231, 1), (1360, 1), (1361, 2), (1490, 2), (1491, 3), (1620, 3), (1621, 4),
             (1749, 4), (1750, 5), (2199, 5)]
    assert [mode_switch_position(p) for p, _ in edges] == [k for _, k in edges]
    assert mode_switch_position(800) is None and mode_switch_position(2200) is None


def test_a_switch_counts_once_it_has_held_200_ms():
    d = Debounced()
    d.settle(LOW)
    assert not d.read(HIGH, 1.0) and not d.read(HIGH, 1.1)
    assert d.read(HIGH, 1.2) and d.current == HIGH
    assert not d.read(HIGH, 1.3)  # no news
    assert not d.read(LOW, 2.0) and not d.read(MIDDLE, 2.1) and not d.read(LOW, 2.25)  # a flick: starts again
    assert d.read(LOW, 2.45)


def _override(link: Link, *pwm: int, sysid: int = 255) -> None:
    codec = new_codec(sysid, 190)
    fields = list(pwm) + [LEAVE] * (8 - len(pwm))
    link.send(wire(codec.rc_channels_override_encode(SYSTEM_ID, 1, *fields), codec))
    link.vehicle.rc.read(link.vehicle.time_s)


def test_overrides_count_from_the_ground_stations_system_id_only():
    link = Link(ready_vehicle())
    v = link.vehicle
    _override(link, 1500, 1500, 1700, 1500, sysid=245)  # MAVSDK's ManualControl's id
    assert v.rc.channel_us(3) == 1000 and v.pilot.throttle == 0.0
    codec = new_codec(245, 190)
    link.send(wire(codec.manual_control_encode(SYSTEM_ID, 0, 0, 800, 0, 0), codec))
    v.rc.read(v.time_s)
    assert v.rc.channel_us(3) == 1000
    _override(link, 1500, 1500, 1700, 1500)
    assert v.rc.channel_us(3) == 1700 and v.pilot.throttle == pytest.approx(670 / 970)
    v.params.set("MAV_GCS_SYSID", 245)
    _override(link, 1500, 1500, 1300, 1500, sysid=245)
    assert v.rc.channel_us(3) == 1300


def test_override_fields_zero_releases_uint16_max_leaves_and_the_override_lapses():
    link = Link(ready_vehicle())
    v = link.vehicle
    _override(link, 1600, 1400, 1500, 1700, 1100)
    assert v.rc.radio_in[:5] == [1600, 1400, 1500, 1700, 1100]
    _override(link, RELEASE, LEAVE, LEAVE, LEAVE)
    assert v.rc.radio_in[:5] == [1500, 1400, 1500, 1700, 1100]  # channel 1 back to the receiver
    v.run_until(v.time_s + 3.1)  # RC_OVERRIDE_TIME
    assert v.rc.radio_in[:5] == [1500, 1500, 1000, 1500, 1800]
    v.params.set("RC_OVERRIDE_TIME", 0)  # overrides off
    _override(link, 1600)
    assert v.rc.channel_us(1) == 1500


def test_channels_9_to_16_take_zero_as_leave_and_uint16_max_minus_one_as_release():
    link = Link(ready_vehicle())
    v = link.vehicle
    codec = new_codec(255, 190)
    chans = [LEAVE] * 8 + [1700] + [0] * 9
    link.send(wire(codec.rc_channels_override_encode(SYSTEM_ID, 1, *chans), codec))
    v.rc.read(v.time_s)
    assert v.rc.channel_us(9) == 1700
    chans[8] = 0
    link.send(wire(codec.rc_channels_override_encode(SYSTEM_ID, 1, *chans), codec))
    assert v.rc.overrides.values[8] == 1700
    chans[8] = 65534
    link.send(wire(codec.rc_channels_override_encode(SYSTEM_ID, 1, *chans), codec))
    assert v.rc.overrides.values[8] == 0


def test_the_mode_switch_moved_by_an_override_takes_its_fltmode_after_the_debounce():
    link = Link(ready_vehicle())
    v = link.vehicle
    assert v.mode.number == M.STABILIZE  # switch at 1800: FLTMODE6
    _override(link, LEAVE, LEAVE, LEAVE, LEAVE, 1555)  # position 4: FLTMODE4 (AUTO in SITL's copter.parm)
    v.run_until(v.time_s + 0.1)
    assert v.mode.number == M.STABILIZE
    v.run_until(v.time_s + 0.2)
    assert v.mode.number == int(v.params["FLTMODE4"]) == M.AUTO
    assert v.set_mode(M.GUIDED) == Result.ACCEPTED
    v.run_until(v.time_s + 1.0)
    assert v.mode.number == M.GUIDED  # the switch has not moved: a ground station's mode stays


def test_do_aux_function_answers_as_arducopter():
    link = Link(hovering_vehicle(10.0))
    v = link.vehicle
    ack = link.send(command_long(mav.MAV_CMD_DO_AUX_FUNCTION, 4, 2))  # RTL, high
    assert ack[0].result == mav.MAV_RESULT_ACCEPTED and v.mode.number == M.RTL
    ack = link.send(command_long(mav.MAV_CMD_DO_AUX_FUNCTION, 4, 0))  # RTL low: the switch's mode back
    assert ack[0].result == mav.MAV_RESULT_ACCEPTED
    v.run_until(v.time_s + 0.3)
    assert v.mode.number == int(v.params["FLTMODE6"])
    out = link.send(command_long(mav.MAV_CMD_DO_AUX_FUNCTION, 9999, 2))
    assert of_result(out) == mav.MAV_RESULT_FAILED and "Invalid channel option (9999)" in texts(link)
    assert of_result(link.send(command_long(mav.MAV_CMD_DO_AUX_FUNCTION, 4, 3))) == mav.MAV_RESULT_DENIED


def of_result(out) -> int:
    return [m for m in out if m.get_type() == "COMMAND_ACK"][0].result


def texts(link: Link) -> list[str]:
    return statustexts(link.poll())


def test_the_aux_table_runs_mode_functions_at_high_and_announces_only_its_own():
    assert AUX_FUNCTIONS[42].name == "SMART_RTL" and AUX_FUNCTIONS[31].announce == "MotorEStop"
    assert announcement(7, 7, HIGH) == "RC7: SaveWaypoint HIGH"
    assert announcement(8, 4, HIGH) is None


def test_an_aux_switch_on_a_channel_changes_the_mode_and_estop_stops_the_motors():
    link = Link(hovering_vehicle(10.0))
    v = link.vehicle
    v.params.set("RC6_OPTION", 18)  # LAND
    v.params.set("RC_OVERRIDE_TIME", -1)
    _override(link, 1500, 1500, 1500, 1500, LEAVE, 1900)
    v.run_until(v.time_s + 0.5)
    assert v.mode.number == M.LAND
    v.params.set("RC8_OPTION", 31)  # motor emergency stop
    _override(link, LEAVE, LEAVE, LEAVE, LEAVE, LEAVE, LEAVE, LEAVE, 1900)
    v.run_until(v.time_s + 0.5)
    assert v.motors_emergency_stopped and "RC8: MotorEStop HIGH" in texts(link)
    assert fly_until(v, lambda x: altitude(x) < 1.0, 10.0)  # it falls


def test_alt_hold_descends_with_sitls_closed_throttle_and_holds_at_mid():
    v = hovering_vehicle(10.0)
    assert v.set_mode(M.ALT_HOLD) == Result.ACCEPTED
    v.run_until(v.time_s + 2.0)
    assert altitude(v) < 8.0  # towards PILOT_SPEED_UP (PILOT_SPEED_DN 0): 2.5 m/s down
    v.params.set("RC_OVERRIDE_TIME", -1)
    v.rc.hold_sticks(0.0, 0.0, 0.0, 0.5, v.time_s)
    v.run_until(v.time_s + 3.0)  # the descent braked
    held = altitude(v)
    v.run_until(v.time_s + 3.0)
    assert abs(altitude(v) - held) < 0.3


def test_an_override_stream_keeps_the_radio_alive_without_receiver_frames():
    link = Link(hovering_vehicle(10.0))
    v = link.vehicle
    assert v.set_mode(M.LOITER) == Result.ACCEPTED
    v.params.set("SIM_RC_FAIL", 1)
    for _ in range(30):
        _override(link, 1500, 1500, 1500, 1500)
        v.run_until(v.time_s + 0.1)
    assert v.mode.number == M.LOITER and not v.failsafes.radio
    v.run_until(v.time_s + 2.0)
    assert v.failsafes.radio and v.mode.number == M.RTL


def test_arming_needs_the_throttle_down_and_above_the_failsafe_value():
    v = ready_vehicle()
    v.params.set("RC_OVERRIDE_TIME", -1)
    assert v.set_mode(M.ALT_HOLD) == Result.ACCEPTED
    v.rc.hold_sticks(0.0, 0.0, 0.0, 0.8, v.time_s)
    assert v.arm() == Result.FAILED and (2, "Arm: Throttle too high") in v.drain_events()
    # In GUIDED a ground station may arm with the stick up as far as ArduCopter's own check goes;
    # AP_Arming's RC check still wants it neutral (RC_OPTIONS 32, SITL's default)
    assert v.set_mode(M.GUIDED) == Result.ACCEPTED and v.arm() == Result.FAILED
    assert v.drain_events() == [(2, "Arm: Throttle (RC3) is not neutral")]
    v.params.set("RC_OPTIONS", 0)
    assert v.arm() == Result.ACCEPTED
    v.disarm()
    v.params.set("SIM_RC_FAIL", 2)  # the receiver's failsafe values: throttle 950
    v.params.set("RC_OVERRIDE_TIME", 0)
    v.run_until(v.time_s + 0.1)
    assert v.prearm_failure() == "Throttle below failsafe"


def _forward_m(v, n0: float, e0: float, yaw: float) -> float:
    import math
    return (v.body.n_m - n0) * math.cos(yaw) + (v.body.e_m - e0) * math.sin(yaw)


def test_loiter_takes_a_stick_as_a_lean_with_drag_as_ac_loiter():
    """3 s of pitch stick at 1300 us: ArduCopter moved 3.7 m (surface_messages' recording), not
    the 8 m a velocity of LOIT_SPEED times the stick would give; centred, it brakes and holds."""
    v = hovering_vehicle(10.0)
    v.params.set("RC_OVERRIDE_TIME", -1)
    v.rc.hold_sticks(0.0, 0.0, 0.0, 0.5, v.time_s)
    assert v.set_mode(M.LOITER) == Result.ACCEPTED
    v.run_until(v.time_s + 2.0)
    n0, e0, yaw = v.body.n_m, v.body.e_m, v.attitude[2]
    v.rc.overrides.set(1, 1300, v.time_s)
    v.run_until(v.time_s + 3.0)
    assert 3.0 < _forward_m(v, n0, e0, yaw) < 5.0
    v.rc.overrides.set(1, 1500, v.time_s)
    v.run_until(v.time_s + 8.0)  # braked, and back on the point where its target stopped
    stopped = _forward_m(v, n0, e0, yaw)
    v.run_until(v.time_s + 3.0)
    assert abs(_forward_m(v, n0, e0, yaw) - stopped) < 0.3


def test_rtl_near_home_climbs_no_higher_than_its_cone():
    v = hovering_vehicle(10.0)  # over home
    assert v.set_mode(M.RTL) == Result.ACCEPTED
    v.run_until(v.time_s + 4.0)
    assert altitude(v) < 10.5  # RTL_CONE_SLOPE 3 x ~0 m: no climb to RTL_ALT (15 m)
    v = hovering_vehicle(10.0)
    v.guided_goto(v.body.n_m + 30.0, v.body.e_m, v.body.d_m)
    assert fly_until(v, lambda x: abs(x.body.vn_m_s) < 0.1 and x.body.n_m > 29.0, 30.0)
    assert v.set_mode(M.RTL) == Result.ACCEPTED
    assert fly_until(v, lambda x: altitude(x) > 14.5, 15.0)  # 30 m away: the cone allows 90 m, RTL_ALT rules

"""The small link, board and calibration commands (autopilot/mavlink/housekeeping_commands.py) and
the safety switch, as ArduCopter SITL was measured answering them (tests/parity/probes/misc_commands.py)."""
from __future__ import annotations

import math

from firefly.autopilot.mavlink.dialect import mavlink as mav
from firefly.autopilot.mavlink.housekeeping_commands import MAV_CMD_EXTERNAL_WIND_ESTIMATE
from firefly.autopilot.mavlink.sensor_messages import motor_pwm

from ._session_link import Link
from ._util import hovering_vehicle, statustexts

ACCEPTED, DENIED, FAILED, UNSUPPORTED = (mav.MAV_RESULT_ACCEPTED, mav.MAV_RESULT_DENIED, mav.MAV_RESULT_FAILED,
                                         mav.MAV_RESULT_UNSUPPORTED)


def answer(link: Link, command: int, *params) -> tuple[int, list[str]]:
    ack, out = link.command(command, *params)
    return ack.result, statustexts(out + link.poll())


def test_each_answers_as_arducopter_and_high_latency_says_so():
    link = Link()
    assert answer(link, mav.MAV_CMD_CONTROL_HIGH_LATENCY, 1) == (ACCEPTED, ["High Latency enabled"])
    assert answer(link, mav.MAV_CMD_CONTROL_HIGH_LATENCY, 0) == (ACCEPTED, ["High Latency disabled"])
    assert answer(link, mav.MAV_CMD_CONTROL_HIGH_LATENCY, 2) == (FAILED, [])
    assert [answer(link, mav.MAV_CMD_SCRIPTING, n)[0] for n in (0, 1, 2, 3, 9, math.nan)] == \
        [DENIED, DENIED, ACCEPTED, ACCEPTED, UNSUPPORTED, UNSUPPORTED]
    assert [answer(link, MAV_CMD_EXTERNAL_WIND_ESTIMATE, *p)[0] for p in
            ((3, 1, 90, 10), (-1, 1, 90, 10), (3, 1, 400, 10), (3, 1, -5, 10), (math.nan, 0, math.nan, 0))] == \
        [ACCEPTED, DENIED, DENIED, DENIED, ACCEPTED]
    for command, result in ((mav.MAV_CMD_START_RX_PAIR, ACCEPTED), (mav.MAV_CMD_AIRFRAME_CONFIGURATION, ACCEPTED),
                            (mav.MAV_CMD_DO_ACCEPT_MAG_CAL, ACCEPTED), (mav.MAV_CMD_DO_CANCEL_MAG_CAL, ACCEPTED),
                            (mav.MAV_CMD_ACCELCAL_VEHICLE_POS, FAILED)):
        assert answer(link, command, 1, 1)[0] == result
    # STORAGE_FORMAT: the card (1) with "format" (1) is taken, and fails: SITL has none; anything else
    assert [answer(link, mav.MAV_CMD_STORAGE_FORMAT, *p)[0] for p in ((1, 1), (1, 0), (0, 1), (2, 1))] == \
        [FAILED, UNSUPPORTED, UNSUPPORTED, UNSUPPORTED]


def test_a_compass_calibration_starts_only_disarmed_and_reports_its_progress():
    link = Link()
    ack, out = link.command(mav.MAV_CMD_DO_START_MAG_CAL, 0, 0, 1)
    assert ack.result == ACCEPTED and [m.get_type() for m in out].count("MAG_CAL_PROGRESS") == 1
    assert answer(link, mav.MAV_CMD_DO_START_MAG_CAL, 256)[0] == FAILED  # not a compass mask
    assert answer(link, mav.MAV_CMD_FIXED_MAG_CAL_YAW, 0)[0] == ACCEPTED
    flying = Link(hovering_vehicle(10.0))
    ack, out = flying.command(mav.MAV_CMD_DO_START_MAG_CAL, 0, 0, 1)
    assert ack.result == FAILED and "MAG_CAL_PROGRESS" not in [m.get_type() for m in out]
    assert statustexts(out + flying.poll())[-1] == "Disarm to allow compass calibration"
    assert answer(flying, mav.MAV_CMD_FIXED_MAG_CAL_YAW, 0)[0] == ACCEPTED  # in flight too, as SITL


def test_the_safety_switch_cuts_the_motors_refuses_arming_and_a_motor_test():
    link = Link()
    v = link.vehicle
    assert answer(link, mav.MAV_CMD_DO_SET_SAFETY_SWITCH_STATE, 7)[0] == DENIED and not v.safety_on
    assert answer(link, mav.MAV_CMD_DO_SET_SAFETY_SWITCH_STATE, mav.SAFETY_SWITCH_STATE_SAFE)[0] == ACCEPTED
    assert motor_pwm(v) == [0, 0, 0, 0]
    assert answer(link, mav.MAV_CMD_COMPONENT_ARM_DISARM, 1) == (FAILED, ["Arm: Hardware safety switch"])
    assert answer(link, mav.MAV_CMD_DO_MOTOR_TEST, 1, 0, 10, 1) == (FAILED, ["Motor Test: Safety switch"])
    assert answer(link, mav.MAV_CMD_DO_SET_SAFETY_SWITCH_STATE, mav.SAFETY_SWITCH_STATE_DANGEROUS)[0] == ACCEPTED
    assert motor_pwm(v) == [1000] * 4
    assert answer(link, mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)[0] == ACCEPTED


def test_the_safety_switch_in_flight_drops_the_vehicle_until_it_is_off_again():
    v = hovering_vehicle(40.0)
    start = -v.body.d_m
    v.set_safety_switch(True)
    v.run_until(v.time_s + 1.5)
    assert v.armed and start - (-v.body.d_m) > 8.0  # about 11 m of free fall
    v.set_safety_switch(False)
    v.run_until(v.time_s + 6.0)
    assert v.armed and -v.body.d_m > 5.0 and abs(v.body.vd_m_s) < 3.0

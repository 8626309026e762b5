"""The winch on the real process, as a user sets it up with pymavlink: with none, DO_WINCH FAILED;
WINCH_TYPE 1 and a winch output (SERVO9_FUNCTION 88) set and the vehicle rebooted (the winch is
made at boot, as ArduPilot's), then rate and length control by DO_WINCH, read off WINCH_STATUS and
SERVO_OUTPUT_RAW, as the parity area `winch` measured on ArduCopter."""
from __future__ import annotations

import pytest
from pymavlink import mavutil

from .pymav import Gcs, set_param
from .test_mission_progress import gcs  # noqa: F401 - gcs: the fixture
from .test_reboot import reboot_and_wait

pytestmark = pytest.mark.sitl
mav = mavutil.mavlink
RELAX, LENGTH, RATE = 0, 1, 2


def status_where(gcs: Gcs, condition, what: str, timeout: float = 30.0):
    msg = gcs.recv("WINCH_STATUS", timeout, condition)
    assert msg is not None, f"no WINCH_STATUS with {what}"
    return msg


def winch_output(gcs: Gcs) -> int:
    msg = gcs.recv("SERVO_OUTPUT_RAW", 10)
    assert msg is not None, "no SERVO_OUTPUT_RAW"
    return msg.servo9_raw


def test_do_winch_runs_the_line_out_and_in_as_winch_status_reports(gcs):
    assert gcs.command(mav.MAV_CMD_DO_WINCH, 1, RATE, 0, 0.5) == mav.MAV_RESULT_FAILED  # no winch made
    set_param(gcs, "WINCH_TYPE", 1)
    set_param(gcs, "SERVO9_FUNCTION", 88)
    reboot_and_wait(gcs)
    gcs.mav.request_data_stream_send(gcs.conn.target_system, gcs.conn.target_component,
                                     mav.MAV_DATA_STREAM_ALL, 10, 1)
    rest = status_where(gcs, lambda m: True, "the winch at rest")
    assert (rest.line_length, rest.speed, rest.status) == (0.0, 0.0, mav.MAV_WINCH_STATUS_HEALTHY)
    assert rest.temperature == 32767
    assert winch_output(gcs) == 0  # WINCH_OPTIONS bit 0: relaxed from boot, no pulses

    assert gcs.command(mav.MAV_CMD_DO_WINCH, 1, RATE, 0, 0.5) == mav.MAV_RESULT_ACCEPTED
    status_where(gcs, lambda m: m.speed == 0.5 and m.line_length > 1.0, "the line past 1 m at 0.5 m/s")
    assert winch_output(gcs) == 1700  # trim + half of (max - trim): 0.5 of WINCH_RATE_MAX

    assert gcs.command(mav.MAV_CMD_DO_WINCH, 1, RATE, 0, 0) == mav.MAV_RESULT_ACCEPTED  # held where it is
    held = status_where(gcs, lambda m: m.speed == 0.0, "the line held")
    assert gcs.command(mav.MAV_CMD_DO_WINCH, 1, LENGTH, -1.0, 0) == mav.MAV_RESULT_ACCEPTED
    target = held.line_length - 1.0
    done = status_where(gcs, lambda m: abs(m.line_length - target) < 0.02, f"the line at {target:.2f} m")
    assert abs(done.speed) < 0.05

    assert gcs.command(mav.MAV_CMD_DO_WINCH, 1, 9, 0, 0) == mav.MAV_RESULT_FAILED  # LOAD_PAYLOAD: not handled
    assert gcs.command(mav.MAV_CMD_DO_WINCH, 1, RELAX, 0, 0) == mav.MAV_RESULT_ACCEPTED
    assert gcs.recv("SERVO_OUTPUT_RAW", 10, lambda m: m.servo9_raw == 0) is not None

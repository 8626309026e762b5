"""pymavlink scripts against the real autopilot process: identity, modes, parameters, refusals."""
from __future__ import annotations

import math
import socket

import pytest
from pymavlink import mavutil

from .pymav import Gcs

pytestmark = pytest.mark.sitl
mav = mavutil.mavlink
GUIDED, LOITER, LAND, BRAKE = 4, 5, 9, 17


@pytest.fixture
def gcs(autopilot):
    g = Gcs(autopilot.pymavlink_url)
    yield g
    g.close()


def heartbeat(gcs, condition=None, timeout=5.0):
    hb = gcs.recv("HEARTBEAT", timeout, lambda m: m.get_srcSystem() == 1 and (condition is None or condition(m)))
    assert hb is not None, "no matching HEARTBEAT"
    return hb


def test_heartbeat_identifies_an_arducopter(gcs):
    hb = gcs.heartbeat
    assert hb.get_srcSystem() == 1 and hb.get_srcComponent() == 1
    assert hb.type == mav.MAV_TYPE_QUADROTOR
    assert hb.autopilot == mav.MAV_AUTOPILOT_ARDUPILOTMEGA
    assert hb.base_mode & mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED
    assert not hb.base_mode & mav.MAV_MODE_FLAG_SAFETY_ARMED
    assert hb.system_status == mav.MAV_STATE_STANDBY
    assert hb.custom_mode == 0  # ArduCopter boots in STABILIZE
    assert gcs.conn.WIRE_PROTOCOL_VERSION == "2.0" and hb.get_msgbuf()[0] == 0xFD  # MAVLink 2 frame


def test_mode_change_by_do_set_mode_and_set_mode_message(gcs):
    assert gcs.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, GUIDED) == mav.MAV_RESULT_ACCEPTED
    hb = heartbeat(gcs, lambda m: m.custom_mode == GUIDED)
    assert hb.base_mode & mav.MAV_MODE_FLAG_GUIDED_ENABLED
    gcs.mav.set_mode_send(1, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, LOITER)  # unanswered, as ArduCopter 4.7
    heartbeat(gcs, lambda m: m.custom_mode == LOITER)
    # An unknown mode number is refused and the mode stays.
    assert gcs.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, 99) == mav.MAV_RESULT_FAILED
    assert heartbeat(gcs).custom_mode == LOITER


def test_full_parameter_download_has_no_missing_index(gcs):
    gcs.mav.param_request_list_send(1, 1)
    seen, count = {}, None
    while count is None or len(seen) < count:
        msg = gcs.recv("PARAM_VALUE", 5)
        assert msg is not None, f"parameter download stalled at {len(seen)} of {count}"
        count = msg.param_count if count is None else count
        assert msg.param_count == count, "parameter count changed during download"
        seen[msg.param_index] = msg.param_id
    assert sorted(seen) == list(range(count))
    assert len(set(seen.values())) == count
    assert {"PSC_POSXY_P", "ATC_RAT_RLL_P", "WPNAV_SPEED", "RTL_ALT", "PILOT_TKOFF_ALT"} <= set(seen.values())


def test_takeoff_while_disarmed_is_refused(gcs):
    assert gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, GUIDED) == mav.MAV_RESULT_ACCEPTED
    assert gcs.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 10) == mav.MAV_RESULT_FAILED
    assert not heartbeat(gcs).base_mode & mav.MAV_MODE_FLAG_SAFETY_ARMED


def test_unknown_command_is_unsupported(gcs):
    assert gcs.command(31999) == mav.MAV_RESULT_UNSUPPORTED


def test_arming_refused_in_brake_with_statustext(gcs):
    assert gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, BRAKE) == mav.MAV_RESULT_ACCEPTED
    assert gcs.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1) == mav.MAV_RESULT_FAILED
    text = gcs.recv("STATUSTEXT", 5, lambda m: "not armable" in m.text)
    assert text is not None


def test_nan_and_garbage_are_refused_and_the_vehicle_flies_on(autopilot, gcs):
    assert gcs.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, math.nan) == mav.MAV_RESULT_DENIED
    assert gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, math.inf) == mav.MAV_RESULT_DENIED
    # Raw garbage and a truncated frame straight at the vehicle's socket.
    hb = gcs.heartbeat
    addr = next(iter(gcs.conn.clients))  # the address the vehicle sends from
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        for junk in (b"\xfd\x09\x00", b"\x00" * 300, bytes(range(256)), hb.get_msgbuf()[:-3]):
            s.sendto(junk, addr)
    assert gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, GUIDED) == mav.MAV_RESULT_ACCEPTED
    assert gcs.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1) == mav.MAV_RESULT_ACCEPTED
    assert gcs.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 5) == mav.MAV_RESULT_ACCEPTED
    pos = gcs.recv("GLOBAL_POSITION_INT", 20, lambda m: m.relative_alt > 4500)
    assert pos is not None, "vehicle did not climb after the garbage"
    assert autopilot.process.poll() is None


def test_parameters_survive_a_restart_and_wipe_resets_them(autopilot_factory, tmp_path):
    first = autopilot_factory()
    g = Gcs(first.pymavlink_url)
    g.mav.param_set_send(1, 1, b"RTL_ALT", 2500.0, mav.MAV_PARAM_TYPE_REAL32)
    echo = g.recv("PARAM_VALUE", 5, lambda m: m.param_id == "RTL_ALT")
    assert echo is not None and echo.param_value == 2500.0
    g.close()
    assert first.stop() == 0

    def read_rtl_alt(ap):
        g = Gcs(ap.pymavlink_url)
        g.mav.param_request_read_send(1, 1, b"RTL_ALT", -1)
        msg = g.recv("PARAM_VALUE", 5, lambda m: m.param_id == "RTL_ALT")
        g.close()
        ap.stop()
        return msg.param_value

    assert read_rtl_alt(autopilot_factory(wipe=False)) == 2500.0
    assert read_rtl_alt(autopilot_factory(wipe=True)) == 1500.0

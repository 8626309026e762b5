"""MAV_CMD_PREFLIGHT_REBOOT_SHUTDOWN on the real process: the vehicle reboots in place, as
ArduCopter SITL does, and clients keep their link (autopilot/io/reboot.py).

The reference facts (ArduCopter 4.7.0-dev SITL, commit 90700977c553d2dfd95a305acf1c3e098e4d9477,
`--model quad`, measured with pymavlink) are REFERENCE below."""
from __future__ import annotations

import time

import pytest
from mavsdk.asyncio.plugins.action import ActionAsync
from mavsdk.asyncio.plugins.param import ParamAsync
from mavsdk.asyncio.plugins.telemetry import TelemetryAsync

from firefly.groundstation.flight.reference_flight import connect
from firefly.groundstation.flight.vehicle_link import first

from .pymav import GUIDED, Gcs, mav, set_param, upload_mission
from .test_signing import KEY as SIGNING_KEY
from .test_signing import answers_before_probe, intruder, signing_now

pytestmark = pytest.mark.sitl

REBOOT = mav.MAV_CMD_PREFLIGHT_REBOOT_SHUTDOWN
ARM = mav.MAV_CMD_COMPONENT_ARM_DISARM
REFERENCE = {
    "armed": mav.MAV_RESULT_FAILED,  # param 1 = 1 while armed
    "param1_0": mav.MAV_RESULT_UNSUPPORTED,  # disarmed: only 1 (reboot) and 3 (to the bootloader) reboot
    "param1_2": mav.MAV_RESULT_UNSUPPORTED,
    "reboot": mav.MAV_RESULT_ACCEPTED,
    "first_heartbeat_wall_s_at_10x": 0.124,  # after the ACK
    "first_heartbeat_status": mav.MAV_STATE_BOOT,  # until "ArduPilot Ready", then STANDBY
    "boot_texts": ["EKF3 IMU0 initialised", "AHRS: EKF3 active", "EKF3 IMU0 tilt alignment complete"],
    "storage_erase_text": "All parameters reset, reboot board",  # PREFLIGHT_STORAGE param 1 = 2, ACCEPTED
}
FORCE_REBOOT_MAGIC = 20190226  # ArduPilot's: param 6 lets an armed vehicle reboot
WAYPOINTS = [(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 10.0),
             (mav.MAV_CMD_NAV_WAYPOINT, int(1e3), int(1e3), 20.0),
             (mav.MAV_CMD_NAV_WAYPOINT, int(2e3), int(1e3), 20.0)]


def boot_time_ms(gcs: Gcs) -> int:
    gcs.mav.command_long_send(1, 1, mav.MAV_CMD_REQUEST_MESSAGE, 0, mav.MAVLINK_MSG_ID_SYSTEM_TIME, 0, 0, 0, 0, 0, 0)
    msg = gcs.recv("SYSTEM_TIME", 5)
    assert msg is not None, "no SYSTEM_TIME"
    return msg.time_boot_ms


def running_for(gcs: Gcs, seconds: float) -> int:
    """Wait until the vehicle has been up `seconds` (a reboot then sets its clock back for sure);
    its boot time [ms]."""
    msg = gcs.recv("ATTITUDE", 30, lambda m: m.time_boot_ms >= seconds * 1000)
    assert msg is not None, f"the vehicle's clock did not reach {seconds} s"
    return msg.time_boot_ms


def reboot_and_wait(gcs: Gcs, timeout: float = 20.0) -> list[str]:
    """Reboot (ACCEPTED), then wait until the vehicle's boot clock has gone back and it answers
    again; the texts it said meanwhile."""
    before = running_for(gcs, 3.0)
    assert gcs.command(REBOOT, 1) == REFERENCE["reboot"]
    texts, deadline = [], time.monotonic() + timeout
    while time.monotonic() < deadline:
        msg = gcs.recv(["ATTITUDE", "STATUSTEXT"], 1)  # ATTITUDE: streamed, stamped with boot time
        if msg is None:
            continue
        if msg.get_type() == "STATUSTEXT":
            texts.append(msg.text)
        elif msg.time_boot_ms < before:
            return texts
    raise AssertionError("the vehicle's boot clock never went back: no reboot")


def arm_in_guided_once_booted(gcs: Gcs, timeout: float = 30.0) -> None:
    """GUIDED, then ARM until it takes: a rebooted vehicle starts as ArduCopter does (its EKF
    uses the GPS some 41 s of vehicle time after boot: autopilot/startup.py)."""
    assert gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, GUIDED) == mav.MAV_RESULT_ACCEPTED
    deadline = time.monotonic() + timeout
    while gcs.command(ARM, 1) != mav.MAV_RESULT_ACCEPTED:
        assert time.monotonic() < deadline, "not armable in GUIDED after the reboot"
        gcs.recv("HEARTBEAT", 1)  # a vehicle second or so


def mission_count(gcs: Gcs) -> int:
    gcs.mav.mission_request_list_send(1, 1, 0)
    msg = gcs.recv("MISSION_COUNT", 5)
    assert msg is not None
    return msg.count


def read_param(gcs: Gcs, name: str) -> float:
    gcs.mav.param_request_read_send(1, 1, name.encode(), -1)
    msg = gcs.recv("PARAM_VALUE", 5, lambda m: m.param_id == name)
    assert msg is not None, f"no PARAM_VALUE for {name}"
    return msg.param_value


@pytest.mark.serial  # the silence of a reboot, in wall time
def test_reboot_in_place_keeps_saved_state_and_the_link(autopilot):
    gcs = Gcs(autopilot.pymavlink_url)
    try:
        set_param(gcs, "RTL_ALT", 2345)
        upload_mission(gcs, WAYPOINTS)
        before = running_for(gcs, 3.0)
        wall0 = time.monotonic()
        assert gcs.command(REBOOT, 1) == REFERENCE["reboot"]
        # silent, then back on the same socket, its clock started again from zero
        first_beat = gcs.recv("HEARTBEAT", 10)
        silent_s = time.monotonic() - wall0
        assert first_beat is not None and first_beat.system_status == REFERENCE["first_heartbeat_status"]
        assert 0.5 * REFERENCE["first_heartbeat_wall_s_at_10x"] < silent_s < 1.0, silent_s
        after = boot_time_ms(gcs)
        assert after < before and after < 5000, (before, after)
        texts = [m.text for m in iter(lambda: gcs.recv("STATUSTEXT", 3), None)]
        for text in REFERENCE["boot_texts"]:
            assert text in texts, texts
        assert read_param(gcs, "RTL_ALT") == 2345
        assert mission_count(gcs) == len(WAYPOINTS) + 1  # and home
    finally:
        gcs.close()


def test_reboot_refused_while_armed_and_for_other_param1_values(autopilot):
    gcs = Gcs(autopilot.pymavlink_url)
    try:
        assert gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, GUIDED) == mav.MAV_RESULT_ACCEPTED
        assert gcs.command(ARM, 1) == mav.MAV_RESULT_ACCEPTED
        assert gcs.command(REBOOT, 1) == REFERENCE["armed"]
        assert gcs.recv("HEARTBEAT", 3, lambda m: m.base_mode & mav.MAV_MODE_FLAG_SAFETY_ARMED) is not None
        assert gcs.command(ARM, 0) == mav.MAV_RESULT_ACCEPTED
        assert gcs.command(REBOOT, 0) == REFERENCE["param1_0"]
        assert gcs.command(REBOOT, 2) == REFERENCE["param1_2"]
        # ArduPilot's force: an armed vehicle reboots with the magic in param 6
        assert gcs.command(ARM, 1) == mav.MAV_RESULT_ACCEPTED
        assert gcs.command(REBOOT, 1, 0, 0, 0, 0, FORCE_REBOOT_MAGIC) == mav.MAV_RESULT_ACCEPTED
        assert gcs.recv("HEARTBEAT", 10, lambda m: not m.base_mode & mav.MAV_MODE_FLAG_SAFETY_ARMED) is not None
    finally:
        gcs.close()


def test_storage_erase_takes_effect_at_the_next_boot(autopilot):
    gcs = Gcs(autopilot.pymavlink_url)
    try:
        set_param(gcs, "RTL_ALT", 2345)
        assert gcs.command(mav.MAV_CMD_PREFLIGHT_STORAGE, 1) == mav.MAV_RESULT_DENIED
        assert gcs.command(mav.MAV_CMD_PREFLIGHT_STORAGE, 2) == mav.MAV_RESULT_ACCEPTED
        text = gcs.recv("STATUSTEXT", 3)
        assert text is not None and text.text == REFERENCE["storage_erase_text"]
        assert read_param(gcs, "RTL_ALT") == 2345  # in use until the reboot
        reboot_and_wait(gcs)
        assert read_param(gcs, "RTL_ALT") != 2345
    finally:
        gcs.close()


def test_reboot_never_down_mid_transfers_and_twice_in_a_row(autopilot):
    gcs = Gcs(autopilot.pymavlink_url)
    try:
        # in the middle of a mission upload: the vehicle asked for item 0, the reboot cuts it off
        gcs.mav.mission_count_send(1, 1, 5, 0)
        assert gcs.recv(["MISSION_REQUEST_INT", "MISSION_REQUEST"], 5) is not None
        reboot_and_wait(gcs)
        # in the middle of a parameter download
        gcs.mav.param_request_list_send(1, 1)
        assert gcs.recv("PARAM_VALUE", 5) is not None
        reboot_and_wait(gcs)
        # twice in a row, the second sent while the first is still booting (it is lost, as on
        # ArduCopter: the vehicle hears nothing then) and again once it is back
        assert gcs.command(REBOOT, 1) == mav.MAV_RESULT_ACCEPTED
        gcs.mav.command_long_send(1, 1, REBOOT, 0, 1, 0, 0, 0, 0, 0, 0)
        assert gcs.recv("HEARTBEAT", 10) is not None
        reboot_and_wait(gcs)
        # and it still works: a mission upload and a takeoff
        upload_mission(gcs, WAYPOINTS)
        assert mission_count(gcs) == len(WAYPOINTS) + 1
        arm_in_guided_once_booted(gcs)
        assert gcs.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 5.0) == mav.MAV_RESULT_ACCEPTED
        assert gcs.recv("GLOBAL_POSITION_INT", 30, lambda m: m.relative_alt > 4500) is not None
    finally:
        gcs.close()


async def test_mavsdk_reconnects_after_a_reboot_and_flies_again(autopilot):
    mavsdk, system = await connect(autopilot.mavsdk_url)
    try:
        telemetry, action, param = TelemetryAsync(system), ActionAsync(system), ParamAsync(system)
        await param.set_param_int("RTL_ALT", 2345)
        await action.reboot()
        # the vehicle goes silent and comes back on the same connection: not armable while it
        # boots (its EKF and GPS start again), then armable, with its saved parameter
        await first(telemetry.subscribe_health(), lambda h: not h.is_armable, 10, "booting again")
        await first(telemetry.subscribe_health(), lambda h: h.is_armable and h.is_global_position_ok
                    and h.is_home_position_ok, 60, "armable after the reboot")
        assert await param.get_param_int("RTL_ALT") == 2345
        await action.arm()
        await first(telemetry.subscribe_armed(), bool, 5, "armed")
        await action.set_takeoff_altitude(5.0)
        await action.takeoff()
        await first(telemetry.subscribe_position(), lambda p: p.relative_altitude_m > 4.5, 30, "5 m altitude")
    finally:
        mavsdk.destroy()


def test_a_key_set_over_the_link_survives_the_reboot(autopilot):
    """SETUP_SIGNING's key is kept as ArduPilot keeps it in storage: after the reboot the vehicle
    signs what it sends and drops unsigned commands, and the client's signed reboot went through."""
    gcs = Gcs(autopilot.pymavlink_url)
    try:
        gcs.mav.setup_signing_send(1, 1, list(SIGNING_KEY), signing_now())
        gcs.conn.setup_signing(SIGNING_KEY, sign_outgoing=True, link_id=1)
        assert gcs.recv("HEARTBEAT", 5, lambda m: m.get_signed()) is not None  # it took the key
        reboot_and_wait(gcs)
        fresh = gcs.recv("HEARTBEAT", 5)
        assert fresh is not None and fresh.get_signed()
        unsigned = intruder(gcs)
        unsigned.mav.command_long_send(1, 1, ARM, 0, 1, 0, 0, 0, 0, 0, 0)
        unsigned.close()
        assert answers_before_probe(gcs) == []  # the unsigned ARM was dropped, the signed probe answered
    finally:
        gcs.close()

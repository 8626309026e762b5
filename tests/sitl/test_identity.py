"""Which ArduCopter the real process says it is, and the preflight commands' answers, against the
reference: ArduCopter 4.7.0-dev SITL, commit 90700977c553d2dfd95a305acf1c3e098e4d9477, `--model
quad`, measured with pymavlink (REFERENCE below; autopilot/version.py, autopilot/mavlink/preflight.py)."""
from __future__ import annotations

import pytest

from firefly.autopilot.io.board_id import read_machine_id
from firefly.autopilot.version import board_id_for

from .pymav import GUIDED, Gcs, mav

pytestmark = pytest.mark.sitl

REFERENCE = {
    "capabilities": 64495,
    "flight_sw_version": 0x04070000,  # 4.7.0, FIRMWARE_VERSION_TYPE_DEV (0)
    "flight_custom_version": b"90700977",
    "zeros": ("middleware_sw_version", "os_sw_version", "board_version", "vendor_id", "product_id", "uid"),
    "banner": ["ArduCopter V4.7.0-dev (90700977)", "<board id>", "Frame: QUAD/PLUS"],  # all INFO
    "calibration": {  # PREFLIGHT_CALIBRATION params, disarmed -> (result, texts)
        (0, 0, 0, 0, 0, 0, 0): (mav.MAV_RESULT_UNSUPPORTED, []),
        (1, 0, 0, 0, 0, 0, 0): (mav.MAV_RESULT_ACCEPTED, []),  # gyros
        (0, 0, 1, 0, 0, 0, 0): (mav.MAV_RESULT_ACCEPTED, ["Updating barometer calibration",
                                                          "Barometer calibration complete"]),
        (0, 0, 0, 1, 0, 0, 0): (mav.MAV_RESULT_UNSUPPORTED, []),  # the radio calibration flag alone
        (0, 76, 0, 0, 0, 0, 0): (mav.MAV_RESULT_ACCEPTED, []),  # keep the compass calibration
        (0, 0, 0, 0, 76, 0, 0): (mav.MAV_RESULT_ACCEPTED, []),  # keep the accelerometer calibration
    },
    "calibration_armed": (mav.MAV_RESULT_FAILED, "Disarm to allow calibration"),
    "run_prearm_checks_armed": mav.MAV_RESULT_TEMPORARILY_REJECTED,
}


def texts(gcs: Gcs, count: int) -> list:
    found = [gcs.recv("STATUSTEXT", 3) for _ in range(count)]
    assert all(found), f"fewer than {count} texts: {found}"
    return found


def test_autopilot_version_and_banner_are_the_references(autopilot):
    board_id = board_id_for(read_machine_id(), 0)  # instance 0
    gcs = Gcs(autopilot.pymavlink_url)
    try:
        result, version = gcs.command_with_reply(mav.MAV_CMD_REQUEST_MESSAGE, "AUTOPILOT_VERSION",
                                                 mav.MAVLINK_MSG_ID_AUTOPILOT_VERSION)
        assert result == mav.MAV_RESULT_ACCEPTED
        assert version.capabilities == REFERENCE["capabilities"]
        assert version.flight_sw_version == REFERENCE["flight_sw_version"]
        assert bytes(version.flight_custom_version) == REFERENCE["flight_custom_version"]
        assert all(getattr(version, name) == 0 for name in REFERENCE["zeros"])
        assert bytes(version.uid2) == board_id.encode()[:17].ljust(18, b"\0")
        expected = [board_id if text == "<board id>" else text for text in REFERENCE["banner"]]
        # as ArduPilot: the texts, then the ACK, to the link that asked
        gcs.mav.command_long_send(1, 1, mav.MAV_CMD_DO_SEND_BANNER, 0, 0, 0, 0, 0, 0, 0, 0)
        said = []
        while (m := gcs.recv(["STATUSTEXT", "COMMAND_ACK"], 3)) is not None and m.get_type() == "STATUSTEXT":
            said.append(m)
        assert m is not None and m.command == mav.MAV_CMD_DO_SEND_BANNER and m.result == mav.MAV_RESULT_ACCEPTED
        assert [m.text for m in said] == expected and {m.severity for m in said} == {mav.MAV_SEVERITY_INFO}
        gcs.mav.param_request_list_send(1, 1)  # ArduPilot sends its banner with a parameter download
        assert [m.text for m in texts(gcs, 3)] == expected
    finally:
        gcs.close()


def test_sim_speedup_reads_the_process_speedup(autopilot):
    gcs = Gcs(autopilot.pymavlink_url)  # the fixture runs at --speedup 10
    try:
        gcs.mav.param_request_read_send(1, 1, b"SIM_SPEEDUP", -1)
        value = gcs.recv("PARAM_VALUE", 5, lambda m: m.param_id == "SIM_SPEEDUP")
        assert value is not None and value.param_value == 10.0
    finally:
        gcs.close()


def test_preflight_calibration_as_the_reference_answers(autopilot):
    gcs = Gcs(autopilot.pymavlink_url)
    try:
        for params, (result, said) in REFERENCE["calibration"].items():
            assert gcs.command(mav.MAV_CMD_PREFLIGHT_CALIBRATION, *params) == result, params
            assert [m.text for m in texts(gcs, len(said))] == said, params
        assert gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, GUIDED) == mav.MAV_RESULT_ACCEPTED
        assert gcs.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1) == mav.MAV_RESULT_ACCEPTED
        result, text = REFERENCE["calibration_armed"]
        assert gcs.command(mav.MAV_CMD_PREFLIGHT_CALIBRATION, 0, 0, 1) == result
        assert gcs.recv("STATUSTEXT", 3, lambda m: m.text == text) is not None
        assert gcs.command(mav.MAV_CMD_RUN_PREARM_CHECKS) == REFERENCE["run_prearm_checks_armed"]
    finally:
        gcs.close()

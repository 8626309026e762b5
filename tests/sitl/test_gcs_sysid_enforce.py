"""MAV_OPTIONS bit 0 (ArduPilot's GCS sysid enforcement) on the real process, as measured on
ArduCopter 4.7.0-dev SITL (90700977) with pymavlink: with the bit set, a command or a parameter
read from system 200 gets nothing back, while the ground station (MAV_GCS_SYSID, 255) and the
vehicle's own system id (1, a companion's) are answered; with it clear, everyone is."""
from __future__ import annotations

import pytest

from .pymav import Gcs, mav, set_param

pytestmark = pytest.mark.sitl

STRANGER, GCS_ID, OWN = 200, 255, 1


def answered_from(gcs: Gcs, sender: int) -> tuple[bool, bool]:
    """(command answered, parameter read answered) for a request from system `sender`, judged
    when the ground station's own request sent after it is answered: the vehicle handles the
    link's messages in order, so an answer to the first would have come before."""
    target = gcs.conn.target_system
    gcs.mav.srcSystem = sender
    gcs.mav.command_long_send(target, 1, mav.MAV_CMD_REQUEST_MESSAGE, 0,
                              mav.MAVLINK_MSG_ID_AUTOPILOT_VERSION, 0, 0, 0, 0, 0, 0)
    gcs.mav.param_request_read_send(target, 1, b"MAV_OPTIONS", -1)
    gcs.mav.srcSystem = GCS_ID
    gcs.mav.command_long_send(target, 1, mav.MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES, 0, 1, 0, 0, 0, 0, 0, 0)
    gcs.mav.param_request_read_send(target, 1, b"MAV_GCS_SYSID", -1)
    command = param = False
    ends = {"command": False, "param": False}
    while not all(ends.values()):
        msg = gcs.recv(["COMMAND_ACK", "PARAM_VALUE"], 5)
        assert msg is not None, "the ground station's own requests went unanswered"
        if msg.get_type() == "COMMAND_ACK":
            command |= msg.command == mav.MAV_CMD_REQUEST_MESSAGE and not ends["command"]
            ends["command"] |= msg.command == mav.MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES
        else:
            param |= msg.param_id == "MAV_OPTIONS" and not ends["param"]
            ends["param"] |= msg.param_id == "MAV_GCS_SYSID"
    return command, param


def test_only_the_ground_station_and_own_system_are_heard_with_enforcement(autopilot):
    gcs = Gcs(autopilot.pymavlink_url)
    try:
        assert answered_from(gcs, STRANGER) == (True, True)
        set_param(gcs, "MAV_OPTIONS", 1)
        assert answered_from(gcs, STRANGER) == (False, False)
        assert answered_from(gcs, OWN) == (True, True)
        assert answered_from(gcs, GCS_ID) == (True, True)
        set_param(gcs, "MAV_OPTIONS", 0)
        assert answered_from(gcs, STRANGER) == (True, True)
    finally:
        gcs.close()

"""QGroundControl's connection sequence (src/Vehicle/InitialConnectStateMachine.cc), replayed
step by step with pymavlink: every step must be answered, none may need a timeout to move on."""
from __future__ import annotations

import struct

import pytest
from pymavlink import mavutil

from .pymav import Gcs

pytestmark = pytest.mark.sitl
mav = mavutil.mavlink
STEP_TIMEOUT_S = 2.0  # QGC's own per-step wait is longer; a quick answer is what is checked


@pytest.fixture
def gcs(autopilot):
    g = Gcs(autopilot.pymavlink_url)
    yield g
    g.close()


def test_qgc_connection_sequence_completes(gcs):
    # 1. Autopilot version: capabilities and version numbers QGC decodes.
    result, version = gcs.command_with_reply(mav.MAV_CMD_REQUEST_MESSAGE, "AUTOPILOT_VERSION",
                                             mav.MAVLINK_MSG_ID_AUTOPILOT_VERSION, timeout=STEP_TIMEOUT_S)
    assert result == mav.MAV_RESULT_ACCEPTED
    for cap in ("MISSION_INT", "COMMAND_INT", "PARAM_FLOAT", "MAVLINK2", "SET_POSITION_TARGET_LOCAL_NED"):
        assert version.capabilities & getattr(mav, f"MAV_PROTOCOL_CAPABILITY_{cap}"), cap
    major, minor = version.flight_sw_version >> 24, (version.flight_sw_version >> 16) & 0xFF
    assert (major, minor) >= (4, 0)
    # 2. Parameters over FTP: @PARAM/param.pck opens (QGC then downloads it; the download itself is
    # tests/sitl/test_ftp_params.py), and the session ends when asked.
    assert version.capabilities & mav.MAV_PROTOCOL_CAPABILITY_FTP
    name = b"@PARAM/param.pck"
    for seq, opcode, data in ((7, 4, name), (9, 1, b"")):  # OpenFileRO, TerminateSession
        payload = struct.pack("<HBBBBBBI", seq, 0, opcode, len(data), 0, 0, 0, 0) + data
        gcs.mav.file_transfer_protocol_send(0, 1, 1, list(payload.ljust(251, b"\0")))
        reply = gcs.recv("FILE_TRANSFER_PROTOCOL", STEP_TIMEOUT_S)
        assert reply is not None
        r_seq, _, r_opcode, size, req_opcode = struct.unpack_from("<HBBBB", bytes(reply.payload))
        assert (r_seq, r_opcode, req_opcode) == (seq + 1, 128, opcode)  # ACK
        assert size == (4 if opcode == 4 else 0)  # the open's ACK carries the file size
    # 3. Full parameter list, then a second time with the same count (QGC#4020).
    counts = []
    for _ in range(2):
        gcs.mav.param_request_list_send(1, 1)
        seen = set()
        count = None
        while count is None or len(seen) < count:
            msg = gcs.recv("PARAM_VALUE", STEP_TIMEOUT_S)
            assert msg is not None
            count = msg.param_count
            seen.add(msg.param_index)
        counts.append(count)
    assert counts[0] == counts[1]
    # 4. Mission, fence and rally lists (empty is fine: a count each, ArduPilot's home at seq 0).
    for kind in (mav.MAV_MISSION_TYPE_MISSION, mav.MAV_MISSION_TYPE_FENCE, mav.MAV_MISSION_TYPE_RALLY):
        gcs.mav.mission_request_list_send(1, 1, kind)
        count = gcs.recv("MISSION_COUNT", STEP_TIMEOUT_S, lambda m: m.mission_type == kind)
        assert count is not None
        for seq in range(count.count):
            gcs.mav.mission_request_int_send(1, 1, seq, kind)
            assert gcs.recv("MISSION_ITEM_INT", STEP_TIMEOUT_S, lambda m: m.seq == seq) is not None
        gcs.mav.mission_ack_send(1, 1, 0, kind)
    # 5. Home position (MAVProxy polls this command too).
    result, home = gcs.command_with_reply(mav.MAV_CMD_GET_HOME_POSITION, "HOME_POSITION", timeout=STEP_TIMEOUT_S)
    assert result == mav.MAV_RESULT_ACCEPTED and home.latitude != 0


def test_message_interval_and_data_stream_requests(gcs):
    # Stop ATTITUDE, then ask for 20 Hz and read the interval back.
    assert gcs.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_ATTITUDE, -1) == mav.MAV_RESULT_ACCEPTED
    assert gcs.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_ATTITUDE, 50000) == mav.MAV_RESULT_ACCEPTED
    result, interval = gcs.command_with_reply(mav.MAV_CMD_GET_MESSAGE_INTERVAL, "MESSAGE_INTERVAL",
                                              mav.MAVLINK_MSG_ID_ATTITUDE, timeout=STEP_TIMEOUT_S)
    assert result == mav.MAV_RESULT_ACCEPTED
    assert interval.message_id == mav.MAVLINK_MSG_ID_ATTITUDE and interval.interval_us == 50000
    assert gcs.command(mav.MAV_CMD_REQUEST_MESSAGE, 9999) == mav.MAV_RESULT_FAILED
    # REQUEST_DATA_STREAM stop-all: the position stream stops; restart brings it back.
    gcs.mav.request_data_stream_send(1, 1, 0, 0, 0)
    gcs.recv("HEARTBEAT", 3)  # the stop has been applied by the next heartbeat
    gcs.recv("HEARTBEAT", 3)
    assert gcs.recv("GLOBAL_POSITION_INT", 1.0) is None
    gcs.mav.request_data_stream_send(1, 1, mav.MAV_DATA_STREAM_POSITION, 10, 1)
    assert gcs.recv("GLOBAL_POSITION_INT", 3) is not None

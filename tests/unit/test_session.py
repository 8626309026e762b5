"""The MAVLink session, sans-IO: decoded messages in, messages to send out, in sim time."""
from __future__ import annotations

import math
import struct

import pytest

from autopilot.mavlink.dialect import new_codec
from autopilot.mavlink.session import Session
from autopilot.modes import Brake, Guided, Land, Loiter
from autopilot.params import PARAM_TABLE
from autopilot.safety.arming import FORCE_DISARM_MAGIC

from ._util import (GCS_COMPONENT, GCS_SYSTEM, client_codec, command_long, mav, of_type,
                    ready_vehicle, statustexts, wire)

SYSTEM_ID = 1


class Link:
    """A vehicle and its session, with every outgoing message packed and decoded as on the wire."""

    def __init__(self, vehicle=None):
        self.vehicle = vehicle or ready_vehicle()
        self.session = Session(self.vehicle, new_codec(SYSTEM_ID))
        self._decoder = new_codec(GCS_SYSTEM, GCS_COMPONENT)

    def _decode(self, messages) -> list:
        out = []
        for m in messages:
            decoded = self._decoder.parse_buffer(m.pack(self.session.codec))
            assert decoded and len(decoded) == 1, m
            assert decoded[0].get_srcSystem() == SYSTEM_ID
            out.extend(decoded)
        return out

    def send(self, msg, now: float | None = None) -> list:
        now = self.vehicle.time_s if now is None else now
        return self._decode(self.session.receive(msg, now))

    def poll(self, now: float | None = None) -> list:
        now = self.vehicle.time_s if now is None else now
        return self._decode(self.session.poll(now))

    def command(self, command: int, *params, now=None, **kw):
        out = self.send(command_long(command, *params, **kw), now)
        acks = of_type(out, "COMMAND_ACK")
        assert len(acks) == 1, out
        assert acks[0].command == command
        return acks[0], out


@pytest.fixture
def link():
    return Link()


def gcs():
    return client_codec()


# ----- commands ----------------------------------------------------------------------------------
def test_command_long_gets_exactly_one_ack_addressed_to_the_sender(link):
    out = link.send(command_long(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1))
    assert [m.get_type() for m in out] == ["COMMAND_ACK"]
    ack = out[0]
    assert ack.command == mav.MAV_CMD_COMPONENT_ARM_DISARM
    assert (ack.target_system, ack.target_component) == (GCS_SYSTEM, GCS_COMPONENT)
    assert ack.result == mav.MAV_RESULT_ACCEPTED
    assert link.vehicle.armed


def test_unknown_command_is_unsupported(link):
    ack, _ = link.command(mav.MAV_CMD_DO_SET_SERVO, 5, 1500)
    assert ack.result == mav.MAV_RESULT_UNSUPPORTED == 3
    assert link.session.counters["refused"] == 1


def test_takeoff_while_disarmed_fails(link):
    link.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, Guided.number)
    ack, _ = link.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 10)
    assert ack.result == mav.MAV_RESULT_FAILED == 4
    assert not link.vehicle.armed


def test_arm_with_nan_param_is_denied(link):
    ack, _ = link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, math.nan)
    assert ack.result == mav.MAV_RESULT_DENIED
    assert not link.vehicle.armed
    ack, _ = link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1, math.inf)
    assert ack.result == mav.MAV_RESULT_DENIED
    assert not link.vehicle.armed


def test_do_set_mode_changes_the_mode(link):
    ack, _ = link.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, Loiter.number)
    assert ack.result == mav.MAV_RESULT_ACCEPTED
    assert link.vehicle.mode.number == Loiter.number
    ack, _ = link.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, 99)
    assert ack.result == mav.MAV_RESULT_FAILED
    assert link.vehicle.mode.number == Loiter.number
    ack, _ = link.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, 4.5)
    assert ack.result == mav.MAV_RESULT_DENIED
    assert link.vehicle.mode.number == Loiter.number


def test_set_mode_message_changes_the_mode_and_is_acked_as_command_11(link):
    msg = wire(gcs().set_mode_encode(SYSTEM_ID, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, Guided.number))
    out = link.send(msg)
    assert [m.get_type() for m in out] == ["COMMAND_ACK"]
    ack = out[0]
    assert ack.command == mav.MAVLINK_MSG_ID_SET_MODE == 11
    assert ack.result == mav.MAV_RESULT_ACCEPTED
    assert (ack.target_system, ack.target_component) == (GCS_SYSTEM, GCS_COMPONENT)
    assert link.vehicle.mode.number == Guided.number


def test_set_mode_without_custom_mode_flag_is_unsupported(link):
    before = link.vehicle.mode
    out = link.send(wire(gcs().set_mode_encode(SYSTEM_ID, 0, Guided.number)))
    assert out[0].result == mav.MAV_RESULT_UNSUPPORTED
    assert link.vehicle.mode is before


def test_exact_retry_of_a_refused_arm_replays_the_result_without_acting_again(link):
    link.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, Land.number)
    link.vehicle.events.clear()
    t = link.vehicle.time_s
    ack1, _ = link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1, now=t)
    ack2, _ = link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1, now=t + 0.5, confirmation=1)
    assert ack1.result == ack2.result == mav.MAV_RESULT_FAILED
    assert [text for _, text in link.vehicle.events].count("Arm: Mode not armable") == 1


def test_exact_retry_of_an_accepted_arm_does_not_arm_again(link):
    t = link.vehicle.time_s
    ack1, _ = link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1, now=t)
    assert ack1.result == mav.MAV_RESULT_ACCEPTED and link.vehicle.armed
    link.vehicle.disarm("test")  # something else disarms it before the client's retry arrives
    ack2, _ = link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1, now=t + 0.5, confirmation=1)
    assert ack2.result == mav.MAV_RESULT_ACCEPTED
    assert not link.vehicle.armed  # replayed, not acted on
    # The same command long after the retry window (and without confirmation) is a new command.
    ack3, _ = link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1, now=t + 5.0)
    assert ack3.result == mav.MAV_RESULT_ACCEPTED
    assert link.vehicle.armed


def test_force_disarm_in_flight_needs_the_magic_number():
    from ._util import hovering_vehicle
    link = Link(hovering_vehicle(5.0))
    ack, _ = link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0)
    assert ack.result == mav.MAV_RESULT_FAILED and link.vehicle.armed
    ack, _ = link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0, FORCE_DISARM_MAGIC)
    assert ack.result == mav.MAV_RESULT_ACCEPTED and not link.vehicle.armed


def test_command_int_takeoff_path_matches_command_long(link):
    link.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, Guided.number)
    link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    msg = wire(gcs().command_int_encode(SYSTEM_ID, 1, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT,
                                        mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 0, 0, 8.0))
    out = link.send(msg)
    acks = of_type(out, "COMMAND_ACK")
    assert len(acks) == 1 and acks[0].result == mav.MAV_RESULT_ACCEPTED
    assert (acks[0].target_system, acks[0].target_component) == (GCS_SYSTEM, GCS_COMPONENT)
    link.vehicle.run_until(link.vehicle.time_s + 10.0)
    assert -link.vehicle.body.d_m == pytest.approx(8.0, abs=0.3)


# ----- addressing ---------------------------------------------------------------------------------
def test_messages_for_another_system_are_ignored(link):
    out = link.send(command_long(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1, target_system=2))
    assert out == []
    assert not link.vehicle.armed
    assert link.session.counters["ignored_other_system"] == 1
    out = link.send(wire(gcs().param_set_encode(2, 1, b"DISARM_DELAY", 3.0, mav.MAV_PARAM_TYPE_REAL32)))
    assert out == []
    assert link.vehicle.params["DISARM_DELAY"] == 10.0
    out = link.send(wire(gcs().set_mode_encode(2, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, Brake.number)))
    assert out == [] and link.vehicle.mode.number != Brake.number


def test_broadcast_target_zero_is_accepted(link):
    out = link.send(command_long(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1, target_system=0))
    assert out[0].result == mav.MAV_RESULT_ACCEPTED


def test_manual_control_for_another_system_is_ignored(link):
    before = (link.vehicle.pilot_input.roll, link.vehicle.pilot_input.pitch,
              link.vehicle.pilot_input.throttle)
    link.send(wire(gcs().manual_control_encode(2, 1000, 500, 900, 0, 0)))
    after = (link.vehicle.pilot_input.roll, link.vehicle.pilot_input.pitch,
             link.vehicle.pilot_input.throttle)
    assert after == before


def test_manual_control_for_this_system_sets_the_sticks(link):
    link.send(wire(gcs().manual_control_encode(SYSTEM_ID, 1000, -500, 750, 0, 0)))
    p = link.vehicle.pilot_input
    assert (p.pitch, p.roll, p.throttle) == pytest.approx((1.0, -0.5, 0.75))
    assert p.present(link.vehicle.time_s)


def test_bad_data_is_counted_and_answered_with_nothing(link):
    bad = mav.MAVLink_bad_data(b"\xfd\x00\x00", "bad")
    assert link.session.receive(bad, 0.0) == []
    assert link.session.counters["bad_data"] == 1


# ----- parameters ---------------------------------------------------------------------------------
def _name(msg) -> str:
    pid = msg.param_id
    return (pid.decode() if isinstance(pid, bytes) else pid).rstrip("\0")


def test_param_request_list_yields_every_parameter_once_with_consistent_indices(link):
    out = link.send(wire(gcs().param_request_list_encode(SYSTEM_ID, 1)))
    values = of_type(out, "PARAM_VALUE")
    assert len(values) == len(out) == len(PARAM_TABLE)
    assert {m.param_count for m in values} == {len(PARAM_TABLE)}
    assert sorted(m.param_index for m in values) == list(range(len(PARAM_TABLE)))
    assert {_name(m) for m in values} == {spec.name for spec in PARAM_TABLE}
    for m in values:
        spec = next(s for s in PARAM_TABLE if s.name == _name(m))
        assert m.param_value == pytest.approx(spec.default, rel=1e-6)
        expected_type = mav.MAV_PARAM_TYPE_INT32 if spec.is_int else mav.MAV_PARAM_TYPE_REAL32
        assert m.param_type == expected_type


def test_param_set_echoes_the_new_value(link):
    out = link.send(wire(gcs().param_set_encode(SYSTEM_ID, 1, b"WPNAV_SPEED", 750.0,
                                                mav.MAV_PARAM_TYPE_REAL32)))
    assert len(out) == 1 and out[0].get_type() == "PARAM_VALUE"
    assert _name(out[0]) == "WPNAV_SPEED" and out[0].param_value == 750.0
    assert out[0].param_index == link.vehicle.params.index_of("WPNAV_SPEED")
    assert link.vehicle.params["WPNAV_SPEED"] == 750.0
    assert link.vehicle.nav_speed_m_s == pytest.approx(7.5)  # and the vehicle uses it


def test_param_set_of_an_integer_rounds(link):
    out = link.send(wire(gcs().param_set_encode(SYSTEM_ID, 1, b"SR0_POSITION", 6.6,
                                                mav.MAV_PARAM_TYPE_INT32)))
    assert out[0].param_value == 7.0
    assert link.vehicle.params["SR0_POSITION"] == 7.0


@pytest.mark.parametrize("value", [5000.0, -1.0, math.nan, math.inf])
def test_param_set_refused_keeps_value_echoes_old_and_says_why(link, value):
    before = link.vehicle.params["WPNAV_SPEED"]
    link.poll()  # drain the boot messages
    out = link.send(wire(gcs().param_set_encode(SYSTEM_ID, 1, b"WPNAV_SPEED", value,
                                                mav.MAV_PARAM_TYPE_REAL32)))
    assert len(out) == 1 and out[0].get_type() == "PARAM_VALUE"
    assert out[0].param_value == before
    assert link.vehicle.params["WPNAV_SPEED"] == before
    texts = statustexts(link.poll())
    assert any(t.startswith("Param set failed") and "WPNAV_SPEED" in t for t in texts), texts


def test_param_set_of_unknown_name_changes_nothing_and_says_why(link):
    link.poll()
    out = link.send(wire(gcs().param_set_encode(SYSTEM_ID, 1, b"NO_SUCH_PARAM", 1.0,
                                                mav.MAV_PARAM_TYPE_REAL32)))
    assert out == []
    assert any("NO_SUCH_PARAM" in t for t in statustexts(link.poll()))


def test_param_request_read_by_name_and_by_index(link):
    out = link.send(wire(gcs().param_request_read_encode(SYSTEM_ID, 1, b"RTL_ALT", -1)))
    assert len(out) == 1
    assert _name(out[0]) == "RTL_ALT" and out[0].param_value == link.vehicle.params["RTL_ALT"]
    index = out[0].param_index
    assert index == link.vehicle.params.index_of("RTL_ALT")
    out = link.send(wire(gcs().param_request_read_encode(SYSTEM_ID, 1, b"", index)))
    assert len(out) == 1 and _name(out[0]) == "RTL_ALT"
    assert out[0].param_count == len(PARAM_TABLE)
    # Out-of-range index and unknown name: nothing to answer.
    assert link.send(wire(gcs().param_request_read_encode(SYSTEM_ID, 1, b"", len(PARAM_TABLE)))) == []
    assert link.send(wire(gcs().param_request_read_encode(SYSTEM_ID, 1, b"NOPE", -1))) == []


def test_param_name_of_full_16_characters(link):
    name = "PSC_VELXY_IMAX"  # 14 chars; the longest names still round-trip through char[16]
    out = link.send(wire(gcs().param_request_read_encode(SYSTEM_ID, 1, name.encode(), -1)))
    assert _name(out[0]) == name


# ----- FTP --------------------------------------------------------------------------------------
def _ftp_request(seq: int, opcode: int, session: int = 0) -> list:
    header = struct.pack("<HBBBBBBI", seq, session, opcode, 0, 0, 0, 0, 0)
    return list(header.ljust(251, b"\0"))


def _ftp_fields(msg):
    payload = bytes(msg.payload)
    seq, session, opcode, size, req_opcode = struct.unpack_from("<HBBBB", payload, 0)
    return seq, session, opcode, size, req_opcode, payload[12:12 + size]


def test_ftp_request_gets_file_not_found_nak_with_next_seq(link):
    open_file_ro = 4
    out = link.send(wire(gcs().file_transfer_protocol_encode(0, SYSTEM_ID, 1,
                                                             _ftp_request(41, open_file_ro, 3))))
    assert len(out) == 1 and out[0].get_type() == "FILE_TRANSFER_PROTOCOL"
    reply = out[0]
    assert (reply.target_system, reply.target_component) == (GCS_SYSTEM, GCS_COMPONENT)
    seq, session, opcode, size, req_opcode, data = _ftp_fields(reply)
    assert seq == 42
    assert session == 3
    assert opcode == 129  # NAK
    assert req_opcode == open_file_ro
    assert size == 1 and data == bytes([10])  # FILE_NOT_FOUND


def test_ftp_seq_wraps_and_replies_are_never_answered(link):
    out = link.send(wire(gcs().file_transfer_protocol_encode(0, SYSTEM_ID, 1, _ftp_request(0xFFFF, 3))))
    assert _ftp_fields(out[0])[0] == 0
    for reply_opcode in (128, 129):  # ACK, NAK from someone else
        assert link.send(wire(gcs().file_transfer_protocol_encode(
            0, SYSTEM_ID, 1, _ftp_request(5, reply_opcode)))) == []


# ----- requested messages and streams -----------------------------------------------------------
def test_request_message_autopilot_version_has_mission_int_capability(link):
    ack, out = link.command(mav.MAV_CMD_REQUEST_MESSAGE, mav.MAVLINK_MSG_ID_AUTOPILOT_VERSION)
    assert mav.MAVLINK_MSG_ID_AUTOPILOT_VERSION == 148
    assert ack.result == mav.MAV_RESULT_ACCEPTED
    versions = of_type(out, "AUTOPILOT_VERSION")
    assert len(versions) == 1
    caps = versions[0].capabilities
    assert caps & mav.MAV_PROTOCOL_CAPABILITY_MISSION_INT
    assert caps & mav.MAV_PROTOCOL_CAPABILITY_MAVLINK2
    assert caps & mav.MAV_PROTOCOL_CAPABILITY_COMMAND_INT
    # FTP is answered with NAKs only, so it must not be advertised; integer parameters travel by
    # value in the float field (C cast), not bytewise.
    assert not caps & mav.MAV_PROTOCOL_CAPABILITY_FTP
    assert caps & mav.MAV_PROTOCOL_CAPABILITY_PARAM_ENCODE_C_CAST
    assert not caps & mav.MAV_PROTOCOL_CAPABILITY_PARAM_ENCODE_BYTEWISE
    assert versions[0].uid == link.vehicle.system_id


def test_request_message_of_unknown_id_fails(link):
    ack, out = link.command(mav.MAV_CMD_REQUEST_MESSAGE, 9999)
    assert ack.result == mav.MAV_RESULT_FAILED
    assert out == [ack]


def count_over(link, msg_type: str, t0: float, seconds: float, rate_hz: int = 100) -> int:
    n = 0
    for k in range(int(seconds * rate_hz)):
        n += len(of_type(link.poll(t0 + k / rate_hz), msg_type))
    return n


def test_set_message_interval_changes_the_stream_rate(link):
    default_hz = link.vehicle.params["SR0_POSITION"]
    assert count_over(link, "GLOBAL_POSITION_INT", 0.0, 2.0) == pytest.approx(2 * default_hz, abs=1)
    ack, _ = link.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_GLOBAL_POSITION_INT,
                          50_000, now=2.0)
    assert ack.result == mav.MAV_RESULT_ACCEPTED
    assert count_over(link, "GLOBAL_POSITION_INT", 2.0, 2.0) == pytest.approx(40, abs=1)
    link.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_GLOBAL_POSITION_INT, -1, now=4.0)
    assert count_over(link, "GLOBAL_POSITION_INT", 4.0, 2.0) == 0
    link.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_GLOBAL_POSITION_INT, 0, now=6.0)
    assert count_over(link, "GLOBAL_POSITION_INT", 6.0, 2.0) == pytest.approx(2 * default_hz, abs=1)


def test_get_message_interval_reports_default_and_stopped(link):
    ack, out = link.command(mav.MAV_CMD_GET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_HEARTBEAT)
    assert ack.result == mav.MAV_RESULT_ACCEPTED
    reply = of_type(out, "MESSAGE_INTERVAL")[0]
    assert reply.message_id == mav.MAVLINK_MSG_ID_HEARTBEAT and reply.interval_us == 1_000_000
    link.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_ATTITUDE, -1)
    _, out = link.command(mav.MAV_CMD_GET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_ATTITUDE)
    assert of_type(out, "MESSAGE_INTERVAL")[0].interval_us == -1


@pytest.mark.parametrize("interval_us", [50_000, 100_000, 200_000])
def test_get_message_interval_reads_back_what_was_set(link, interval_us):
    msg_id = mav.MAVLINK_MSG_ID_GLOBAL_POSITION_INT
    link.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, msg_id, interval_us)
    _, out = link.command(mav.MAV_CMD_GET_MESSAGE_INTERVAL, msg_id)
    assert of_type(out, "MESSAGE_INTERVAL")[0].interval_us == interval_us


def test_set_message_interval_for_unknown_message_fails(link):
    ack, _ = link.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, 9999, 100_000)
    assert ack.result == mav.MAV_RESULT_FAILED


def test_request_data_stream_sets_group_rates(link):
    link.send(wire(gcs().request_data_stream_encode(SYSTEM_ID, 1, mav.MAV_DATA_STREAM_EXTRA1, 20, 1)))
    assert count_over(link, "ATTITUDE", 0.0, 2.0) == pytest.approx(40, abs=1)
    link.send(wire(gcs().request_data_stream_encode(SYSTEM_ID, 1, mav.MAV_DATA_STREAM_EXTRA1, 20, 0)))
    assert count_over(link, "ATTITUDE", 2.0, 2.0) == 0


def test_heartbeat_streams_at_1hz_and_identifies_an_arducopter_quad(link):
    assert count_over(link, "HEARTBEAT", 0.0, 5.0) == 5
    hb = of_type(link.poll(5.0), "HEARTBEAT")[0]
    assert hb.type == mav.MAV_TYPE_QUADROTOR == 2
    assert hb.autopilot == mav.MAV_AUTOPILOT_ARDUPILOTMEGA == 3
    assert hb.base_mode & mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED
    assert not hb.base_mode & mav.MAV_MODE_FLAG_SAFETY_ARMED
    assert hb.custom_mode == link.vehicle.mode.number
    assert hb.system_status == mav.MAV_STATE_STANDBY


def test_heartbeat_reports_mode_and_armed_flag_after_arming(link):
    link.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, Guided.number)
    link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    hb = of_type(link.poll(0.0), "HEARTBEAT")[0]
    assert hb.base_mode & mav.MAV_MODE_FLAG_SAFETY_ARMED
    assert hb.base_mode & mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED
    assert hb.custom_mode == Guided.number
    assert hb.system_status == mav.MAV_STATE_ACTIVE


def test_first_message_a_new_client_sees_is_the_heartbeat():
    link = Link(ready_vehicle())
    out = link.poll(0.0)
    assert out[0].get_type() == "HEARTBEAT"


def test_vehicle_events_go_out_as_statustext_with_severity(link):
    link.poll(0.0)
    link.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, Brake.number)
    link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    out = link.poll(0.01)
    texts = of_type(out, "STATUSTEXT")
    assert any(statustexts([m])[0] == "Arm: Mode not armable" and
               m.severity == mav.MAV_SEVERITY_CRITICAL for m in texts)
    assert link.vehicle.events == []  # drained
    link.vehicle.notify("x" * 80)
    long_text = statustexts(link.poll(0.02))
    assert long_text == ["x" * 50]


def test_home_position_and_global_position_are_consistent(link):
    ack, out = link.command(mav.MAV_CMD_GET_HOME_POSITION)
    assert ack.result == mav.MAV_RESULT_ACCEPTED
    home = of_type(out, "HOME_POSITION")[0]
    cfg = link.vehicle.config.home
    assert home.latitude == round(cfg.lat_deg * 1e7)
    assert home.longitude == round(cfg.lon_deg * 1e7)
    assert home.altitude == pytest.approx(cfg.alt_m * 1000, abs=1)
    pos = of_type(link.poll(0.0), "GLOBAL_POSITION_INT")[0]
    assert pos.relative_alt == 0
    assert (pos.lat, pos.lon) == (home.latitude, home.longitude)


# ----- guided setpoints -------------------------------------------------------------------------
def _local_target(x, y, z, mask=0b0000_1111_1111_1000, frame=None):
    frame = mav.MAV_FRAME_LOCAL_NED if frame is None else frame
    return wire(gcs().set_position_target_local_ned_encode(0, SYSTEM_ID, 1, frame, mask,
                                                           x, y, z, 0, 0, 0, 0, 0, 0, 0, 0))


def test_position_target_with_nan_is_ignored_and_counted(link):
    link.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, Guided.number)
    guided = link.vehicle.mode
    assert link.send(_local_target(5.0, 6.0, -3.0)) == []
    assert guided.target_ne == (5.0, 6.0)
    refused = link.session.counters["refused"]
    out = link.send(_local_target(math.nan, 1.0, -3.0))
    assert out == []
    assert link.session.counters["refused"] == refused + 1
    assert guided.target_ne == (5.0, 6.0)  # unchanged


def test_position_target_outside_guided_is_refused(link):
    link.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, Loiter.number)
    refused = link.session.counters["refused"]
    link.send(_local_target(5.0, 6.0, -3.0))
    assert link.session.counters["refused"] == refused + 1


def test_timesync_is_answered_with_sim_time(link):
    out = link.send(wire(gcs().timesync_encode(0, 123456789)), now=2.5)
    ts = of_type(out, "TIMESYNC")
    assert len(ts) == 1
    assert ts[0].tc1 == int(2.5e9) and ts[0].ts1 == 123456789
    assert link.send(wire(gcs().timesync_encode(5, 6)), now=2.5) == []  # a reply: not answered


# ----- telemetry units -----------------------------------------------------------------------------
def test_telemetry_in_flight_uses_mavlink_units():
    from ._util import hovering_vehicle
    link = Link(hovering_vehicle(10.0, home_yaw_deg=90.0))
    v = link.vehicle
    v.guided_velocity(0.0, 0.0, 0.5)  # descending at 0.5 m/s (NED down positive)
    v.run_until(v.time_s + 2.0)
    out = link.poll(v.time_s)
    pos = of_type(out, "GLOBAL_POSITION_INT")[0]
    assert pos.relative_alt == pytest.approx(-v.body.d_m * 1000, abs=2)  # mm above home
    assert pos.vz == pytest.approx(50, abs=5)  # cm/s, positive down
    assert pos.hdg == pytest.approx(9000, abs=100)  # centidegrees
    assert pos.time_boot_ms == int(v.time_s * 1000)
    local = of_type(out, "LOCAL_POSITION_NED")[0]
    assert local.z == pytest.approx(v.body.d_m, abs=1e-3) and local.vz == pytest.approx(0.5, abs=0.05)
    att = of_type(out, "ATTITUDE")[0]
    assert att.yaw == pytest.approx(math.pi / 2, abs=0.02)
    hud = of_type(out, "VFR_HUD")[0]
    assert hud.climb == pytest.approx(-0.5, abs=0.05) and hud.heading == 90
    assert 20 <= hud.throttle <= 80  # hovering: neither idle nor full
    ext = of_type(out, "EXTENDED_SYS_STATE")[0]
    assert ext.landed_state == mav.MAV_LANDED_STATE_IN_AIR
    sys_status = of_type(out, "SYS_STATUS")[0]
    assert 4 * 3.3 * 1000 < sys_status.voltage_battery < 4 * 4.2 * 1000  # mV of a 4S pack
    # cA: at least the ideal induced power of hover (4 x 20 W) over a full 4S pack (16.8 V).
    assert sys_status.current_battery > 80.0 / 16.8 * 100
    assert 0 < sys_status.battery_remaining <= 100


def test_extended_sys_state_on_the_ground(link):
    ext = of_type(link.poll(0.0), "EXTENDED_SYS_STATE")[0]
    assert ext.landed_state == mav.MAV_LANDED_STATE_ON_GROUND


def test_stream_rate_parameter_applies_at_once():
    from autopilot.mavlink.dialect import new_codec
    from autopilot.mavlink.session import Session
    from autopilot.vehicle import Vehicle, VehicleConfig
    v = Vehicle(VehicleConfig())
    s = Session(v, new_codec(1))

    def count_attitude(seconds):
        n, t0 = 0, v.time_s
        while v.time_s < t0 + seconds - 1e-9:
            v.run_until(v.time_s + 0.01)
            n += sum(1 for m in s.poll(v.time_s) if m.get_type() == "ATTITUDE")
        return n
    assert 18 <= count_attitude(2.0) <= 22  # SR0_EXTRA1 default 10 Hz
    v.params.set("SR0_EXTRA1", 2)
    assert 3 <= count_attitude(2.0) <= 5
    v.params.set("SR0_EXTRA1", 0)
    assert count_attitude(2.0) == 0

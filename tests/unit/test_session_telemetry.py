"""The MAVLink session, sans-IO: requested messages, streams, guided setpoints and telemetry units."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.modes import Brake, Guided, Loiter

from ._session_link import SYSTEM_ID, Link, gcs, link  # noqa: F401 - link is a fixture
from firefly.autopilot.results import Result

from ._util import fly_until, hovering_vehicle, mav, of_type, ready_vehicle, statustexts, wire


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
    assert caps & mav.MAV_PROTOCOL_CAPABILITY_FTP  # @PARAM/param.pck is served
    # Integers travel by value in the float field, as ArduPilot sends them, which (like the
    # reference) claims neither encoding bit: ground stations know ArduPilot's way by its type.
    assert not caps & mav.MAV_PROTOCOL_CAPABILITY_PARAM_ENCODE_BYTEWISE
    assert caps == 64495  # the reference ArduCopter 4.7.0-dev SITL's, measured (autopilot/version.py)
    assert versions[0].flight_sw_version == 0x04070000  # 4.7.0, FIRMWARE_VERSION_TYPE_DEV
    assert bytes(versions[0].flight_custom_version) == b"90700977"
    assert versions[0].uid == 0 and bytes(versions[0].uid2).rstrip(b"\0") == link.vehicle.board_id.encode()[:17]


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
    default_hz = link.vehicle.params["MAV1_POSITION"]
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
    assert hb.system_status == mav.MAV_STATE_STANDBY  # ArduCopter: STANDBY while landed, armed or not
    flying = Link(hovering_vehicle())
    hb = of_type(flying.poll(0.0), "HEARTBEAT")[0]
    assert hb.system_status == mav.MAV_STATE_ACTIVE
    assert hb.base_mode & mav.MAV_MODE_FLAG_GUIDED_ENABLED  # GUIDED: the position controller flies it


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
    assert any(statustexts([m])[0] == "Arm: BRAKE mode not armable" and
               m.severity == mav.MAV_SEVERITY_CRITICAL for m in texts)
    assert link.vehicle.events == []  # drained
    link.vehicle.notify("x" * 80)
    long_text = statustexts(link.poll(0.02))
    assert long_text == ["x" * 50, "x" * 30]  # in chunks, as ArduPilot sends a long text


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


def test_position_target_with_nan_stops_and_is_counted(link):
    """Measured on ArduCopter SITL: a NaN position stops the vehicle (it holds where it slows to)."""
    link.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, Guided.number)
    guided = link.vehicle.mode
    assert link.send(_local_target(5.0, 6.0, -3.0)) == []
    assert guided.target_ne == (5.0, 6.0) and guided.destination() is not None
    refused = link.session.counters["refused"]
    out = link.send(_local_target(math.nan, 1.0, -3.0))
    assert out == []
    assert link.session.counters["refused"] == refused + 1
    assert guided.destination() is None and guided.target_ne != (5.0, 6.0)  # stopped


def test_a_vehicle_started_off_the_shared_origin_has_its_own_local_frame():
    """Vehicle k of a --count process starts 5 m from vehicle 0; as each ArduCopter sets its EKF
    origin where it first has a fix, its local frame starts at its own start: LOCAL_POSITION_NED
    and HOME_POSITION's x/y read 0 there, and a local target is relative to it."""
    link = Link(ready_vehicle(offset_ne_m=(3.0, 5.0)))
    v = link.vehicle
    assert (v.body.n_m, v.body.e_m) == pytest.approx((3.0, 5.0), abs=0.01)  # the sim's shared frame
    local = of_type(link.poll(1.0), "LOCAL_POSITION_NED")[0]
    assert (local.x, local.y) == pytest.approx((0.0, 0.0), abs=0.01)
    _, out = link.command(mav.MAV_CMD_REQUEST_MESSAGE, mav.MAVLINK_MSG_ID_HOME_POSITION)
    home = of_type(out, "HOME_POSITION")[0]
    assert (home.x, home.y) == pytest.approx((0.0, 0.0), abs=0.01)
    link.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, Guided.number)
    assert v.arm() == Result.ACCEPTED and v.takeoff(3.0) == Result.ACCEPTED
    assert fly_until(v, lambda x: x.body.d_m < -2.8, 20.0)
    assert link.send(_local_target(10.0, 0.0, -3.0)) == []
    assert v.mode.target_ne == (13.0, 5.0)  # 10 m north of its own start
    assert fly_until(v, lambda x: math.hypot(x.body.n_m - 13.0, x.body.e_m - 5.0) < 0.3, 40.0)
    local = of_type(link.poll(v.time_s + 1.0), "LOCAL_POSITION_NED")[0]
    assert (local.x, local.y) == pytest.approx((10.0, 0.0), abs=0.3)


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
    assert 3 * 3.3 * 1000 < sys_status.voltage_battery < 3 * 4.2 * 1000  # mV of a 3S pack
    # cA: at least the ideal induced power of hover (4 x 20 W) over a full 3S pack (12.6 V).
    assert sys_status.current_battery > 80.0 / 12.6 * 100
    assert 0 < sys_status.battery_remaining <= 100


def test_extended_sys_state_on_the_ground(link):
    ext = of_type(link.poll(0.0), "EXTENDED_SYS_STATE")[0]
    assert ext.landed_state == mav.MAV_LANDED_STATE_ON_GROUND


def test_stream_rate_parameter_applies_at_once():
    from firefly.autopilot.mavlink.dialect import new_codec
    from firefly.autopilot.mavlink.session import Session
    from firefly.autopilot.vehicle import Vehicle, VehicleConfig
    v = Vehicle(VehicleConfig())
    s = Session(v, new_codec(1))

    def count_attitude(seconds):
        n, t0 = 0, v.time_s
        while v.time_s < t0 + seconds - 1e-9:
            v.run_until(v.time_s + 0.01)
            n += sum(1 for m in s.poll(v.time_s) if m.get_type() == "ATTITUDE")
        return n
    assert 18 <= count_attitude(2.0) <= 22  # SR0_EXTRA1 default 10 Hz
    v.params.set("MAV1_EXTRA1", 2)
    assert 3 <= count_attitude(2.0) <= 5
    v.params.set("MAV1_EXTRA1", 0)
    assert count_attitude(2.0) == 0

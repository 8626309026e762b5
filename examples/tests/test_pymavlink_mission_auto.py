"""Example: a pymavlink script uploads a mission and flies it in AUTO.

The mission: take off to 15 m, a waypoint 40 m north, one 40 m north and 20 m east, then
return to launch. The test checks what truly happened (the vehicle's state from the simulator):
it reached both waypoints and came down within 2 m of home, disarmed.
"""
import math

from pymavlink import mavutil

MAV = mavutil.mavlink
M_PER_DEG_LAT = 111_320.0


def receive(conn, kind: str, timeout: float = 5.0):
    msg = conn.recv_match(type=kind, blocking=True, timeout=timeout)
    assert msg is not None, f"no {kind} within {timeout} s"
    return msg


def command(conn, system_id: int, command_id: int, *params: float) -> None:
    conn.mav.command_long_send(system_id, 1, command_id, 0, *(list(params) + [0] * 7)[:7])
    ack = receive(conn, "COMMAND_ACK")
    while ack.command != command_id:
        ack = receive(conn, "COMMAND_ACK")
    assert ack.result == MAV.MAV_RESULT_ACCEPTED, f"command {command_id}: result {ack.result}"


def upload(conn, system_id: int, items: list) -> None:
    """The MAVLink mission protocol: count, then each item the vehicle asks for, then its ACK."""
    conn.mav.mission_count_send(system_id, 1, len(items), MAV.MAV_MISSION_TYPE_MISSION)
    while True:
        msg = conn.recv_match(type=["MISSION_REQUEST_INT", "MISSION_REQUEST", "MISSION_ACK"], blocking=True,
                              timeout=5)
        assert msg is not None, "the vehicle stopped asking for mission items"
        if msg.get_type() == "MISSION_ACK":
            assert msg.type == MAV.MAV_MISSION_ACCEPTED, f"mission refused: {msg.type}"
            return
        frame, cmd, lat, lon, alt = items[msg.seq]
        conn.mav.mission_item_int_send(system_id, 1, msg.seq, frame, cmd, 0, 1, 0, 0, 0, 0,
                                       int(lat * 1e7), int(lon * 1e7), alt, MAV.MAV_MISSION_TYPE_MISSION)


def test_upload_a_mission_and_fly_it_in_auto(firefly):
    conn = firefly.mavlink()
    sysid = firefly.system_id
    conn.mav.request_data_stream_send(sysid, 1, MAV.MAV_DATA_STREAM_POSITION, 4, 1)
    home = receive(conn, "GLOBAL_POSITION_INT")
    lat0, lon0 = home.lat / 1e7, home.lon / 1e7
    m_per_deg_lon = M_PER_DEG_LAT * math.cos(math.radians(lat0))
    rel = MAV.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT
    upload(conn, sysid, [
        (MAV.MAV_FRAME_GLOBAL_INT, MAV.MAV_CMD_NAV_WAYPOINT, lat0, lon0, 0),  # item 0: home
        (rel, MAV.MAV_CMD_NAV_TAKEOFF, 0, 0, 15),
        (rel, MAV.MAV_CMD_NAV_WAYPOINT, lat0 + 40 / M_PER_DEG_LAT, lon0, 15),
        (rel, MAV.MAV_CMD_NAV_WAYPOINT, lat0 + 40 / M_PER_DEG_LAT, lon0 + 20 / m_per_deg_lon, 15),
        (rel, MAV.MAV_CMD_NAV_RETURN_TO_LAUNCH, 0, 0, 0),
    ])

    command(conn, sysid, MAV.MAV_CMD_DO_SET_MODE, MAV.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, 4)  # GUIDED
    command(conn, sysid, MAV.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    command(conn, sysid, MAV.MAV_CMD_DO_SET_MODE, MAV.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, 3)  # AUTO
    command(conn, sysid, MAV.MAV_CMD_MISSION_START)

    firefly.wait_until(lambda s: math.hypot(s.north_m - 40, s.east_m) < 2, timeout=60, what="waypoint 1")
    firefly.wait_until(lambda s: math.hypot(s.north_m - 40, s.east_m - 20) < 2, timeout=60, what="waypoint 2")
    landed = firefly.wait_until(lambda s: s.landed, timeout=120, what="the return and landing")
    assert landed.mode == "AUTO" and landed.distance_from_home_m < 2.0  # the RTL item is flown in AUTO

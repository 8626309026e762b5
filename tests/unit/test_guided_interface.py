"""GUIDED's whole interface through the session, as a client sends it: the guided waypoint
(MISSION_ITEM current = 2), SET_POSITION_TARGET's masks, SET_ATTITUDE_TARGET in GUIDED and
GUIDED_NOGPS, GUID_TIMEOUT, DO_PAUSE_CONTINUE, DO_CHANGE_SPEED's climb speed, and what a landed
vehicle ignores. The ArduCopter figures are from its SITL (tests/parity/probes/guided.py)."""
from __future__ import annotations

import math

from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.mavlink.session import Session
from firefly.autopilot.modes import ModeNumber
from firefly.autopilot.results import Result

from ._util import (altitude, client_codec, command_long, fly_until, hovering_vehicle, mav, of_type,
                    ready_vehicle, wire)

VEL_ONLY = 0b0000_1100_0111  # position, acceleration and yaw ignored
POS_ONLY = 0b0000_1111_1000


def session_for(v) -> Session:
    return Session(v, new_codec(1))


def local_target(s, mask, frame=mav.MAV_FRAME_LOCAL_NED, pos=(0, 0, 0), vel=(0, 0, 0), accel=(0, 0, 0),
                 yaw=0.0, yaw_rate=0.0):
    msg = client_codec().set_position_target_local_ned_encode(0, 1, 1, frame, mask, *pos, *vel, *accel, yaw,
                                                              yaw_rate)
    return s.receive(wire(msg), s.vehicle.time_s)


def attitude_target(s, q=(1.0, 0.0, 0.0, 0.0), thrust=0.5, mask=0b0000_0111, rates=(0.0, 0.0, 0.0)):
    msg = client_codec().set_attitude_target_encode(0, 1, 1, mask, list(q), *rates, thrust)
    return s.receive(wire(msg), s.vehicle.time_s)


def guided_waypoint(s, lat, lon, alt, frame=mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, current=2,
                    command=mav.MAV_CMD_NAV_WAYPOINT):
    msg = client_codec().mission_item_int_encode(1, 1, 0, frame, command, current, 1, 0, 0, 0, 0,
                                                 int(lat * 1e7), int(lon * 1e7), alt)
    acks = of_type(s.receive(wire(msg), s.vehicle.time_s), "MISSION_ACK")
    assert len(acks) == 1
    return acks[0].type


def ack(s, command, *params) -> int:
    out = of_type(s.receive(command_long(command, *params), s.vehicle.time_s), "COMMAND_ACK")
    assert len(out) == 1
    return out[0].result


def pitch_deg(v) -> float:
    return math.degrees(v.attitude[1])


def test_velocity_targets_do_not_lift_an_armed_landed_vehicle_which_then_disarms():
    """MAVSDK Offboard's velocity on an armed vehicle on the ground: ArduCopter stays there and
    disarms after DISARM_DELAY (issue 28: Firefly took off and flew 150 m)."""
    v = ready_vehicle()
    s = session_for(v)
    assert v.set_mode(ModeNumber.GUIDED) == Result.ACCEPTED and v.arm() == Result.ACCEPTED
    start = v.time_s
    while v.time_s - start < 12.0 and v.armed:
        local_target(s, VEL_ONLY, vel=(3.0, 0.0, -1.0))
        v.run_until(v.time_s + 0.1)
    assert not v.armed and altitude(v) < 0.1 and math.hypot(v.body.n_m, v.body.e_m) < 0.5
    assert 9.0 < v.time_s - start < 11.5


def test_guided_waypoint_is_flown_and_acknowledged_as_arducopter_does():
    v = hovering_vehicle(10.0)
    s = session_for(v)
    home = v.home
    lat = home.lat_deg + 30.0 / 111_195.0  # ~30 m north
    assert guided_waypoint(s, lat, home.lon_deg, 15.0) == mav.MAV_MISSION_ACCEPTED
    assert fly_until(v, lambda x: abs(x.body.n_m - 30.0) < 1.0 and abs(altitude(x) - 15.0) < 0.5, 30.0)
    assert guided_waypoint(s, lat, home.lon_deg, 15.0, current=3) == mav.MAV_MISSION_ACCEPTED
    assert guided_waypoint(s, lat, home.lon_deg, 15.0, frame=mav.MAV_FRAME_LOCAL_NED) \
        == mav.MAV_MISSION_UNSUPPORTED_FRAME
    assert guided_waypoint(s, 95.0, home.lon_deg, 15.0) == mav.MAV_MISSION_INVALID_PARAM5_X
    assert guided_waypoint(s, lat, home.lon_deg, 15.0, command=mav.MAV_CMD_NAV_LAND) == mav.MAV_MISSION_ERROR
    assert v.set_mode(ModeNumber.LOITER) == Result.ACCEPTED
    assert guided_waypoint(s, lat, home.lon_deg, 15.0) == mav.MAV_MISSION_ERROR
    assert not v.mission_items()  # no upload's item was stored


def test_acceleration_target_is_flown_and_stops_when_the_stream_stops():
    v = hovering_vehicle(10.0)
    s = session_for(v)
    v.params.set("GUID_TIMEOUT", 1.0)
    mask = 0b1100_0011_1111  # position and velocity ignored, yaw and yaw rate ignored
    start = v.time_s
    while v.time_s - start < 2.0:
        local_target(s, mask, accel=(1.0, 0.0, 0.0))
        v.run_until(v.time_s + 0.1)
    assert 1.2 < v.body.vn_m_s < 2.6
    assert fly_until(v, lambda x: abs(x.body.vn_m_s) < 0.1, 6.0)  # GUID_TIMEOUT: it stops
    assert abs(altitude(v) - 10.0) < 0.5


def test_invalid_targets_stop_the_vehicle():
    v = hovering_vehicle(10.0)
    s = session_for(v)
    local_target(s, POS_ONLY, pos=(50.0, 0.0, -10.0))
    v.run_until(v.time_s + 3.0)
    assert v.body.vn_m_s > 2.0
    local_target(s, VEL_ONLY, vel=(math.nan, 0.0, 0.0))  # NaN in a used velocity: ArduCopter stops
    assert fly_until(v, lambda x: math.hypot(x.body.vn_m_s, x.body.ve_m_s) < 0.1, 8.0)
    assert v.body.n_m < 45.0


def test_pause_and_continue_in_guided():
    v = hovering_vehicle(10.0)
    s = session_for(v)
    local_target(s, POS_ONLY, pos=(100.0, 0.0, -10.0))
    v.run_until(v.time_s + 4.0)
    assert ack(s, mav.MAV_CMD_DO_PAUSE_CONTINUE, 0) == Result.ACCEPTED
    took = fly_until(v, lambda x: abs(x.body.vn_m_s) < 0.3, 8.0) and v.time_s
    stopped = v.body.n_m
    v.run_until(v.time_s + 2.0)
    assert abs(v.body.n_m - stopped) < 0.5 and stopped < 70.0
    assert ack(s, mav.MAV_CMD_DO_PAUSE_CONTINUE, 1) == Result.ACCEPTED
    assert fly_until(v, lambda x: abs(x.body.n_m - 100.0) < 1.0, 30.0)
    assert took
    assert ack(s, mav.MAV_CMD_DO_PAUSE_CONTINUE, 2) == Result.DENIED


def test_pause_outside_guided_and_auto_fails_with_arducopters_text():
    v = hovering_vehicle(10.0)
    s = session_for(v)
    assert v.set_mode(ModeNumber.LOITER) == Result.ACCEPTED
    v.drain_events()
    assert ack(s, mav.MAV_CMD_DO_PAUSE_CONTINUE, 0) == Result.FAILED
    assert ack(s, mav.MAV_CMD_DO_PAUSE_CONTINUE, 1) == Result.FAILED
    assert [text for _, text in v.drain_events()] == ["Failed to pause", "Failed to resume"]


def test_climb_speed_of_do_change_speed_in_guided():
    v = hovering_vehicle(10.0)
    s = session_for(v)
    assert ack(s, mav.MAV_CMD_DO_CHANGE_SPEED, 2, 1.0) == Result.ACCEPTED
    local_target(s, POS_ONLY, pos=(0.0, 0.0, -30.0))
    v.run_until(v.time_s + 6.0)
    assert 0.8 < -v.body.vd_m_s < 1.2
    assert v.set_mode(ModeNumber.LOITER) == Result.ACCEPTED
    assert ack(s, mav.MAV_CMD_DO_CHANGE_SPEED, 3, 1.0) == Result.FAILED


def test_guided_nogps_climbs_on_thrust_and_pitches_to_the_attitude():
    v = ready_vehicle()
    s = session_for(v)
    assert v.set_mode(ModeNumber.GUIDED_NOGPS) == Result.ACCEPTED and v.arm() == Result.ACCEPTED
    start = v.time_s
    while v.time_s - start < 4.0:  # thrust 0.7: a climb at 40 % of WPNAV_SPEED_UP
        attitude_target(s, thrust=0.7)
        v.run_until(v.time_s + 0.1)
    assert 2.0 < altitude(v) < 5.0
    q = (math.cos(math.radians(-10) / 2), 0.0, math.sin(math.radians(-10) / 2), 0.0)  # pitch -10 degrees
    for _ in range(20):
        attitude_target(s, q=q, thrust=0.5)
        v.run_until(v.time_s + 0.1)
    assert abs(pitch_deg(v) + 10.0) < 1.5 and v.body.vn_m_s > 1.0
    v.run_until(v.time_s + 4.0)  # GUID_TIMEOUT: level again
    assert abs(pitch_deg(v)) < 1.0


def test_attitude_targets_that_arducopter_refuses():
    v = hovering_vehicle(10.0)
    s = session_for(v)
    for bad in ({"q": (0.0, 0.0, 0.0, 0.0)}, {"q": (math.nan, 0, 0, 0)}, {"mask": 0b0100_0111},
                {"mask": 0b0000_0001, "rates": (0.0, 0.5, 0.0)}):
        assert v.mode.number == ModeNumber.GUIDED
        attitude_target(s, **bad)
        assert v.mode.submode != "angle"  # stopped: GUIDED re-initialised, no attitude flown
    attitude_target(s, thrust=math.nan)  # NaN thrust: the middle, a hover
    v.run_until(v.time_s + 2.0)
    assert v.mode.submode == "angle" and abs(v.body.vd_m_s) < 0.2

"""External navigation (autopilot/external_nav.py): a companion's pose in place of the GPS, with
EKF3's gate and reset and ArduCopter's answers around it, as measured on ArduCopter SITL (the
sitl test flies it over real sockets)."""
from __future__ import annotations

import math

import pytest

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from firefly.autopilot.external_nav import GATE_SIGMAS, RESET_POSE_ONLY_S, RESET_WITH_VELOCITY_S, ExternalNav
from firefly.autopilot.mavlink.commands import MAV_CMD_DO_SET_GLOBAL_ORIGIN
from firefly.autopilot.mavlink.dialect import mavlink as mav
from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.mavlink.session import Session
from firefly.autopilot.modes import ModeNumber
from firefly.autopilot.params import ParamStore
from firefly.autopilot.results import Result

from ..fuzz.checks import vehicle_problems
from ._util import fly_until, ready_vehicle, wire
from .test_hostile_messages import MESSAGES

EXTNAV = {"GPS1_TYPE": 0, "VISO_TYPE": 1, "EK3_SRC1_POSXY": 6, "EK3_SRC1_VELXY": 6, "EK3_SRC1_VELZ": 6}
HERE = (0.0, 0.0, 0.0)


def sensor(**values) -> ExternalNav:
    params = ParamStore()
    for name, value in {"VISO_TYPE": 1, **values}.items():
        params.set(name, value)
    return ExternalNav(params)


def test_no_sensor_takes_nothing():
    ext = sensor(VISO_TYPE=0)
    assert not ext.pose(1.0, HERE, (1.0, 2.0, 0.0), HERE) and not ext.healthy(1.0) and ext.poses == 0


def test_a_pose_gives_its_error_and_the_sensor_is_healthy_for_300_ms():
    ext = sensor()
    assert ext.pose(1.0, (10.0, 0.0, 0.0), (0.5, -0.2, -3.0), (10.0, 0.0, -3.0))
    assert ext.offset_ned == (0.5, -0.2, 0.0)
    assert ext.healthy(1.29) and not ext.healthy(1.3)


def test_a_jump_past_the_gate_with_a_velocity_is_held_off_then_taken_and_the_position_lost():
    ext = sensor()
    gate = GATE_SIGMAS * 0.2  # VISO_POS_M_NSE's default
    assert ext.pose(0.0, HERE, HERE, HERE)
    assert ext.pose(0.1, HERE, (0.9 * gate, 0.0, 0.0), HERE)  # within the gate: at once
    t = 0.2
    while t < 0.2 + RESET_WITH_VELOCITY_S - 0.05:
        ext.speed(t)
        assert not ext.pose(t, HERE, (5.0, 0.0, 0.0), HERE), t
        assert not ext.lost and ext.measured_s == t  # held off, the position still trusted
        t += 0.05
    assert math.isclose(ext.offset_ned[0], 0.9 * gate)
    t += 0.1
    assert ext.pose(t, HERE, (5.0, 0.0, 0.0), HERE) and ext.lost and ext.offset_ned[0] == 5.0
    assert ext.pose(t + 0.1, HERE, HERE, HERE)  # lost, it follows every pose (and stays lost)
    assert ext.offset_ned[0] == 0.0 and ext.lost


def test_a_jump_with_no_velocity_is_taken_sooner_and_the_position_kept():
    ext = sensor()
    assert ext.pose(0.0, HERE, HERE, HERE)
    t = 0.05
    while t < 0.05 + RESET_POSE_ONLY_S - 0.05:
        assert not ext.pose(t, HERE, (5.0, 0.0, 0.0), HERE), t
        t += 0.05
    t += 0.1
    assert ext.pose(t, HERE, (5.0, 0.0, 0.0), HERE) and not ext.lost and ext.offset_ned[0] == 5.0


def test_a_nan_position_is_heard_not_fused_and_its_height_still_counts():
    ext = sensor()
    ext.pose(0.0, HERE, (1.0, 1.0, -2.0), HERE)
    assert not ext.pose(1.0, HERE, (math.nan, 3.0, -4.0), HERE)
    assert ext.healthy(1.0) and ext.measured_s == 0.0 and ext.offset_ned == (1.0, 1.0, -4.0)


def test_a_pose_under_the_quality_floor_keeps_the_sensor_healthy_but_is_not_fused():
    ext = sensor(VISO_QUAL_MIN=50)
    assert not ext.pose(1.0, HERE, (1.0, 0.0, 0.0), HERE, quality=20)
    assert ext.healthy(1.0) and ext.poses == 0
    assert ext.pose(1.1, HERE, (1.0, 0.0, 0.0), HERE, quality=80)


def speak(v, until_s: float, error_ne=(0.0, 0.0)) -> None:
    """A companion sending the true position (plus error_ne) at 20 Hz until until_s."""
    while v.time_s < until_s - 1e-9:
        b = v.estimate.sim.state.body
        v.vision_pose((b.n_m + error_ne[0], b.e_m + error_ne[1], b.d_m))
        v.run_until(v.time_s + 0.05)


def texts(v) -> list[str]:
    return [text for _, text in v.drain_events()]


def test_without_an_origin_it_navigates_but_reports_no_location_and_refuses_loiter():
    v = ready_vehicle(EXTNAV)
    assert v.gps.fix_type == 0 and not v.local_position_known()  # no LOCAL_POSITION_NED before a pose
    texts(v)
    speak(v, v.time_s + 1.0)
    said = texts(v)
    assert said[:2] == ["EKF3 IMU1 is using external nav data", "EKF3 IMU1 initial pos NED = 0.0,0.0,0.0 (m)"]
    assert "EKF3 IMU0 is using external nav data" in said and not any("initial vel" in t for t in said)
    assert v.has_position() and v.local_position_known() and v.home_ned is None
    assert v.arm() == Result.ACCEPTED and v.disarm() == Result.ACCEPTED  # STABILIZE needs no home
    texts(v)
    assert v.set_mode(ModeNumber.LOITER) == Result.ACCEPTED
    assert v.arm() == Result.FAILED and texts(v) == ["Arm: AHRS: waiting for home"]


def test_the_origin_is_taken_once_with_home_and_its_texts():
    v = ready_vehicle(EXTNAV)
    speak(v, v.time_s + 1.0)
    texts(v)
    assert v.set_gps_global_origin(-35.3632621, 149.1652374, 584.0)
    assert texts(v) == ["EKF3 IMU0 origin set", "EKF3 IMU1 origin set", "Field Elevation Set: 584m"]
    assert v.home_ned is not None and abs(v.home.lat_deg + 35.3632621) < 1e-7 and abs(v.home.alt_m - 584.0) < 0.1
    assert not v.set_gps_global_origin(-35.0, 149.0, 600.0) and texts(v) == []  # a second one: dropped
    assert abs(v.home.lat_deg + 35.3632621) < 1e-7
    session = Session(v, new_codec(1))
    ack = session.receive(wire(session.codec.command_int_encode(1, 1, mav.MAV_FRAME_GLOBAL_INT, MAV_CMD_DO_SET_GLOBAL_ORIGIN,
                                                                0, 0, 0, 0, 0, 0, -350000000, 1490000000, 600.0)),
                          v.time_s, 0.0)
    assert [m.result for m in ack if m.get_type() == "COMMAND_ACK"] == [mav.MAV_RESULT_FAILED]


def test_the_origin_command_sets_it_and_sends_the_origin_and_home():
    v = ready_vehicle(EXTNAV)
    speak(v, v.time_s + 1.0)
    session = Session(v, new_codec(1))
    out = session.receive(wire(session.codec.command_int_encode(1, 1, mav.MAV_FRAME_GLOBAL_INT, MAV_CMD_DO_SET_GLOBAL_ORIGIN,
                                                                0, 0, 0, 0, 0, 0, -353632621, 1491652374, 584.0)),
                          v.time_s, 0.0)
    assert [m.get_type() for m in out][-1] == "COMMAND_ACK" and out[-1].result == mav.MAV_RESULT_ACCEPTED
    assert {"GPS_GLOBAL_ORIGIN", "HOME_POSITION"} <= {m.get_type() for m in session.poll(v.time_s, 0.0)} | \
        {m.get_type() for m in out}


def test_a_silent_sensor_refuses_arming_and_a_lost_pose_lands_by_the_ekf_failsafe():
    v = ready_vehicle(EXTNAV)
    assert v.arm() == Result.FAILED and "Arm: VisOdom: not healthy" in texts(v)
    speak(v, v.time_s + 1.0)
    v.set_gps_global_origin(-35.3632621, 149.1652374, 584.0)
    assert v.set_mode(ModeNumber.GUIDED) == Result.ACCEPTED and v.arm() == Result.ACCEPTED
    assert v.takeoff(10.0) == Result.ACCEPTED
    speak(v, v.time_s + 15.0)
    texts(v)
    stopped = v.time_s
    assert fly_until(v, lambda x: x.mode.number == ModeNumber.LAND, 15.0)
    assert 7.5 <= v.time_s - stopped <= 8.5  # ArduCopter: 7.8-8.0 s
    assert texts(v)[-2:] == ["EKF variance", "EKF Failsafe: changed to LAND Mode"]


def test_the_vehicle_holds_the_point_the_pose_names():
    v = ready_vehicle(EXTNAV)
    speak(v, v.time_s + 1.0)
    v.set_gps_global_origin(-35.3632621, 149.1652374, 584.0)
    assert v.set_mode(ModeNumber.GUIDED) == Result.ACCEPTED and v.arm() == Result.ACCEPTED
    assert v.takeoff(10.0) == Result.ACCEPTED
    speak(v, v.time_s + 12.0, error_ne=(0.6, -0.4))
    true = v.estimate.sim.state.body
    assert abs(v.body.n_m) < 0.1 and abs(v.body.e_m) < 0.1
    assert abs(true.n_m + 0.6) < 0.1 and abs(true.e_m - 0.4) < 0.1


def test_a_source_left_on_a_missing_sensor_refuses_the_position_modes():
    v = ready_vehicle({**EXTNAV, "EK3_SRC1_VELZ": 3})
    speak(v, v.time_s + 1.0)
    v.set_gps_global_origin(-35.3632621, 149.1652374, 584.0)
    texts(v)
    assert v.set_mode(ModeNumber.LOITER) == Result.ACCEPTED
    assert v.arm() == Result.FAILED and texts(v) == ["Arm: AHRS: EK3 sources require GPS"]
    v.params.set("EK3_SRC1_VELZ", 6)
    v.params.set("EK3_SRC2_POSXY", 5)  # not a position source
    assert v.arm() == Result.FAILED and texts(v) == ["Arm: AHRS: Check EK3_SRC2_POSXY"]
    v.params.set("EK3_SRC2_POSXY", 0)
    assert v.arm() == Result.ACCEPTED


def gps_input(session, v, lat_e7: int, lon_e7: int, alt_m: float = 584.0, fix: int = 3):
    return session.receive(wire(session.codec.gps_input_encode(0, 0, 0, 0, 0, fix, lat_e7, lon_e7, alt_m, 0.8, 1.0,
                                                               0.0, 0.0, 0.0, 0.2, 0.3, 0.5, 12)), v.time_s, 0.0)


def test_a_companion_gps_is_the_receiver_with_gps1_type_14():
    v = ready_vehicle({"GPS1_TYPE": 14})
    session = Session(v, new_codec(1))
    assert v.gps.fix_type == 1 and v.home_ned is None and not v.gps_detected
    assert not v.local_position_known()  # no LOCAL_POSITION_NED before the companion's fix
    texts(v)
    origin = v.origin
    lat, lon = round(origin.lat_deg * 1e7) + 270, round(origin.lon_deg * 1e7)  # 3 m north of the boot place
    gps_input(session, v, lat, lon)
    assert texts(v) == ["GPS 1: detected MAV"] and v.gps_detected and v.local_position_known()
    v.run_until(v.time_s + 0.2)
    assert v.gps.fix_type == 3 and v.gps.satellites == 12 and abs(v.gps.n_m - 3.0) < 0.1
    assert v.home_ned is not None  # Firefly's start-up: home at the first fix (ArduCopter's EKF: 10 s later)
    gps_input(session, v, lat, lon)
    assert texts(v) == []  # detected once
    v.run_until(v.time_s + 3.8)
    assert v.gps.fix_type == 3
    v.run_until(v.time_s + 0.4)  # silent: no fix (ArduCopter: fix type 1 after 4.2 s)
    assert v.gps.fix_type == 1 and v.gps.satellites == 0


def test_gps_input_is_ignored_without_gps1_type_14():
    v = ready_vehicle()
    session = Session(v, new_codec(1))
    before = v.gps
    gps_input(session, v, 0, 0)
    v.run_until(v.time_s + 0.2)
    assert v.gps.fix_type == 3 and abs(v.gps.n_m - before.n_m) < 5.0


@settings(max_examples=30, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(MESSAGES, st.sampled_from([0, 4, 40, 400])), min_size=1, max_size=12))
def test_hostile_messages_to_a_vehicle_on_external_navigation_leave_it_valid(sequence):
    """A hovering vehicle on a companion's pose, sent anything (poses at 1e30, NaN, other frames,
    origins, GPS_INPUTs, commands): nothing raises and the vehicle stays valid."""
    v = ready_vehicle({**EXTNAV, "GPS1_TYPE": 14})
    speak(v, v.time_s + 1.0)
    v.set_gps_global_origin(-35.3632621, 149.1652374, 584.0)
    assert v.set_mode(ModeNumber.GUIDED) == Result.ACCEPTED and v.arm() == Result.ACCEPTED
    assert v.takeoff(8.0) == Result.ACCEPTED
    speak(v, v.time_s + 4.0)
    session = Session(v, new_codec(1))
    for msg, steps in sequence:
        session.receive(wire(msg), v.time_s)
        v.run_until(v.time_s + steps / 400.0)
        session.poll(v.time_s, 0.0)
        assert not vehicle_problems(v, session), vehicle_problems(v, session)


def test_a_lost_gps_fix_keeps_the_location_known_since_home():
    """GLOBAL_POSITION_INT is all zeros only before the vehicle ever had a location: a GPS lost in
    flight leaves it reporting the estimate (parity area surface_sim_faults, SIM_GPS1_ENABLE 0)."""
    from firefly.autopilot.mavlink.telemetry import global_position_int
    v = ready_vehicle()
    v.params.set("SIM_GPS1_ENABLE", 0)
    v.run_until(v.time_s + 0.5)
    assert v.gps.fix_type < 3
    msg = global_position_int(v, new_codec(1))
    assert msg.lat != 0 and msg.lon != 0
    blind = ready_vehicle({"GPS1_TYPE": 0})
    assert global_position_int(blind, new_codec(1)).lat == 0


SOURCE_SETS = {"VISO_TYPE": 1, "EK3_SRC2_POSXY": 6, "EK3_SRC2_VELXY": 6, "EK3_SRC2_VELZ": 6, "EK3_SRC2_YAW": 1}


def source_set_command(session, v, wanted: float) -> int:
    out = session.receive(wire(session.codec.command_long_encode(1, 1, mav.MAV_CMD_SET_EKF_SOURCE_SET, 0, wanted,
                                                                 0, 0, 0, 0, 0, 0)), v.time_s, 0.0)
    return [m.result for m in out if m.get_type() == "COMMAND_ACK"][0]


def test_the_source_set_command_takes_sets_1_to_3_and_denies_the_rest():
    v = ready_vehicle(SOURCE_SETS)
    session = Session(v, new_codec(1))
    for wanted in (0, 4, -1, math.nan, math.inf):
        assert source_set_command(session, v, wanted) == mav.MAV_RESULT_DENIED
        assert v.estimate.source_set == 1
    assert source_set_command(session, v, 2.7) == mav.MAV_RESULT_ACCEPTED and v.estimate.source_set == 2
    assert texts(v) == []  # the command says nothing; the RC switch does


def test_switching_onto_the_pose_resets_to_it_and_back_onto_the_gps():
    v = ready_vehicle(SOURCE_SETS)
    speak(v, v.time_s + 1.0)  # a sensor set up must be sending to arm, whatever the source
    assert v.set_mode(ModeNumber.GUIDED) == Result.ACCEPTED and v.arm() == Result.ACCEPTED
    assert v.takeoff(10.0) == Result.ACCEPTED
    speak(v, v.time_s + 10.0, error_ne=(3.0, 0.0))
    assert abs(v.body.n_m - v.estimate.sim.state.body.n_m) < 1e-9  # on the GPS, the pose is not used
    true_n = v.estimate.sim.state.body.n_m
    v.use_source_set(2)
    assert abs(v.body.n_m - true_n - 3.0) < 0.05  # reset to the pose at once
    speak(v, v.time_s + 10.0, error_ne=(3.0, 0.0))
    # the held point moved with the estimate: the vehicle stays where it was (measured)
    assert abs(v.estimate.sim.state.body.n_m - true_n) < 0.2 and abs(v.body.n_m - true_n - 3.0) < 0.2
    texts(v)
    v.source_set_switch(0)  # RC function 90 low
    assert texts(v) == ["Using EKF Source Set 1"] and v.estimate.source_set == 1
    speak(v, v.time_s + 10.0, error_ne=(3.0, 0.0))
    assert abs(v.estimate.sim.state.body.n_m - true_n) < 0.2 and abs(v.body.n_m - true_n) < 0.05


def test_no_position_source_is_dead_reckoned_then_the_ekf_failsafe_lands():
    v = ready_vehicle(SOURCE_SETS)
    speak(v, v.time_s + 1.0)  # a sensor set up must be sending to arm, whatever the source
    assert v.set_mode(ModeNumber.GUIDED) == Result.ACCEPTED and v.arm() == Result.ACCEPTED
    assert v.takeoff(10.0) == Result.ACCEPTED
    speak(v, v.time_s + 10.0)
    switched = v.time_s
    v.use_source_set(3)  # its defaults: no horizontal position source
    assert fly_until(v, lambda x: x.mode.number == ModeNumber.LAND, 15.0)
    assert 7.0 <= v.time_s - switched <= 9.0  # ArduCopter: LAND within the 10 s watched
    assert texts(v)[-2:] == ["EKF variance", "EKF Failsafe: changed to LAND Mode"]


@pytest.mark.parametrize("mode", [ModeNumber.LOITER, ModeNumber.BRAKE, ModeNumber.POSHOLD, ModeNumber.LAND])
def test_a_mode_holding_a_point_stays_put_when_the_source_switches(mode):
    v = ready_vehicle(SOURCE_SETS)
    speak(v, v.time_s + 1.0)
    assert v.set_mode(ModeNumber.GUIDED) == Result.ACCEPTED and v.arm() == Result.ACCEPTED
    assert v.takeoff(10.0) == Result.ACCEPTED
    speak(v, v.time_s + 10.0, error_ne=(3.0, 0.0))
    assert v.set_mode(mode) == Result.ACCEPTED
    speak(v, v.time_s + 3.0, error_ne=(3.0, 0.0))
    true_n = v.estimate.sim.state.body.n_m
    v.use_source_set(2)
    speak(v, v.time_s + 5.0, error_ne=(3.0, 0.0))
    assert abs(v.estimate.sim.state.body.n_m - true_n) < 0.2


def test_a_guided_waypoint_stays_where_it_is_in_the_local_frame():
    v = ready_vehicle(SOURCE_SETS)
    speak(v, v.time_s + 1.0)
    assert v.set_mode(ModeNumber.GUIDED) == Result.ACCEPTED and v.arm() == Result.ACCEPTED
    assert v.takeoff(10.0) == Result.ACCEPTED
    speak(v, v.time_s + 10.0, error_ne=(3.0, 0.0))
    here = v.body
    v.guided_goto(here.n_m + 5.0, here.e_m, here.d_m)
    speak(v, v.time_s + 10.0, error_ne=(3.0, 0.0))
    v.use_source_set(2)
    speak(v, v.time_s + 10.0, error_ne=(3.0, 0.0))
    assert abs(v.body.n_m - (here.n_m + 5.0)) < 0.3  # believed there: truly 3 m short of it

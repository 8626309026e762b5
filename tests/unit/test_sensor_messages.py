"""The sensor, subsystem and navigator messages ArduCopter streams (sensor_messages.py, terrain.py),
and the stream groups that carry them."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.mavlink import sensor_messages
from firefly.autopilot.terrain_grid import grid_info
from firefly.autopilot.mavlink.streams import StreamScheduler
from firefly.autopilot.adsb.traffic_list import AdsbReport
from firefly.autopilot.mavlink.telemetry import BUILDERS, STREAM_GROUPS
from firefly.autopilot.motor_outputs import MOTOR_ON_OUTPUT, OUTPUT_OF_MOTOR, in_output_order
from firefly.sim.vehicle import SimConfig
from firefly.sim.wind import SteadyWind

from ._util import altitude, client_codec, fly_until, hovering_vehicle, mav, ready_vehicle

CODEC = client_codec()


def test_accelerometer_reads_one_g_up_at_rest_and_while_hovering():
    v = ready_vehicle()
    imu = sensor_messages.raw_imu(v, CODEC)
    assert (imu.xacc, imu.yacc) == (0, 0) and imu.zacc == -1000
    v = hovering_vehicle(10.0)
    imu = sensor_messages.raw_imu(v, CODEC)
    assert abs(imu.zacc + 1000) < 30 and abs(imu.xacc) < 30 and abs(imu.yacc) < 30


def test_compass_turns_with_the_vehicle():
    v = hovering_vehicle(10.0)
    before = sensor_messages.raw_imu(v, CODEC)
    v.set_yaw(90.0, relative=False, direction=0)
    v.run_until(v.time_s + 8.0)
    after = sensor_messages.raw_imu(v, CODEC)
    # Facing east, magnetic north is to the left: the field's north part moves from x to -y.
    assert before.xmag == pytest.approx(232, abs=10) and after.ymag == pytest.approx(-232, abs=15)


def test_servo_outputs_idle_disarmed_and_spread_over_the_spin_range_when_flying():
    v = ready_vehicle()
    servo = sensor_messages.servo_output_raw(v, CODEC)
    assert [servo.servo1_raw, servo.servo2_raw, servo.servo3_raw, servo.servo4_raw] == [1000] * 4
    v = hovering_vehicle(10.0)
    pwm = sensor_messages.motor_pwm(v)
    low = 1000 + 1000 * v.params["MOT_SPIN_MIN"]
    assert all(low < p < 1800 for p in pwm), pwm
    esc = sensor_messages.esc_telemetry_1_to_4(v, CODEC)
    assert all(r > 1000 for r in esc.rpm)


DRAG_FUSION = {"EK3_DRAG_BCOEF_X": 9.5, "EK3_DRAG_BCOEF_Y": 9.5, "EK3_DRAG_MCOEF": 0.082}


def test_wind_reads_zero_without_drag_fusion_as_arducopter_sends_it():
    """ArduCopter estimates no wind unless its EKF fuses the rotors' drag: a 6 m/s wind, WIND 0."""
    v = hovering_vehicle(sim=SimConfig(wind=SteadyWind(6.0, 270.0)))
    w = sensor_messages.wind(v, CODEC)
    assert (w.speed, w.speed_z) == (0.0, 0.0)


def test_wind_with_drag_fusion_reports_where_the_wind_blows_from_once_flying():
    v = ready_vehicle(sim=SimConfig(wind=SteadyWind(6.0, 270.0)))
    for name, value in DRAG_FUSION.items():
        v.params.set(name, value)
    assert sensor_messages.wind(v, CODEC).speed == 0.0  # on the ground: nothing fused yet
    assert v.set_mode(4) == 0 and v.arm() == 0 and v.takeoff(10.0) == 0
    assert fly_until(v, lambda x: altitude(x) > 9.8, 20.0)
    w = sensor_messages.wind(v, CODEC)
    assert w.speed == pytest.approx(6.0, abs=1e-6)  # (a scenario's wind blows the same at every height)
    assert w.direction % 360 == pytest.approx(270.0, abs=1e-6)


def test_nav_controller_output_points_at_the_guided_destination():
    v = hovering_vehicle(10.0)
    v.guided_goto(v.body.n_m, v.body.e_m + 40.0, v.body.d_m - 5.0)
    v.run_until(v.time_s + 1.0)
    out = sensor_messages.nav_controller_output(v, CODEC)
    assert out.target_bearing == pytest.approx(90, abs=2)
    assert 30 < out.wp_dist < 40
    assert 3.0 < out.alt_error <= 5.0


def test_terrain_grid_block_is_ap_terrains():
    # Measured on ArduCopter SITL at its default home: TERRAIN_REQUEST lat -353747690 lon 1491548424.
    info = grid_info(-353632610, 1491652299, 100)
    assert (info.block_lat_e7, info.block_lon_e7) == (-353747690, 1491548424)
    info = grid_info(435615000, 14838000, 100)
    assert info.block_lat_e7 <= 435615000 and info.block_lon_e7 <= 14838000


def test_terrain_request_goes_out_no_more_often_than_every_two_seconds():
    v = ready_vehicle()
    streams = StreamScheduler(v.params)
    streams.set_group_rate(0, 10, True)
    sent = sum(mav.MAVLINK_MSG_ID_TERRAIN_REQUEST in streams.due(k / 100.0) for k in range(1000))
    assert sent == 5


def test_every_streamed_message_has_a_builder_and_builds():
    # the rangefinder's are sent with one, the gimbal's with a mount, the winch's and the optical
    # flow's with theirs
    v = hovering_vehicle(5.0, boot_params={"RNGFND1_TYPE": 100, "ADSB_TYPE": 1, "MNT1_TYPE": 1, "WINCH_TYPE": 1,
                                           "SERVO9_FUNCTION": 88, "FLOW_TYPE": 10, "SIM_FLOW_ENABLE": 1})
    near = v.adsb_location()  # ADSB_VEHICLE is sent with traffic listed
    v.adsb_vehicle(AdsbReport(1, near.lat_e7, near.lon_e7, 0, 1000, 0, 0, 0, b"T", 1, 1, 0x1FF, 1200))
    # Hovering after a takeoff GUIDED has no waypoint: ArduCopter sends no position target then.
    assert BUILDERS[mav.MAVLINK_MSG_ID_POSITION_TARGET_GLOBAL_INT](v, CODEC) is None
    v.guided_goto(10.0, 0.0, -5.0)
    target = BUILDERS[mav.MAVLINK_MSG_ID_POSITION_TARGET_GLOBAL_INT](v, CODEC)
    assert (target.lat_int, target.lon_int) == (round(v.ned_to_global(10.0, 0.0, -5.0).lat_deg * 1e7),
                                                round(v.ned_to_global(10.0, 0.0, -5.0).lon_deg * 1e7))
    v.guided_goto(1e9, 0.0, -5.0)  # a hostile target off the globe: not sent, and no internal error
    assert BUILDERS[mav.MAVLINK_MSG_ID_POSITION_TARGET_GLOBAL_INT](v, CODEC) is None
    v.guided_goto(10.0, 0.0, -5.0)
    v.fence_enable(1, 0)  # FENCE_STATUS is sent only while a fence is on (as ArduCopter's)
    for _, ids in STREAM_GROUPS.values():
        for msg_id in ids:
            msg = BUILDERS[msg_id](v, CODEC)
            assert msg is not None
            msg.pack(CODEC)  # every field in range for its wire type
    assert all(math.isfinite(x) for x in sensor_messages.ahrs2(v, CODEC).to_dict().values()
               if isinstance(x, float))


def test_the_motors_are_reported_on_arducopters_outputs():
    """The sim's motors 1-4 (front, left, back, right) are ArduCopter QUAD PLUS's 3, 2, 4, 1."""
    assert in_output_order(("front", "left", "back", "right")) == ["right", "left", "front", "back"]
    assert [OUTPUT_OF_MOTOR[m] for m in MOTOR_ON_OUTPUT] == [1, 2, 3, 4]

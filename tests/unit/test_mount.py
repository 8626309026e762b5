"""The camera mount (autopilot/payload/mount.py) and its commands and messages
(autopilot/mavlink/mount_commands.py, mount_messages.py), as ArduCopter SITL was measured running a
servo gimbal (tests/parity/probes/mount.py): every command answered once, whatever it carries."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.mavlink.dialect import mavlink as mav
from firefly.autopilot.mavlink.mount_commands import gimbal_manager_set_attitude, gimbal_manager_set_pitchyaw
from firefly.autopilot.payload.mount import read_rc
from firefly.autopilot.results import Result

from ._session_link import Link
from ._util import client_codec, of_type, ready_vehicle, wire

SERVO_GIMBAL = {"MNT1_TYPE": 1, "SERVO9_FUNCTION": 7, "SERVO10_FUNCTION": 6, "SERVO11_FUNCTION": 8}
NAN, INF = float("nan"), float("inf")
PITCHYAW, CONFIGURE = mav.MAV_CMD_DO_GIMBAL_MANAGER_PITCHYAW, mav.MAV_CMD_DO_GIMBAL_MANAGER_CONFIGURE
CONTROL, MOUNT_CONFIGURE = mav.MAV_CMD_DO_MOUNT_CONTROL, mav.MAV_CMD_DO_MOUNT_CONFIGURE


def gimbal_link(params=SERVO_GIMBAL) -> Link:
    return Link(ready_vehicle(params))


def euler_deg(v) -> list[float]:
    w, x, y, z = v.mount.attitude_quaternion()
    roll = math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = math.asin(2 * (w * y - z * x))
    yaw = math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return [round(math.degrees(a), 1) for a in (roll, pitch, yaw)]


def settle(link: Link, s: float = 0.1) -> None:
    link.vehicle.run_until(link.vehicle.time_s + s)


def result(link: Link, command: int, *params) -> int:
    ack, _ = link.command(command, *params)
    return ack.result


def test_without_a_mount_every_gimbal_command_fails_and_roi_sysid_is_accepted():
    """As measured: FAILED, and the gimbal messages asked for ACCEPTED with none sent."""
    link = Link()
    assert not link.vehicle.mount.fitted
    for command, params in ((CONTROL, (-30, 0, 0, 0, 0, 0, 2)), (MOUNT_CONFIGURE, (2,)),
                            (PITCHYAW, (-30, 20, NAN, NAN, 0, 0, 0)), (CONFIGURE, (-2, -2))):
        assert result(link, command, *params) == Result.FAILED
    assert result(link, mav.MAV_CMD_DO_SET_ROI_SYSID, 5) == Result.ACCEPTED
    out = link.send(link_request(mav.MAVLINK_MSG_ID_GIMBAL_MANAGER_INFORMATION))
    assert of_type(out, "COMMAND_ACK")[0].result == Result.ACCEPTED  # as ArduCopter: asked, and nothing sent
    assert of_type(out, "GIMBAL_MANAGER_INFORMATION") == []
    out = link.send(link_request(mav.MAVLINK_MSG_ID_GIMBAL_DEVICE_INFORMATION))
    assert of_type(out, "COMMAND_ACK")[0].result == Result.FAILED  # not one ArduCopter sends


def link_request(msg_id: int):
    from ._util import command_long
    return command_long(mav.MAV_CMD_REQUEST_MESSAGE, msg_id)


def test_at_boot_the_servo_gimbal_points_at_the_middle_of_its_ranges():
    link = gimbal_link()
    v = link.vehicle
    settle(link)
    assert v.mount.fitted
    assert euler_deg(v) == pytest.approx([0.0, -35.0, 0.0], abs=0.5)
    assert v.servo_pwm[8:11] == pytest.approx([1500, 1500, 1500], abs=3)


def test_mount_control_angles_go_straight_to_the_servos_within_the_limits():
    link = gimbal_link()
    v = link.vehicle
    assert result(link, CONTROL, -30, 10, 45, 0, 0, 0, 2) == Result.ACCEPTED
    settle(link)
    assert euler_deg(v) == pytest.approx([10.0, -30.0, 45.0], abs=0.5)
    assert result(link, CONTROL, 40, -50, -400, 0, 0, 0, 2) == Result.FAILED  # beyond 360: centidegrees?
    assert result(link, CONTROL, 20, -50, -170, 0, 0, 0, 2) == Result.ACCEPTED
    settle(link)
    assert euler_deg(v) == pytest.approx([-30.0, 20.0, -170.0], abs=0.5)  # roll and pitch at their limits


@pytest.mark.parametrize("command,params", [
    (CONTROL, (NAN, NAN, NAN, NAN, NAN, NAN, NAN)), (CONTROL, (NAN, 0, 0, 0, 0, 0, 2)),
    (CONTROL, (INF, -INF, INF, 0, 0, 0, 2)), (CONTROL, (0, 0, 0, NAN, NAN, NAN, 4)),
    (CONTROL, (1e30, 1e30, 0, 1e30, 1e30, 1e30, 4)), (CONTROL, (0, 0, 0, 0, 0, 0, -1)),
    (CONTROL, (0, 0, 0, 0, 0, 0, 1e12)), (MOUNT_CONFIGURE, (NAN,)), (MOUNT_CONFIGURE, (-5,)),
    (MOUNT_CONFIGURE, (1e20,)), (PITCHYAW, (NAN,) * 7), (PITCHYAW, (1e9, -1e9, NAN, NAN, NAN, NAN, NAN)),
    (PITCHYAW, (0, 0, 0, 0, 1e12, 0, 1e12)), (PITCHYAW, (NAN, NAN, INF, -INF, 0, 0, 0)),
    (PITCHYAW, (-45, 30, NAN, NAN, 0, 0, 7)), (PITCHYAW, (-45, 30, NAN, NAN, 0, 0, -1)),
    (CONFIGURE, (NAN, NAN, 0, 0, 0, 0, NAN)), (CONFIGURE, (INF, 0)), (CONFIGURE, (-2, -2, 0, 0, 0, 0, 9)),
    (mav.MAV_CMD_DO_SET_ROI_SYSID, (NAN,)), (mav.MAV_CMD_DO_SET_ROI_SYSID, (1e12,)),
])
def test_bad_params_each_get_their_one_ack_and_the_gimbal_keeps_sane_outputs(command, params):
    link = gimbal_link()
    ack, _ = link.command(command, *params)
    assert ack.result in (Result.ACCEPTED, Result.FAILED)
    settle(link, 0.2)
    v = link.vehicle
    assert all(math.isfinite(a) for a in euler_deg(v))
    assert all(1100 <= pwm <= 1900 for pwm in v.servo_pwm[8:11])
    assert link.session.counters.get("handler_errors", 0) == 0


def test_an_unknown_gimbal_device_fails_and_device_one_is_the_first():
    link = gimbal_link()
    assert result(link, PITCHYAW, -10, -30, NAN, NAN, 0, 0, 2) == Result.FAILED
    assert result(link, CONFIGURE, -2, -2, 0, 0, 0, 0, 2) == Result.FAILED
    assert result(link, PITCHYAW, -10, -30, NAN, NAN, 0, 0, 1) == Result.ACCEPTED
    assert result(link, PITCHYAW, -10, NAN, NAN, NAN, 0, 0, 0) == Result.FAILED  # half an angle


def test_out_of_range_angles_are_held_at_the_limits_and_nan_ones_are_the_middle():
    link = gimbal_link()
    v = link.vehicle
    assert result(link, PITCHYAW, 60, 270, NAN, NAN, 0, 0, 0) == Result.ACCEPTED
    settle(link)
    assert euler_deg(v) == pytest.approx([0.0, 20.0, -90.0], abs=0.5)  # 270 is -90 in the body frame
    assert result(link, CONTROL, NAN, 0, 0, 0, 0, 0, 2) == Result.ACCEPTED
    settle(link)
    assert euler_deg(v)[1] == pytest.approx(-35.0, abs=0.5)  # ArduPilot's constrain of a NaN


def test_a_rate_moves_the_gimbal_at_that_rate_until_its_limit():
    link = gimbal_link()
    v = link.vehicle
    result(link, PITCHYAW, 0, 0, NAN, NAN, 0, 0, 0)
    settle(link)
    assert result(link, PITCHYAW, NAN, NAN, -10, 0, 0, 0, 0) == Result.ACCEPTED
    settle(link, 1.0)
    assert euler_deg(v)[1] == pytest.approx(-10.0, abs=0.6)
    settle(link, 20.0)
    assert euler_deg(v)[1] == pytest.approx(-90.0, abs=0.5)


def test_manager_configure_hands_control_over_and_says_so():
    link = gimbal_link()
    ack, out = link.command(CONFIGURE, -2, -2)
    assert ack.result == Result.ACCEPTED
    status = of_type(out, "GIMBAL_MANAGER_STATUS")
    assert len(status) == 1 and (status[0].primary_control_sysid, status[0].gimbal_device_id) == (255, 1)
    ack, out = link.command(CONFIGURE, -1, -1)
    assert ack.result == Result.ACCEPTED and of_type(out, "GIMBAL_MANAGER_STATUS") == []
    assert result(link, CONFIGURE, 300, 1) == Result.FAILED
    assert result(link, CONFIGURE, -4, 1) == Result.FAILED


def test_manager_messages_with_nan_or_out_of_range_fields_never_raise():
    link = gimbal_link()
    codec = client_codec()
    v = link.vehicle
    for msg in (codec.gimbal_manager_set_pitchyaw_encode(1, 1, 0, 0, NAN, NAN, NAN, NAN),
                codec.gimbal_manager_set_pitchyaw_encode(1, 1, 0, 200, 1.0, 1.0, NAN, NAN),
                codec.gimbal_manager_set_pitchyaw_encode(1, 1, 0xFFFFFFFF, 0, INF, -INF, INF, NAN),
                codec.gimbal_manager_set_attitude_encode(1, 1, 0, 0, [NAN] * 4, NAN, NAN, NAN),
                codec.gimbal_manager_set_attitude_encode(1, 1, 0, 0, [0, 0, 0, 0], INF, NAN, 1e30),
                codec.gimbal_manager_set_attitude_encode(1, 1, 16, 3, [1, 0, 0, 0], NAN, NAN, NAN)):
        link.send(wire(msg))
        settle(link, 0.1)
        assert all(math.isfinite(a) for a in euler_deg(v))
    assert link.session.counters.get("handler_errors", 0) == 0


def test_a_manager_pitchyaw_message_points_it():
    link = gimbal_link()
    m = client_codec().gimbal_manager_set_pitchyaw_encode(1, 1, 0, 0, math.radians(-20), math.radians(-40), NAN, NAN)
    gimbal_manager_set_pitchyaw(link.session, m)
    settle(link)
    assert euler_deg(link.vehicle) == pytest.approx([0.0, -20.0, -40.0], abs=0.5)
    half = math.radians(25) / 2
    m = client_codec().gimbal_manager_set_attitude_encode(1, 1, 0, 0, [math.cos(half), 0, -math.sin(half), 0],
                                                          NAN, NAN, NAN)
    gimbal_manager_set_attitude(link.session, m)
    settle(link)
    assert euler_deg(link.vehicle) == pytest.approx([0.0, -25.0, 0.0], abs=0.5)


def test_rc_targeting_follows_the_sticks_and_a_moved_stick_takes_the_gimbal_back():
    """Channel 9 pitch (RCn_OPTION 213), 10 yaw (214), as measured: 1800 / 1200 on 1100..1900 put
    the gimbal at 6.2 degrees pitch and -135 yaw; MAVLink targeting holds until a stick moves."""
    v = ready_vehicle({**SERVO_GIMBAL, "RC9_OPTION": 213, "RC10_OPTION": 214})
    mount, pwm = v.mount, {9: 1800, 10: 1200}
    rc = read_rc(v.params, lambda n: pwm.get(n, 0))
    mount.update(v.time_s, (0.0, 0.0, 0.0), None, None, rc)
    assert euler_deg(v) == pytest.approx([0.0, 6.2, -135.0], abs=0.1)
    mount.set_angle_target(0.0, -60.0, 0.0, False)
    mount.update(v.time_s, (0.0, 0.0, 0.0), None, None, rc)
    assert euler_deg(v)[1] == pytest.approx(-60.0, abs=0.1)
    pwm[9] = 1300
    mount.update(v.time_s, (0.0, 0.0, 0.0), None, None, read_rc(v.params, lambda n: pwm.get(n, 0)))
    assert euler_deg(v)[1] == pytest.approx(-62.5, abs=0.1)

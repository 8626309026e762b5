"""The camera mount's messages, as ArduCopter's AP_Mount sends them for MNT1 (payload/mount.py);
none without a mount.

GIMBAL_DEVICE_ATTITUDE_STATUS is in the EXTRA3 stream: the angles put out (a servo gimbal has no
other) as a quaternion, roll and pitch earth-frame and yaw the vehicle's (flags), rates unknown
(NaN), gimbal 1. GIMBAL_MANAGER_INFORMATION (what it can do, its limits) and GIMBAL_MANAGER_STATUS
(the yaw lock, who controls it) go out on request; the status also when control changes.
"""
from __future__ import annotations

from ..views import TelemetryView
from .dialect import mavlink as mav
from .encoding import time_boot_ms

NAN = float("nan")
DEVICE_ID = 1  # MNT1
# What every mount can do (GIMBAL_MANAGER_CAP_FLAGS), and what each axis it controls adds
CAN_ALWAYS = (mav.GIMBAL_MANAGER_CAP_FLAGS_HAS_RETRACT | mav.GIMBAL_MANAGER_CAP_FLAGS_HAS_NEUTRAL
              | mav.GIMBAL_MANAGER_CAP_FLAGS_HAS_RC_INPUTS | mav.GIMBAL_MANAGER_CAP_FLAGS_CAN_POINT_LOCATION_LOCAL
              | mav.GIMBAL_MANAGER_CAP_FLAGS_CAN_POINT_LOCATION_GLOBAL)
CAN_ROLL = (mav.GIMBAL_MANAGER_CAP_FLAGS_HAS_ROLL_AXIS | mav.GIMBAL_MANAGER_CAP_FLAGS_HAS_ROLL_FOLLOW
            | mav.GIMBAL_MANAGER_CAP_FLAGS_HAS_ROLL_LOCK)
CAN_PITCH = (mav.GIMBAL_MANAGER_CAP_FLAGS_HAS_PITCH_AXIS | mav.GIMBAL_MANAGER_CAP_FLAGS_HAS_PITCH_FOLLOW
             | mav.GIMBAL_MANAGER_CAP_FLAGS_HAS_PITCH_LOCK)
CAN_PAN = (mav.GIMBAL_MANAGER_CAP_FLAGS_HAS_YAW_AXIS | mav.GIMBAL_MANAGER_CAP_FLAGS_HAS_YAW_FOLLOW
           | mav.GIMBAL_MANAGER_CAP_FLAGS_HAS_YAW_LOCK)


def gimbal_device_attitude_status(v: TelemetryView, codec):
    mount = v.mount
    if not mount.fitted:
        return None
    return codec.gimbal_device_attitude_status_encode(0, 0, time_boot_ms(v), mount.device_flags(),
                                                      list(mount.attitude_quaternion()), NAN, NAN, NAN, 0,
                                                      NAN, NAN, DEVICE_ID)


def gimbal_manager_information(v: TelemetryView, codec):
    mount = v.mount
    if not mount.fitted:
        return None
    caps = CAN_ALWAYS
    # ArduPilot's capability check for roll and pitch is the range alone (AP_Mount_Backend's),
    # for pan the servo backend's (an output too)
    low = mount.limits_rad()
    if low[0] < low[1]:
        caps |= CAN_ROLL
    if low[2] < low[3]:
        caps |= CAN_PITCH
    if mount.has_pan_control():
        caps |= CAN_PAN
    return codec.gimbal_manager_information_encode(time_boot_ms(v), caps, DEVICE_ID, *low)


def autopilot_state_for_gimbal_device(v: TelemetryView, codec):
    """What a gimbal steadies against (sent with or without a mount, as ArduPilot's GCS does):
    the vehicle's attitude and velocity, its yaw rate."""
    b = v.body
    flags = mav.EKF_ATTITUDE | mav.EKF_VELOCITY_HORIZ | mav.EKF_VELOCITY_VERT if v.has_position() else mav.EKF_ATTITUDE
    return codec.autopilot_state_for_gimbal_device_encode(1, 0, int(v.time_s * 1e6) & 0xFFFFFFFFFFFFFFFF,
                                                          [b.qw, b.qx, b.qy, b.qz], 0, b.vn_m_s, b.ve_m_s, b.vd_m_s,
                                                          0, 0.0, flags, 0, b.r_rad_s)


def gimbal_manager_status(v: TelemetryView, codec):
    mount = v.mount
    if not mount.fitted:
        return None
    sysid, compid = mount.control
    return codec.gimbal_manager_status_encode(time_boot_ms(v), mount.manager_flags(), DEVICE_ID, sysid, compid, 0, 0)


BUILDERS = {
    mav.MAVLINK_MSG_ID_GIMBAL_DEVICE_ATTITUDE_STATUS: gimbal_device_attitude_status,
    mav.MAVLINK_MSG_ID_GIMBAL_MANAGER_INFORMATION: gimbal_manager_information,
    mav.MAVLINK_MSG_ID_GIMBAL_MANAGER_STATUS: gimbal_manager_status,
    mav.MAVLINK_MSG_ID_AUTOPILOT_STATE_FOR_GIMBAL_DEVICE: autopilot_state_for_gimbal_device,
}
# Messages ArduCopter knows how to send, which REQUEST_MESSAGE ACCEPTS also with no mount to send
# them (measured: no reply)
REQUESTABLE = frozenset(BUILDERS)

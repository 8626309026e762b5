"""The camera mount's commands and messages, answered as ArduCopter's AP_Mount answers them
(payload/mount.py acts). Joined into the command table (commands.HANDLERS) as **HANDLERS and into
the session's message handlers as MESSAGE_HANDLERS.

With no mount (MNT1_TYPE 0, or any type Firefly does not make) every mount command is FAILED and
DO_SET_ROI_SYSID ACCEPTED. A command's gimbal is param 7 (0 the first, 1 MNT1; any other: FAILED),
read as C reads a float into a uint8_t (its low byte; NaN: 0), and so is a mode (measured: a NaN
mode is 0, retract). DO_MOUNT_CONTROL's mode is param 7
and its angles params 1-3 (pitch, roll, yaw, all in degrees, checked against 90/180/360 to catch
centidegrees: FAILED with "Mount: invalid angle targets"); a point (mode 4) is x / y in 1e-7
degrees, which a COMMAND_LONG gives as param 5 / 6 cut to integers, as ArduPilot converts it.
Where a gimbal only tilts, DO_MOUNT_CONTROL's yaw turns the vehicle by that much instead
(GCS_MAVLINK_Copter::handle_command_mount).

GIMBAL_MANAGER_SET_ATTITUDE and GIMBAL_MANAGER_SET_PITCHYAW act as the command does, unanswered.
"""
from __future__ import annotations

import math

from ..c_casts import as_int32, as_uint8
from ..payload.mount import (GPS_POINT, HOME_LOCATION, MAVLINK_TARGETING, NEUTRAL, RC_TARGETING, RETRACT,
                             F_NEUTRAL, F_RETRACT, F_YAW_LOCK, Mount)
from ..results import Result, Severity
from .dialect import mavlink as mav

INSTANCES = 1  # Firefly makes MNT1 only


def _x(c) -> int:
    """Param 5 as the int32 ArduPilot reads: a COMMAND_INT's x, a COMMAND_LONG's cut (NaN: 0)."""
    return round(c.p5 * 1e7) if c.is_int else as_int32(c.p5)


def _y(c) -> int:
    return round(c.p6 * 1e7) if c.is_int else as_int32(c.p6)


def _gimbal(mount: Mount, device: float) -> Mount | None:
    """The gimbal a command or message names: 0 the first, n the n-th (Firefly has MNT1 only)."""
    instance = as_uint8(device)
    if not mount.fitted or instance > INSTANCES:
        return None
    return mount


def do_mount_configure(s, c) -> Result:
    mount = s.vehicle.mount
    if not mount.fitted:
        return Result.FAILED
    mount.set_mode(as_uint8(c.p1))  # a mode it does not have is ignored, and ACCEPTED
    return Result.ACCEPTED


def do_mount_control(s, c) -> Result:
    v = s.vehicle
    mount = v.mount
    mode = as_uint8(c.p7)
    if mode == MAVLINK_TARGETING and mount.fitted and not mount.has_pan_control() and math.isfinite(c.p3):
        v.turn_by(c.p3)  # the vehicle turns where the gimbal cannot
    if not mount.fitted:
        return Result.FAILED
    if mode in (RETRACT, NEUTRAL, RC_TARGETING, HOME_LOCATION):
        mount.set_mode(mode)
        return Result.ACCEPTED
    if mode == MAVLINK_TARGETING:
        pitch, roll, yaw = c.p1, c.p2, c.p3
        if abs(pitch) > 90 or abs(roll) > 180 or abs(yaw) > 360:  # NaN passes, as in ArduPilot
            mount.warn(v.time_s, "invalid angle targets", _warning(v))
            return Result.FAILED
        mount.set_angle_target(roll, pitch, yaw, False)
        return Result.ACCEPTED
    if mode == GPS_POINT:
        x, y = _x(c), _y(c)
        if c.p1 != 0 and c.p2 != 0 and x == 0 and y == 0:  # lat / lon in params 1 / 2: AP 4.2's bug relied on
            mount.warn(v.time_s, "GPS_POINT target invalid", _warning(v))
            return Result.FAILED
        up_m = float(as_int32(c.p4))  # whole metres above home
        point = None
        if (x, y, up_m) != (0, 0, 0.0) and v.origin_known():
            n, e, _ = v.ned_of(x * 1e-7, y * 1e-7, v.origin.alt_m)
            point = (n, e, up_m)
        mount.set_roi_target(point)
        return Result.ACCEPTED
    return Result.FAILED


def _warning(v):
    return lambda text: v.notify(text, Severity.WARNING)


def do_gimbal_manager_pitchyaw(s, c) -> Result:
    """Params 1 / 2 pitch and yaw [deg], 3 / 4 their rates [deg/s], 5 the flags, 7 the gimbal."""
    mount = _gimbal(s.vehicle.mount, c.p7)
    if mount is None:
        return Result.FAILED
    flags = _x(c) & 0xFFFFFFFF
    if _pitchyaw(mount, flags, c.p1, c.p2, c.p3, c.p4):
        return Result.ACCEPTED
    return Result.FAILED


def _pitchyaw(mount: Mount, flags: int, pitch: float, yaw: float, pitch_rate: float, yaw_rate: float) -> bool:
    """Retract, neutral, angles [deg], rates [deg/s] or (all NaN) the yaw lock alone; False when
    only some of them are given."""
    lock = bool(flags & F_YAW_LOCK)
    if flags & F_RETRACT:
        mount.set_mode(RETRACT)
    elif flags & F_NEUTRAL:
        mount.set_mode(NEUTRAL)
    elif not math.isnan(pitch) and not math.isnan(yaw):
        mount.set_angle_target(0.0, pitch, yaw, lock)
    elif not math.isnan(pitch_rate) and not math.isnan(yaw_rate):
        mount.set_rate_target(0.0, pitch_rate, yaw_rate, lock)
    elif all(math.isnan(v) for v in (pitch, yaw, pitch_rate, yaw_rate)):
        mount.set_yaw_lock(lock)
    else:
        return False
    return True


def do_gimbal_manager_configure(s, c) -> Result:
    """Params 1 / 2 the system and component to put in control (-1 unchanged, -2 the sender,
    -3 the sender gives it up), 7 the gimbal; a change volunteers GIMBAL_MANAGER_STATUS."""
    mount = _gimbal(s.vehicle.mount, c.p7)
    if mount is None:
        return Result.FAILED
    changed = mount.configure_control(c.p1, c.p2, c.src)
    if changed is None:
        return Result.FAILED
    if changed:
        s.queue(s.build(mav.MAVLINK_MSG_ID_GIMBAL_MANAGER_STATUS))
    return Result.ACCEPTED


def do_set_roi_sysid(s, c) -> Result:
    """Points the gimbal at another system (param 1, as a byte); with none fitted, ACCEPTED and
    nothing moves."""
    mount = s.vehicle.mount
    if mount.fitted:
        mount.set_target_sysid(as_uint8(c.p1))
    return Result.ACCEPTED


HANDLERS = {
    mav.MAV_CMD_DO_MOUNT_CONFIGURE: do_mount_configure,
    mav.MAV_CMD_DO_MOUNT_CONTROL: do_mount_control,
    mav.MAV_CMD_DO_GIMBAL_MANAGER_PITCHYAW: do_gimbal_manager_pitchyaw,
    mav.MAV_CMD_DO_GIMBAL_MANAGER_CONFIGURE: do_gimbal_manager_configure,
    mav.MAV_CMD_DO_SET_ROI_SYSID: do_set_roi_sysid,
}


# ----- messages ---------------------------------------------------------------------------------
def gimbal_manager_set_pitchyaw(s, m) -> None:
    """Pitch and yaw [rad] or their rates [rad/s]: both given at once, ignored."""
    mount = _gimbal(s.vehicle.mount, m.gimbal_device_id)
    if mount is None:
        return
    flags = m.flags & 0xFFFFFFFF
    if not (flags & (F_RETRACT | F_NEUTRAL)) and not any(math.isnan(v) for v in (m.pitch, m.yaw, m.pitch_rate,
                                                                                  m.yaw_rate)):
        return
    _pitchyaw(mount, flags, math.degrees(m.pitch), math.degrees(m.yaw), math.degrees(m.pitch_rate),
              math.degrees(m.yaw_rate))


def gimbal_manager_set_attitude(s, m) -> None:
    """An attitude (a quaternion: roll, pitch, yaw) or, when any of it is NaN, rates [rad/s];
    both given, ignored (ArduPilot reads the roll rate, the pitch rate and the pitch rate again
    for "given")."""
    mount = _gimbal(s.vehicle.mount, m.gimbal_device_id)
    if mount is None:
        return
    flags = m.flags & 0xFFFFFFFF
    lock = bool(flags & F_YAW_LOCK)
    if flags & F_RETRACT:
        mount.set_mode(RETRACT)
        return
    if flags & F_NEUTRAL:
        mount.set_mode(NEUTRAL)
        return
    q_given = not any(math.isnan(v) for v in m.q)
    if q_given and not any(math.isnan(v) for v in (m.angular_velocity_x, m.angular_velocity_y)):
        return
    if q_given:
        roll, pitch, yaw = _euler(m.q)
        mount.set_angle_target(math.degrees(roll), math.degrees(pitch), math.degrees(yaw), lock)
        return
    mount.set_rate_target(math.degrees(m.angular_velocity_x), math.degrees(m.angular_velocity_y),
                          math.degrees(m.angular_velocity_z), lock)


def _euler(q) -> tuple[float, float, float]:
    w, x, y, z = q
    roll = math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2 * (w * y - z * x))))
    yaw = math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return roll, pitch, yaw


MESSAGE_HANDLERS = {
    "GIMBAL_MANAGER_SET_PITCHYAW": gimbal_manager_set_pitchyaw,
    "GIMBAL_MANAGER_SET_ATTITUDE": gimbal_manager_set_attitude,
}

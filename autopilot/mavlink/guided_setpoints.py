"""SET_POSITION_TARGET_LOCAL_NED / _GLOBAL_INT in GUIDED, with the type masks MAVSDK sends.

Returns False (and changes nothing) for a setpoint outside GUIDED, in an unsupported frame, or
carrying NaN/inf where the mask says the value is used.
"""
from __future__ import annotations

import math

from ..modes.numbers import ModeNumber
from ..results import Result
from .dialect import mavlink as mav

POS_IGNORE = 0x7
VEL_IGNORE = 0x38
YAW_IGNORE = 0x400
YAW_RATE_IGNORE = 0x800

LOCAL_FRAMES = (mav.MAV_FRAME_LOCAL_NED, mav.MAV_FRAME_LOCAL_OFFSET_NED, mav.MAV_FRAME_BODY_NED,
                mav.MAV_FRAME_BODY_OFFSET_NED)
GLOBAL_FRAMES = (mav.MAV_FRAME_GLOBAL_INT, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT,
                 mav.MAV_FRAME_GLOBAL_TERRAIN_ALT_INT)
MAX_SPEED_M_S = 50.0


def _used_finite(mask: int, *groups) -> bool:
    """groups: (ignore_bits, values...) — values must be finite unless their bits are set."""
    for bits, *values in groups:
        if (mask & bits) != bits and not all(math.isfinite(v) for v in values):
            return False
    return True


def _yaw(msg):
    return None if msg.type_mask & YAW_IGNORE else msg.yaw


def _rotate_body(v, x: float, y: float) -> tuple:
    yaw = v.attitude[2]
    c, s = math.cos(yaw), math.sin(yaw)
    return x * c - y * s, x * s + y * c


def _apply(v, mask: int, pos, vel, yaw) -> bool:
    pos_used = (mask & POS_IGNORE) != POS_IGNORE
    vel_used = (mask & VEL_IGNORE) != VEL_IGNORE
    if vel_used and math.sqrt(sum(x * x for x in vel)) > MAX_SPEED_M_S:
        return False
    if pos_used:
        return v.guided_goto(pos[0], pos[1], pos[2], yaw, vel if vel_used else (0.0, 0.0, 0.0)) == Result.ACCEPTED
    if vel_used:
        return v.guided_velocity(*vel, yaw=yaw) == Result.ACCEPTED
    return False


def handle_local_ned(v, msg) -> bool:
    mask, frame = msg.type_mask, msg.coordinate_frame
    if v.mode.number != ModeNumber.GUIDED or frame not in LOCAL_FRAMES:
        return False
    if not _used_finite(mask, (POS_IGNORE, msg.x, msg.y, msg.z), (VEL_IGNORE, msg.vx, msg.vy, msg.vz),
                        (YAW_IGNORE, msg.yaw)):
        return False
    pos = (msg.x, msg.y, msg.z)
    vel = (msg.vx, msg.vy, msg.vz)
    b = v.body
    if frame in (mav.MAV_FRAME_BODY_NED, mav.MAV_FRAME_BODY_OFFSET_NED):
        vel = (*_rotate_body(v, msg.vx, msg.vy), msg.vz)
        pos = (*_rotate_body(v, msg.x, msg.y), msg.z)
    if frame != mav.MAV_FRAME_LOCAL_NED:
        pos = (b.n_m + pos[0], b.e_m + pos[1], b.d_m + pos[2])
    else:  # relative to the vehicle's EKF origin
        pos = (*v.sim_ne(pos[0], pos[1]), pos[2])
    return _apply(v, mask, pos, vel, _yaw(msg))


def handle_global_int(v, msg) -> bool:
    mask, frame = msg.type_mask, msg.coordinate_frame
    if v.mode.number != ModeNumber.GUIDED or frame not in GLOBAL_FRAMES or v.home_ned is None:
        return False
    lat, lon = msg.lat_int * 1e-7, msg.lon_int * 1e-7
    if not _used_finite(mask, (POS_IGNORE, msg.alt), (VEL_IGNORE, msg.vx, msg.vy, msg.vz),
                        (YAW_IGNORE, msg.yaw)):
        return False
    if (mask & POS_IGNORE) != POS_IGNORE and not (-90 <= lat <= 90 and -180 <= lon <= 180):
        return False
    n, e, d = v.ned_of(lat, lon, msg.alt)
    if frame != mav.MAV_FRAME_GLOBAL_INT:
        d = v.home_ned[2] - msg.alt
    return _apply(v, mask, (n, e, d), (msg.vx, msg.vy, msg.vz), _yaw(msg))

"""GUIDED's targets from MAVLink: SET_POSITION_TARGET_LOCAL_NED / _GLOBAL_INT and SET_ATTITUDE_TARGET.

As ArduCopter's handlers: taken only in a mode that takes GUIDED's targets (GUIDED,
GUIDED_NOGPS); a part of the target is used only when none of its ignore bits is set; the
combinations it flies are position [+ velocity [+ acceleration]], velocity [+ acceleration] and
acceleration. What it finds invalid (an unsupported frame or mask, a force, a velocity or
acceleration that is not a number or beyond 1000, an attitude quaternion that is not of unit
length, body rates only partly given, an ignored thrust) stops the vehicle, as ArduCopter
re-initialises GUIDED. Each handler returns whether the target was taken.
"""
from __future__ import annotations

import math

from ..results import Result
from .dialect import mavlink as mav

POS_IGNORE = 0x7
VEL_IGNORE = 0x38
ACCEL_IGNORE = 0x1C0
FORCE_SET = 0x200
YAW_IGNORE = 0x400
YAW_RATE_IGNORE = 0x800
# SET_ATTITUDE_TARGET's type_mask
RATES_IGNORE = 0x7
THRUST_IGNORE = 0x40
ATTITUDE_IGNORE = 0x80
THRUST_AS_THRUST = 1 << 3  # GUID_OPTIONS: SET_ATTITUDE_TARGET's thrust is a thrust, not a climb rate
SANE_LIMIT = 1000.0  # m/s or m/s/s: a velocity or acceleration beyond it is invalid
UNIT_QUATERNION_TOLERANCE = 1e-3

LOCAL_FRAMES = (mav.MAV_FRAME_LOCAL_NED, mav.MAV_FRAME_LOCAL_OFFSET_NED, mav.MAV_FRAME_BODY_NED,
                mav.MAV_FRAME_BODY_OFFSET_NED)
BODY_FRAMES = (mav.MAV_FRAME_BODY_NED, mav.MAV_FRAME_BODY_OFFSET_NED)
GLOBAL_ALT_FRAMES = {mav.MAV_FRAME_GLOBAL: "amsl", mav.MAV_FRAME_GLOBAL_INT: "amsl",
                     mav.MAV_FRAME_GLOBAL_RELATIVE_ALT: "home", mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT: "home",
                     mav.MAV_FRAME_GLOBAL_TERRAIN_ALT: "terrain", mav.MAV_FRAME_GLOBAL_TERRAIN_ALT_INT: "terrain"}


class Invalid(Exception):
    """A target ArduCopter refuses by stopping the vehicle."""


def _sane(vector) -> tuple:
    if not all(abs(x) <= SANE_LIMIT for x in vector):  # NaN fails too
        raise Invalid
    return tuple(vector)


def _rotate_body(v, x: float, y: float) -> tuple:
    yaw = v.attitude[2]
    c, s = math.cos(yaw), math.sin(yaw)
    return x * c - y * s, x * s + y * c


def _used(mask: int, bits: int) -> bool:
    return not mask & bits


def _send(v, mask: int, pos, vel, accel, yaw_relative: bool, msg, terrain: bool = False) -> bool:
    yaw = msg.yaw if _used(mask, YAW_IGNORE) else None
    yaw_rate = msg.yaw_rate if _used(mask, YAW_RATE_IGNORE) else None
    if yaw is not None and math.isnan(yaw) or yaw_rate is not None and math.isnan(yaw_rate):
        # ArduCopter flies the target and constrains the NaN heading (measured: internal error
        # 0x400, the position flown); Firefly holds the heading there.
        v.constraining_nan()
        yaw = yaw if yaw is not None and not math.isnan(yaw) else None
        yaw_rate = yaw_rate if yaw_rate is not None and not math.isnan(yaw_rate) else None
    if pos is None and vel is None and accel is None:
        raise Invalid  # nothing to fly (a position with only an acceleration is not a combination)
    if pos is not None and vel is None and accel is not None:
        raise Invalid
    return v.guided_target(pos, vel, accel, yaw, yaw_rate, yaw_relative, terrain) == Result.ACCEPTED


def _taken(v, handle, msg) -> bool:
    if not v.mode.in_guided_mode:
        return False
    try:
        return handle(v, msg)
    except Invalid:
        v.guided_stop()
        return False


def _local(v, msg) -> bool:
    mask, frame = msg.type_mask, msg.coordinate_frame
    if frame not in LOCAL_FRAMES or (mask & FORCE_SET and _used(mask, ACCEL_IGNORE)):
        raise Invalid
    body = frame in BODY_FRAMES
    pos = vel = accel = None
    if _used(mask, POS_IGNORE):
        x, y, z = msg.x, msg.y, msg.z
        if not all(math.isfinite(c) for c in (x, y, z)):
            raise Invalid  # measured: ArduCopter stops (slows down where it was going and holds)
        if body:
            x, y = _rotate_body(v, x, y)
        if frame == mav.MAV_FRAME_LOCAL_NED:  # from the EKF origin
            pos = (*v.sim_ne(x, y), z)  # as LOCAL_POSITION_NED reports the height
        elif not v.has_position():
            raise Invalid  # an offset needs a position to add it to
        else:
            b = v.body
            pos = (b.n_m + x, b.e_m + y, b.d_m + z)
    if _used(mask, VEL_IGNORE):
        vel = _sane((msg.vx, msg.vy, msg.vz))
        if body:
            vel = (*_rotate_body(v, vel[0], vel[1]), vel[2])
    if _used(mask, ACCEL_IGNORE):
        accel = _sane((msg.afx, msg.afy, msg.afz))
        if body:
            accel = (*_rotate_body(v, accel[0], accel[1]), accel[2])
    return _send(v, mask, pos, vel, accel, body, msg)


def _global(v, msg) -> bool:
    mask = msg.type_mask
    if mask & FORCE_SET and _used(mask, ACCEL_IGNORE):
        raise Invalid
    pos = vel = accel = None
    terrain = False
    if _used(mask, POS_IGNORE):
        lat, lon = msg.lat_int * 1e-7, msg.lon_int * 1e-7
        alt_from = GLOBAL_ALT_FRAMES.get(msg.coordinate_frame)
        if not (-90 <= lat <= 90 and -180 <= lon <= 180) or alt_from is None or not math.isfinite(msg.alt):
            raise Invalid
        if v.home_ned is None and alt_from != "amsl":
            raise Invalid
        n, e, d = v.ned_of(lat, lon, msg.alt)
        if alt_from == "home":
            d = v.home_ned[2] - msg.alt
        elif alt_from == "terrain":  # above the terrain under the vehicle (Guided.set_target)
            d, terrain = -msg.alt, True
        pos = (n, e, d)
    if _used(mask, VEL_IGNORE):
        vel = _sane((msg.vx, msg.vy, msg.vz))
    if _used(mask, ACCEL_IGNORE):
        accel = _sane((msg.afx, msg.afy, msg.afz))
    return _send(v, mask, pos, vel, accel, False, msg, terrain)


def _climb_or_thrust(v, thrust: float, use_thrust: bool) -> float:
    """The message's thrust field as ArduCopter reads it: a thrust (-1..1), or 0..1 with 0.5 a
    hover, above it a climb up to WPNAV_SPEED_UP and below a descent up to WPNAV_SPEED_DN [m/s].
    NaN is the middle of the range (ArduPilot's constrain)."""
    low = -1.0 if use_thrust else 0.0
    if math.isnan(thrust):
        v.constraining_nan()
        thrust = (low + 1.0) / 2.0
    thrust = max(low, min(1.0, thrust))
    if use_thrust:
        return thrust
    params = v.params
    if thrust >= 0.5:
        return (thrust - 0.5) * 2.0 * params["WPNAV_SPEED_UP"] / 100.0
    return (thrust - 0.5) * 2.0 * params["WPNAV_SPEED_DN"] / 100.0


def euler_of(w: float, x: float, y: float, z: float) -> tuple[float, float, float]:
    roll = math.atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2.0 * (w * y - z * x))))
    yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    return roll, pitch, yaw


def _attitude(v, msg) -> bool:
    mask = msg.type_mask
    if mask & THRUST_IGNORE:
        raise Invalid
    attitude = None
    if not mask & ATTITUDE_IGNORE:
        w, x, y, z = msg.q
        if not abs(w * w + x * x + y * y + z * z - 1.0) < UNIT_QUATERNION_TOLERANCE:  # NaN fails too
            raise Invalid
        attitude = euler_of(w, x, y, z)
    rates = (0.0, 0.0, 0.0)
    if not mask & RATES_IGNORE:
        rates = (msg.body_roll_rate, msg.body_pitch_rate, msg.body_yaw_rate)
        if not all(math.isfinite(r) for r in rates):
            raise Invalid  # Firefly's: rates that are no number would be flown as none
    elif mask & RATES_IGNORE != RATES_IGNORE:
        raise Invalid  # some rates given, not all
    use_thrust = bool(int(v.params["GUID_OPTIONS"]) & THRUST_AS_THRUST)
    return v.guided_attitude(attitude, rates, _climb_or_thrust(v, msg.thrust, use_thrust), use_thrust) == Result.ACCEPTED


def handle_local_ned(v, msg) -> bool:
    return _taken(v, _local, msg)


def handle_global_int(v, msg) -> bool:
    return _taken(v, _global, msg)


def handle_attitude_target(v, msg) -> bool:
    return _taken(v, _attitude, msg)

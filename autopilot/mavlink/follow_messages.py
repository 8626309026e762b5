"""What another system says of where it is, for FOLLOW's lead estimate (follow_target.py): its
GLOBAL_POSITION_INT and FOLLOW_TARGET, turned into this vehicle's local NED frame as ArduCopter's
AP_Follow reads them. Sans-IO: messages in, the estimate told.

Every system's messages are read, not only the ground station's, before any other handling (as
ArduPilot hands them to AP_Follow before its own sysid filter); the estimate decides whom it
follows.
"""
from __future__ import annotations

import math
from typing import Any

from ..vehicle import LOCATION_ALT_MAX_M

HEADING_UNKNOWN_CDEG = 36000  # GLOBAL_POSITION_INT.hdg above this: no heading given
CAN_POS, CAN_VEL, CAN_ACCEL, CAN_ATT = 1, 2, 4, 8  # FOLLOW_TARGET.est_capabilities bits


def on_global_position_int(vehicle: Any, msg: Any, now_s: float, sender: int | None = None) -> None:
    """sender: the system that sent it, when not in the message's header (another vehicle of this
    process, io/shared_air.py)."""
    target = vehicle.follow_target
    sender = msg.get_srcSystem() if sender is None else sender
    vehicle.position_heard(sender, msg.lat, msg.lon, msg.alt, msg.vx, msg.vy, msg.vz)  # ADS-B avoidance's too
    if not target.listens_to(sender, vehicle.system_id, now_s):
        return
    if msg.lat == 0 and msg.lon == 0:  # no fix
        return
    home = vehicle.home_ned
    if vehicle.params["FOLL_ALT_TYPE"] == 1:  # above home: ArduPilot cannot place it without home
        if home is None:
            return
        alt_amsl = vehicle.origin.alt_m - home[2] + msg.relative_alt / 1000.0
    else:
        alt_amsl = msg.alt / 1000.0
    pos = vehicle.ned_of(msg.lat / 1e7, msg.lon / 1e7, alt_amsl)
    vel = (msg.vx / 100.0, msg.vy / 100.0, msg.vz / 100.0)
    heading = msg.hdg / 100.0 if msg.hdg <= HEADING_UNKNOWN_CDEG else None
    target.hear(sender, now_s, msg.time_boot_ms / 1000.0, pos, vel, (0.0, 0.0, 0.0), heading, None, False)


def on_follow_target(vehicle: Any, msg: Any, now_s: float) -> None:
    target = vehicle.follow_target
    if not target.listens_to(msg.get_srcSystem(), vehicle.system_id, now_s):
        return
    caps = msg.est_capabilities
    if (msg.lat == 0 and msg.lon == 0) or not caps & CAN_POS:
        return
    values = (msg.alt, *msg.vel, *msg.acc, *msg.attitude_q, *msg.rates)
    if not all(math.isfinite(v) for v in values) or abs(msg.alt) > LOCATION_ALT_MAX_M:
        return  # ArduPilot would take the NaN (or an altitude its Location cannot hold) in; Firefly flies to neither
    pos = vehicle.ned_of(msg.lat / 1e7, msg.lon / 1e7, msg.alt)
    vel = tuple(msg.vel) if caps & CAN_VEL else (0.0, 0.0, 0.0)
    accel = tuple(msg.acc) if caps & CAN_ACCEL else (0.0, 0.0, 0.0)
    heading = rate = None
    if caps & CAN_ATT:
        w, x, y, z = msg.attitude_q
        heading = math.degrees(math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))) % 360.0
        rate = math.degrees(_earth_yaw_rate((w, x, y, z), msg.rates))
    # ArduPilot reads the 64-bit timestamp as 32-bit milliseconds
    target.hear(msg.get_srcSystem(), now_s, (msg.timestamp & 0xFFFFFFFF) / 1000.0, pos, vel, accel, heading, rate,
                True)


def _earth_yaw_rate(q: tuple, body_rates: Any) -> float:
    """The down component of body rates turned into the earth frame by attitude q."""
    w, x, y, z = q
    p, r_q, r = body_rates
    # third row of the rotation matrix (body to earth)
    return (2.0 * (x * z - w * y)) * p + (2.0 * (y * z + w * x)) * r_q + (1.0 - 2.0 * (x * x + y * y)) * r

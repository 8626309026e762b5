"""The pilot's input over MAVLink (sans-IO): RC_CHANNELS_OVERRIDE and MANUAL_CONTROL turned into RC
overrides (autopilot/rc/overrides.py), as ArduPilot's GCS_MAVLINK handles them.

Both are taken only from the ground station's system id (MAV_GCS_SYSID, 255 by default: MAVSDK's
ManualControl, sent from 245, moves nothing); MANUAL_CONTROL also only when aimed at this vehicle.

RC_CHANNELS_OVERRIDE: channels 1-8 take any value but UINT16_MAX ("leave it"), 0 gives the
channel back to the receiver; channels 9-16 take any value but 0 and UINT16_MAX ("leave it"),
UINT16_MAX-1 gives it back.
MANUAL_CONTROL: x (pitch, forward positive), y (roll), r (yaw) in -1000..1000 and z (throttle)
in 0..1000 are spread over the mapped channel's RCn_MIN..MAX (INT16_MAX: release that axis);
a message with z below 0 is ignored whole (Copter has no reverse thrust).
"""
from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..vehicle import Vehicle

UINT16_MAX, INT16_MAX = 65535, 32767
FIRST_FIELDS = 8  # RC_CHANNELS_OVERRIDE's channels 1-8: 0 releases


def from_ground_station(vehicle: Vehicle, msg) -> bool:
    return msg.get_srcSystem() == int(vehicle.params["MAV_GCS_SYSID"])


def rc_channels_override(vehicle: Vehicle, msg, now_s: float) -> bool:
    """Overrides from RC_CHANNELS_OVERRIDE; False when the sender is not the ground station."""
    if not from_ground_station(vehicle, msg):
        return False
    overrides = vehicle.rc.overrides
    for i in range(16):
        value = getattr(msg, f"chan{i + 1}_raw", UINT16_MAX)  # MAVLink 1 frames carry 8
        if value == UINT16_MAX:
            continue
        if i >= FIRST_FIELDS:
            if value == 0:
                continue
            value = 0 if value == UINT16_MAX - 1 else value
        overrides.set(i, value, now_s)
    return True


def manual_control(vehicle: Vehicle, msg, now_s: float) -> bool:
    """Overrides of the four mapped sticks from MANUAL_CONTROL; False when ignored."""
    if not from_ground_station(vehicle, msg) or msg.target != vehicle.system_id or msg.z < 0:
        return False
    p = vehicle.params
    axes = (("RCMAP_ROLL", msg.y, 1000, 2000, False), ("RCMAP_PITCH", msg.x, 1000, 2000, True),
            ("RCMAP_THROTTLE", msg.z, 0, 1000, False), ("RCMAP_YAW", msg.r, 1000, 2000, False))
    for role, value, offset, scale, reverse in axes:
        channel = int(p[role])
        value = int(value)
        if value == INT16_MAX:
            pwm = 0
        else:
            low, high = int(p[f"RC{channel}_MIN"]), int(p[f"RC{channel}_MAX"])
            value = -value if reverse else value
            pwm = low + _c_div((high - low) * (value + offset), scale)
        vehicle.rc.overrides.set(channel - 1, _int16(pwm) & 0xFFFF, now_s)
    return True


def _c_div(a: int, b: int) -> int:
    """C's integer division (towards zero)."""
    q = abs(a) // abs(b)
    return q if (a >= 0) == (b > 0) else -q


def _int16(v: int) -> int:
    """As the int16_t ArduPilot computes the PWM in."""
    return (v + 0x8000) % 0x10000 - 0x8000

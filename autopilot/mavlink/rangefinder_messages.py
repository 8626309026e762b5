"""The rangefinder's messages, as ArduCopter sends RNGFND1's (GCS_MAVLINK's send_distance_sensor and
send_rangefinder), both in the EXTRA3 stream:
- DISTANCE_SENSOR while the rangefinder has data, out of range included: its raw range and the
  limits it is judged by in centimetres (truncated), id 0 (the instance), its orientation and type,
  covariance 0, no field of view or quaternion, and the signal quality as MAVLink has it (0 unknown);
- RANGEFINDER whenever a rangefinder faces down, data or not: its last range in metres, even a
  stale one, and a voltage of 0 (only an analog sensor has one).
SYS_STATUS's laser-position bit (telemetry.py) says the same: present and enabled with a downward
rangefinder, healthy while it has data.
"""
from __future__ import annotations

from ..c_casts import float32
from ..proximity import FIRST_ID, SECTORS, Proximity
from ..views import TelemetryView
from .encoding import time_boot_ms
from .dialect import mavlink as mav

CM_MAX = 65535


def _cm(metres: float) -> int:
    """Centimetres as ArduPilot truncates a float32 range times 100 (in float32) into a uint16 (a
    range no sensor gives, negative, huge or NaN, is held to the field: the message must go out)."""
    if not 0.0 <= metres < CM_MAX:  # NaN too
        return 0 if not metres > 0.0 else CM_MAX
    return min(int(float32(metres * 100.0)), CM_MAX)


def _mavlink_quality(quality: int) -> int:
    """ArduPilot's -1 (unknown) is MAVLink's 0; 0 and 1, the worst, are 1; 2-100 as they are."""
    if quality == -1:
        return 0
    return quality if 1 < quality <= 100 else 1


def distance_sensor(v: TelemetryView, codec):
    r = v.rangefinder_reading()
    own = None
    if r.has_data:
        own = codec.distance_sensor_encode(time_boot_ms(v), _cm(r.min_m), _cm(r.max_m), _cm(r.distance_m),
                                           r.sensor_type, 0, r.orientation, 0, 0.0, 0.0, (0.0, 0.0, 0.0, 0.0),
                                           _mavlink_quality(r.signal_quality))
    prox = v.proximity
    if not prox.kind:
        return own
    return ([own] if own is not None else []) + proximity_sensors(prox, time_boot_ms(v), codec)


def proximity_sensors(prox: Proximity, stamp_ms: int, codec) -> list:
    """The proximity sensor as GCS_MAVLINK's send_proximity: with data, one DISTANCE_SENSOR per
    sector ever reported (id 10 + sector, facing it; a sector without a reading now reads the
    sensor's maximum), then the room above (id 19, facing up) whenever there is a figure for it.
    Laser, covariance 0. (ArduPilot keeps 'ever reported' per link, Firefly per vehicle.)"""
    low, high = _cm(prox.range_m[0]), _cm(prox.range_m[1])
    out = []
    if prox.good:
        for sector in range(SECTORS):
            if prox.valid[sector]:
                distance = prox.distance[sector]
            elif prox.ever_valid >> sector & 1:
                distance = prox.range_m[1]
            else:
                continue
            out.append(codec.distance_sensor_encode(stamp_ms, low, high, _cm(distance), mav.MAV_DISTANCE_SENSOR_LASER,
                                                    FIRST_ID + sector, sector, 0, 0.0, 0.0, (0.0, 0.0, 0.0, 0.0), 0))
    if prox.upward_m is not None:
        out.append(codec.distance_sensor_encode(stamp_ms, low, high, _cm(prox.upward_m), mav.MAV_DISTANCE_SENSOR_LASER,
                                                FIRST_ID + SECTORS + 1, mav.MAV_SENSOR_ROTATION_PITCH_90, 0, 0.0, 0.0,
                                                (0.0, 0.0, 0.0, 0.0), 0))
    return out


def rangefinder(v: TelemetryView, codec):
    if not v.rangefinder_down:
        return None
    return codec.rangefinder_encode(v.rangefinder_reading().distance_m, 0.0)


BUILDERS = {
    mav.MAVLINK_MSG_ID_DISTANCE_SENSOR: distance_sensor,
    mav.MAVLINK_MSG_ID_RANGEFINDER: rangefinder,
}

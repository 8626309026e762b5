"""The optical flow sensor's message, as ArduCopter sends it (GCS_MAVLINK's send_opticalflow), in the
EXTRA3 stream while the sensor is healthy:
- time_usec carries the boot time in milliseconds (ArduPilot's millis(), in a microseconds field);
- sensor id 0; flow_x and flow_y, the "pixel" fields, are the flow rates [rad/s] cast to int16,
  which truncates them (0 for any flow under 1 rad/s);
- flow_comp_m_x and _y are not metres: the flow less the body rates [rad/s];
- ground_distance is the EKF's height above ground, 0 when it has none (measured: 0 without a
  rangefinder, all Firefly has with a flow sensor);
- flow_rate_x and _y are the flow rates [rad/s], the body's rotation included.
SYS_STATUS's optical-flow bit (telemetry.py) is present and enabled while FLOW_TYPE is set, healthy
while samples come.
"""
from __future__ import annotations

from ..views import TelemetryView
from .dialect import mavlink as mav
from .encoding import time_boot_ms

INT16_MAX = 32767


def _int16(x: float) -> int:
    """C's float-to-int16 cast of a rate: towards zero, held to the field (a rate no camera gives,
    NaN or infinite, must not stop the message)."""
    if x != x:
        return 0
    return int(max(-INT16_MAX - 1.0, min(float(INT16_MAX), x)))


def optical_flow(v: TelemetryView, codec):
    flow = v.optical_flow
    if not flow.healthy(v.time_s):
        return None
    r = flow.reading
    return codec.optical_flow_encode(time_boot_ms(v), 0, _int16(r.flow_x), _int16(r.flow_y),
                                     r.flow_x - r.body_x, r.flow_y - r.body_y, r.quality, 0.0,
                                     r.flow_x, r.flow_y)


BUILDERS = {mav.MAVLINK_MSG_ID_OPTICAL_FLOW: optical_flow}

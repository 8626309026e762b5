"""The winch's message, as ArduCopter's AP_Winch_PWM sends it (payload/winch.py); none without a
winch made at boot.

WINCH_STATUS is in the EXTRA1 stream: the line out as the autopilot reckons it [m], the rate it
asks (+ve lowering) [m/s] - the last asked, relaxed too - and nothing it cannot know: tension,
voltage and current NaN, temperature INT16_MAX. Its one flag, HEALTHY, while an output has
SERVOn_FUNCTION 88.
"""
from __future__ import annotations

from ..views import TelemetryView
from .dialect import mavlink as mav

NAN = float("nan")
NO_TEMPERATURE = 32767  # INT16_MAX: unknown


def winch_status(v: TelemetryView, codec):
    winch = v.winch
    if not winch.kind:
        return None
    flags = mav.MAV_WINCH_STATUS_HEALTHY if winch.healthy else 0
    return codec.winch_status_encode(int(v.time_s * 1e6), winch.line_m, winch.rate_desired_m_s, NAN, NAN, NAN,
                                     NO_TEMPERATURE, flags)


BUILDERS = {mav.MAVLINK_MSG_ID_WINCH_STATUS: winch_status}
# Asked for by REQUEST_MESSAGE, it is ACCEPTED with a winch or none (ArduPilot queues it and then
# has nothing to send).
REQUESTABLE = frozenset(BUILDERS)

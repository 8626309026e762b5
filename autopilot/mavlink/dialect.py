"""The one place that chooses the MAVLink dialect: ArduPilot's, MAVLink 2."""
import os

os.environ.setdefault("MAVLINK20", "1")

from pymavlink.dialects.v20 import ardupilotmega as mavlink  # noqa: E402

AUTOPILOT_COMPONENT_ID = 1


def new_codec(system_id: int, component_id: int = AUTOPILOT_COMPONENT_ID) -> "mavlink.MAVLink":
    """An encoder/decoder; robust parsing turns bad frames into BAD_DATA instead of raising."""
    codec = mavlink.MAVLink(None, srcSystem=system_id, srcComponent=component_id)
    codec.robust_parsing = True
    return codec

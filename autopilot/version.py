"""Which ArduCopter Firefly is: the reference's version, as AUTOPILOT_VERSION and the banner say it.

Firefly serves the parameter set of ArduCopter 4.7.0-dev (autopilot/data/arducopter_params.json),
so it says it is that firmware, as the reference SITL does (measured with pymavlink on ArduCopter
SITL at commit 90700977c553d2dfd95a305acf1c3e098e4d9477, `--model quad`):

  AUTOPILOT_VERSION  capabilities 64495, flight_sw_version 0x04070000 (4.7.0, type DEV = 0),
                     flight_custom_version the hash's first 8 hex digits as ASCII, middleware and
                     OS versions 0, board_version 0, vendor and product ids 0, uid 0, uid2 the
                     board id (below) as ASCII, cut to 17 characters and a NUL
  banner             "ArduCopter V4.7.0-dev (90700977)", the board id, "Frame: QUAD/PLUS"
                     (INFO; sent for DO_SEND_BANNER and at the start of a parameter download)

The board id is SITL's system id: the host's machine id (/etc/machine-id) with its first character
moved on by the instance number, so that two instances differ. It is read at the I/O edge
(autopilot/io/board_id.py) and handed in.
"""
from __future__ import annotations

from .results import Severity

VERSION = (4, 7, 0)
FIRMWARE_VERSION_TYPE_DEV = 0  # MAV's FIRMWARE_VERSION_TYPE: DEV 0 ... OFFICIAL 255
GIT_HASH = "90700977"  # the reference's commit, as ArduPilot's build stamps it (8 hex digits)
FLIGHT_SW_VERSION = (VERSION[0] << 24) | (VERSION[1] << 16) | (VERSION[2] << 8) | FIRMWARE_VERSION_TYPE_DEV
FLIGHT_CUSTOM_VERSION = list(GIT_HASH.encode())
# MAV_PROTOCOL_CAPABILITY bits the reference sets: MISSION_FLOAT, PARAM_FLOAT, MISSION_INT,
# COMMAND_INT, SET_POSITION_TARGET_LOCAL_NED, SET_POSITION_TARGET_GLOBAL_INT, SET_ATTITUDE_TARGET,
# TERRAIN, MAVLINK2, MISSION_FENCE, MISSION_RALLY, FLIGHT_INFORMATION, PARAM_ENCODE_C_CAST, FTP.
CAPABILITIES = 64495
FW_STRING = f"ArduCopter V{VERSION[0]}.{VERSION[1]}.{VERSION[2]}-dev ({GIT_HASH})"
UID2_CHARS = 17  # SITL reads 18 bytes of the id into uid2 and ends them with a NUL
UID2_LEN = 18

# ArduCopter's frame names (AP_Motors): FRAME_CLASS and FRAME_TYPE as the banner spells them.
FRAME_CLASSES = {1: "QUAD", 2: "HEXA", 3: "OCTA", 4: "OCTAQUAD", 5: "Y6", 7: "TRI", 10: "DODECAHEXA",
                 12: "DECA"}
FRAME_TYPES = {0: "PLUS", 1: "X", 2: "V", 3: "H", 4: "V_TAIL", 5: "A_TAIL", 10: "Y6B", 11: "Y6F",
               12: "BF_X", 13: "DJI_X", 14: "CW_X", 16: "NYT_PLUS", 17: "NYT_X", 18: "BF_X_REV"}
FALLBACK_BOARD_ID = "sitl-unknown-{instance}"  # SITL's own when it finds no id at all


def board_id_for(machine_id: str | None, instance: int) -> str:
    """SITL's system id for `instance` on a host whose machine id is `machine_id` (None: none)."""
    if not machine_id:
        return FALLBACK_BOARD_ID.format(instance=instance)
    return chr((ord(machine_id[0]) + instance) % 256) + machine_id[1:]


def uid2(board_id: str) -> list[int]:
    data = board_id.encode("latin-1", "replace")[:UID2_CHARS]
    return list(data) + [0] * (UID2_LEN - len(data))


def frame_string(frame_class: float, frame_type: float) -> str:
    name = FRAME_CLASSES.get(int(frame_class), "UNSUPPORTED")
    return f"Frame: {name}/{FRAME_TYPES.get(int(frame_type), 'UNSUPPORTED')}"


def banner(board_id: str, params) -> list[tuple[Severity, str]]:
    """The texts ArduCopter SITL sends as its banner (GCS_MAVLINK_Copter::send_banner)."""
    return [(Severity.INFO, FW_STRING), (Severity.INFO, board_id),
            (Severity.INFO, frame_string(params["FRAME_CLASS"], params["FRAME_TYPE"]))]

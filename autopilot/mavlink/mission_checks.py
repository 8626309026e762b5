"""Whether a mission, fence or rally item (and a whole fence) is one ArduCopter stores, and if not,
the MAV_MISSION_RESULT it answers: AP_Mission's conversion of an item for missions, the fence and
rally protocols' for theirs, and AC_PolyFence_loader's validation of a complete fence.

Checked against the reference vehicle by the parity probes missions (fence_and_rally_items,
local_frame_items) and refusals (bad_items).
"""
from __future__ import annotations

import math

from ..c_casts import as_uint16
from ..mission import FENCE, MISSION, RALLY, MissionItem
from ..mission.commands import CMD_DO_JUMP, NAMES
from .dialect import mavlink as mav

GLOBAL_FRAMES = {mav.MAV_FRAME_GLOBAL, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT, mav.MAV_FRAME_GLOBAL_INT,
                 mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, mav.MAV_FRAME_GLOBAL_TERRAIN_ALT,
                 mav.MAV_FRAME_GLOBAL_TERRAIN_ALT_INT}
ALLOWED_FRAMES = GLOBAL_FRAMES | {mav.MAV_FRAME_MISSION, mav.MAV_FRAME_LOCAL_NED}
# An item with a position takes it as latitude/longitude/altitude: ArduCopter's AP_Mission refuses
# any other frame for one (a local NED waypoint is MAV_MISSION_UNSUPPORTED_FRAME).
LOCATION_FRAMES = GLOBAL_FRAMES | {mav.MAV_FRAME_MISSION}
# Commands whose x/y are a latitude/longitude that must make sense.
POSITIONAL = {mav.MAV_CMD_NAV_WAYPOINT, mav.MAV_CMD_NAV_LOITER_UNLIM, mav.MAV_CMD_NAV_LOITER_TURNS,
              mav.MAV_CMD_NAV_LOITER_TIME, mav.MAV_CMD_NAV_LAND, mav.MAV_CMD_NAV_TAKEOFF,
              mav.MAV_CMD_NAV_SPLINE_WAYPOINT, mav.MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION,
              mav.MAV_CMD_NAV_FENCE_POLYGON_VERTEX_EXCLUSION, mav.MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION,
              mav.MAV_CMD_NAV_FENCE_CIRCLE_EXCLUSION, mav.MAV_CMD_NAV_RALLY_POINT,
              mav.MAV_CMD_NAV_FENCE_RETURN_POINT}


# As AP_Mission checks an item's params: infinity never, NaN only where it means "unchanged"
# (a yaw left as it is); commands 0 and 1 are reserved (MAV_MISSION_INVALID).
NAN_ALLOWED = {mav.MAV_CMD_NAV_WAYPOINT: (4,), mav.MAV_CMD_NAV_LOITER_UNLIM: (4,), mav.MAV_CMD_NAV_LAND: (4,),
               mav.MAV_CMD_NAV_TAKEOFF: (4,), mav.MAV_CMD_NAV_VTOL_TAKEOFF: (4,), mav.MAV_CMD_NAV_VTOL_LAND: (3, 4)}
RESERVED_COMMANDS = {0, 1}


def item_from_message(msg) -> MissionItem:
    """MISSION_ITEM_INT as is; MISSION_ITEM (float degrees) scaled to the INT convention."""
    if msg.get_type() == "MISSION_ITEM_INT":
        x, y = msg.x, msg.y
    elif msg.frame in GLOBAL_FRAMES and math.isfinite(msg.x) and math.isfinite(msg.y):
        x, y = int(round(msg.x * 1e7)), int(round(msg.y * 1e7))
    else:
        x, y = (int(msg.x) if math.isfinite(msg.x) else 2**31), (int(msg.y) if math.isfinite(msg.y) else 2**31)
    return MissionItem(msg.command, msg.frame, msg.param1, msg.param2, msg.param3, msg.param4, x, y,
                       msg.z, msg.autocontinue)


FENCE_COMMANDS = {mav.MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION, mav.MAV_CMD_NAV_FENCE_POLYGON_VERTEX_EXCLUSION,
                  mav.MAV_CMD_NAV_FENCE_RETURN_POINT, mav.MAV_CMD_NAV_FENCE_CIRCLE_EXCLUSION,
                  mav.MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION}
VERTEX_COMMANDS = {mav.MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION, mav.MAV_CMD_NAV_FENCE_POLYGON_VERTEX_EXCLUSION}
CIRCLE_COMMANDS = {mav.MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION, mav.MAV_CMD_NAV_FENCE_CIRCLE_EXCLUSION}
# AC_PolyFenceType's numbers, as the validation's texts name the kinds
FENCE_TYPE = {mav.MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION: 98, mav.MAV_CMD_NAV_FENCE_POLYGON_VERTEX_EXCLUSION: 97,
              mav.MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION: 92, mav.MAV_CMD_NAV_FENCE_CIRCLE_EXCLUSION: 93,
              mav.MAV_CMD_NAV_FENCE_RETURN_POINT: 95}


def position_result(item: MissionItem) -> int:
    """A latitude and longitude (1e-7 degrees) on the globe, or which of them is not."""
    if not -900_000_000 <= item.x <= 900_000_000:
        return mav.MAV_MISSION_INVALID_PARAM5_X
    if not -1_800_000_000 <= item.y <= 1_800_000_000:
        return mav.MAV_MISSION_INVALID_PARAM6_Y
    return mav.MAV_MISSION_ACCEPTED


def check_fence_item(item: MissionItem) -> int:
    """As ArduPilot's fence protocol converts an item: a global frame, a fence command, a vertex
    count a byte holds."""
    if item.frame not in GLOBAL_FRAMES:
        return mav.MAV_MISSION_UNSUPPORTED_FRAME
    if item.command not in FENCE_COMMANDS:
        return mav.MAV_MISSION_UNSUPPORTED
    if item.command in VERTEX_COMMANDS and item.p1 > 255:
        return mav.MAV_MISSION_INVALID_PARAM1
    return mav.MAV_MISSION_ACCEPTED


def check_rally_item(item: MissionItem) -> int:
    """As ArduPilot's rally protocol converts an item: a rally point, on the globe, at an altitude
    a 16-bit integer holds, in a global frame."""
    if item.command != mav.MAV_CMD_NAV_RALLY_POINT:
        return mav.MAV_MISSION_UNSUPPORTED
    if (result := position_result(item)) != mav.MAV_MISSION_ACCEPTED:
        return result
    if item.z > 32767 or item.z < -32768:  # NaN passes, as in ArduPilot's conversion (measured)
        return mav.MAV_MISSION_INVALID_PARAM7
    if item.frame not in GLOBAL_FRAMES:
        return mav.MAV_MISSION_UNSUPPORTED_FRAME
    return mav.MAV_MISSION_ACCEPTED


def check_item(item: MissionItem, kind: int = MISSION) -> int:
    """MAV_MISSION_RESULT for one item of a list of `kind`: ACCEPTED or the first problem found."""
    if kind == FENCE:
        return check_fence_item(item)
    if kind == RALLY:
        return check_rally_item(item)
    # In AP_Mission's order: the params, then the command, then where the item is.
    nan_allowed = NAN_ALLOWED.get(item.command, ())
    for n, value in enumerate((item.p1, item.p2, item.p3, item.p4), start=1):
        if math.isinf(value) or (math.isnan(value) and n not in nan_allowed):
            return getattr(mav, f"MAV_MISSION_INVALID_PARAM{n}")
    if item.command in RESERVED_COMMANDS:
        return mav.MAV_MISSION_INVALID
    if item.command not in NAMES:  # a command AP_Mission does not store
        return mav.MAV_MISSION_UNSUPPORTED
    if item.frame not in ALLOWED_FRAMES or (item.command in POSITIONAL and item.frame not in LOCATION_FRAMES):
        return mav.MAV_MISSION_UNSUPPORTED_FRAME
    # z is an altitude only for positional items; elsewhere ArduCopter ignores it, NaN included
    # (MAVSDK's mission plugin sends DO_CHANGE_SPEED with z = NaN).
    if math.isinf(item.z) or abs(item.z) > 100_000 or (math.isnan(item.z) and item.command in POSITIONAL):
        return mav.MAV_MISSION_INVALID_PARAM7
    if item.command in POSITIONAL and item.frame in GLOBAL_FRAMES:
        return position_result(item)
    return mav.MAV_MISSION_ACCEPTED




def check_list_item(item: MissionItem, kind: int, count: int, stored: int) -> int:
    """What an item that passed check_item still needs in its place in the list: a DO_JUMP must
    jump to an item that is or will be there (MissionItemProtocol_Waypoints: not 0, and below the
    stored list's length or at most the upload's last seq), else MAV_MISSION_ERROR.
    `stored`: the mission's items now, home included."""
    if kind == MISSION and item.command == CMD_DO_JUMP:
        target = as_uint16(item.p1)
        if target == 0 or (target >= stored and target > count - 1):
            return mav.MAV_MISSION_ERROR
    return mav.MAV_MISSION_ACCEPTED


def fence_problem(items: list[MissionItem]) -> str | None:
    """What AC_PolyFence_loader's validation says of a complete fence (None: it is stored): each
    polygon's vertices say how many they are (param 1, as a byte holds it), at least 3, all of one
    kind; a circle's radius is positive; one return point at most."""
    expected, kind, count = 0, None, 0
    returns = 0
    for item in items:
        if item.command in VERTEX_COMMANDS:
            vertices = as_uint16(item.p1) & 0xFF
            if vertices < 3:
                return f"Invalid vertex count ({vertices})"
            if expected == 0:
                expected, kind, count = vertices, item.command, vertices
            elif item.command != kind:
                return f"Received incorrect vertex type (want={FENCE_TYPE[kind]} got={FENCE_TYPE[item.command]})"
            elif vertices != count:
                return f"Unexpected vertex count want={count} got={vertices}"
            expected -= 1
        elif expected:
            return f"Received incorrect type (want={FENCE_TYPE[kind]} got={FENCE_TYPE[item.command]})"
        elif item.command in CIRCLE_COMMANDS and not item.p1 > 0:  # NaN is not positive either
            return "Non-positive circle radius"
        elif item.command == mav.MAV_CMD_NAV_FENCE_RETURN_POINT:
            returns += 1
            if returns > 1:
                return "Multiple return points"
        if position_result(item) != mav.MAV_MISSION_ACCEPTED:
            return "Bad lat or lon"
    if expected:
        return "Incorrect item count"
    return None

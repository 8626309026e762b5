"""The guided waypoint: a MISSION_ITEM / MISSION_ITEM_INT with current = 2 (DroneKit's simple_goto,
MAVProxy's `guided`, Mission Planner's "Fly to here"), and current = 3 (change altitude).

As ArduCopter: such an item of the mission list is no upload's; it is converted as a mission
item (what it refuses is answered with the item's MAV_MISSION_RESULT), then a waypoint is flown
to in a mode that takes GUIDED's targets and a CONDITION_YAW turned to (MAV_MISSION_ACCEPTED),
anything else, or any other mode, MAV_MISSION_ERROR. current = 3 is accepted and changes
nothing (ArduCopter has no altitude change for a copter).
"""
from __future__ import annotations

from ..mission import MISSION
from ..results import Result
from .command_locations import ABSOLUTE_ALT_FRAMES, TERRAIN_ALT_FRAMES
from .dialect import mavlink as mav
from .mission_checks import check_item, item_from_message

GUIDED_WAYPOINT, CHANGE_ALTITUDE = 2, 3


def guided_request(v, msg) -> int | None:
    """The MAV_MISSION_RESULT to answer, or None when the item is no guided request."""
    if msg.mission_type != MISSION or msg.current not in (GUIDED_WAYPOINT, CHANGE_ALTITUDE):
        return None
    item = item_from_message(msg)
    result = check_item(item, MISSION)
    if result != mav.MAV_MISSION_ACCEPTED or msg.current == CHANGE_ALTITUDE:
        return result
    if not v.mode.in_guided_mode:
        return mav.MAV_MISSION_ERROR
    if item.command == mav.MAV_CMD_CONDITION_YAW:
        v.set_yaw(item.p1, relative=item.p4 > 0, direction=int(item.p3), rate_deg_s=item.p2)
        return mav.MAV_MISSION_ACCEPTED
    if item.command != mav.MAV_CMD_NAV_WAYPOINT:
        return mav.MAV_MISSION_ERROR
    lat, lon = item.x * 1e-7, item.y * 1e-7
    terrain = item.frame in TERRAIN_ALT_FRAMES
    if item.frame in ABSOLUTE_ALT_FRAMES:
        target = v.ned_of(lat, lon, item.z)
    elif terrain:  # above the terrain, as GUIDED flies it (Guided.set_target)
        n, e, _ = v.ned_of(lat, lon, v.origin.alt_m)
        target = (n, e, -item.z)
    elif v.home_ned is None:
        return mav.MAV_MISSION_ERROR  # a height above home needs home
    else:
        n, e, _ = v.ned_of(lat, lon, v.origin.alt_m)
        target = (n, e, v.home_ned[2] - item.z)
    taken = v.guided_target(target, None, None, terrain=terrain) == Result.ACCEPTED
    return mav.MAV_MISSION_ACCEPTED if taken else mav.MAV_MISSION_ERROR

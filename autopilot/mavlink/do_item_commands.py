"""The mission's "do" items sent as commands (COMMAND_LONG / COMMAND_INT): the fence switch, the
mission's current item and its tags, the region of interest (DO_SET_ROI_SYSID, a gimbal's only:
mount_commands.py). Joined into the command table (commands.HANDLERS) as **HANDLERS."""
from __future__ import annotations

import math

from ..c_casts import as_uint16
from ..results import Result
from .command_locations import is_location, target_ned
from .dialect import mavlink as mav

UINT16_MAX = 0xFFFF


def do_fence_enable(s, c) -> Result:
    """Param 1: 0 off, 1 on, 2 the floor off; param 2: which fences (a FENCE_TYPE mask, 0 all)."""
    return s.vehicle.fence_enable(as_uint16(c.p1), as_uint16(c.p2) & 0xFF)


def _announce_current(s) -> None:
    """ArduCopter volunteers MISSION_CURRENT once the current item changed."""
    s.queue(s.build(mav.MAVLINK_MSG_ID_MISSION_CURRENT))


def do_set_mission_current(s, c) -> Result:
    """Param 1 the seq (DENIED if the list has none such: an empty list has none); param 2 = 1
    resets the mission (jump counts, a completed state) and resumes it from there."""
    seq = _uint32(c.p1)
    progress = s.vehicle.mission_progress
    if seq is None or not seq <= len(progress.items()) or not progress.items():
        return Result.DENIED
    reset = c.p2 == 1
    if reset:
        progress.reset()
    if not progress.set_current(seq):
        return Result.FAILED
    if reset:
        progress.resume()
    _announce_current(s)
    return Result.ACCEPTED


def do_jump_tag(s, c) -> Result:
    """Param 1 the tag: the first JUMP_TAG carrying it becomes current (FAILED: none does)."""
    tag = _uint32(c.p1)
    if tag is None or tag > UINT16_MAX:
        return Result.DENIED
    if not s.vehicle.mission_progress.jump_to_tag(tag):
        return Result.FAILED
    _announce_current(s)
    return Result.ACCEPTED


def do_set_roi(s, c) -> Result:
    """DO_SET_ROI_LOCATION and DO_SET_ROI (whose mode, param 1, ArduCopter does not read): a
    location to face (DENIED: not a location); all zeros clears. Without a position the point
    cannot be placed: accepted, and nothing turns (as ArduCopter)."""
    if not c.is_int:
        c = c._replace(frame=mav.MAV_FRAME_GLOBAL_RELATIVE_ALT)  # ArduCopter's frame for them
    if not is_location(s, c):
        return Result.DENIED
    v = s.vehicle
    if c.p5 == 0 and c.p6 == 0 and c.p7 == 0:
        return v.set_roi(None)
    if not v.has_position():
        return Result.ACCEPTED
    n, e, _ = v.ned_of(c.p5, c.p6, v.origin.alt_m)
    target = target_ned(s, c)  # for its height above home, in the command's frame (a gimbal's pitch)
    return v.set_roi((n, e, 0.0 if target is None else v.height_ref_d - target[2]))


def do_set_roi_none(s, c) -> Result:
    return s.vehicle.set_roi(None)


def _uint32(value: float) -> int | None:
    """A float parameter as C's (uint32_t) cast takes it; None where that cast means nothing
    (NaN, negative, too large: undefined in C, refused here)."""
    if not (math.isfinite(value) and 0 <= value < 2**32):
        return None
    return int(value)


HANDLERS = {
    mav.MAV_CMD_DO_FENCE_ENABLE: do_fence_enable,
    mav.MAV_CMD_DO_SET_MISSION_CURRENT: do_set_mission_current,
    mav.MAV_CMD_DO_JUMP_TAG: do_jump_tag,
    mav.MAV_CMD_DO_SET_ROI_LOCATION: do_set_roi,
    mav.MAV_CMD_DO_SET_ROI: do_set_roi,
    mav.MAV_CMD_DO_SET_ROI_NONE: do_set_roi_none,
}

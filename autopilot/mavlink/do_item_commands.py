"""The mission's "do" items sent as commands (COMMAND_LONG / COMMAND_INT): the fence switch, the
mission's current item and its tags, the region of interest. Joined into the command table
(commands.HANDLERS) as **HANDLERS."""
from __future__ import annotations

from ..c_casts import as_uint16
from ..results import Result
from .dialect import mavlink as mav


def do_fence_enable(s, c) -> Result:
    """Param 1: 0 off, 1 on, 2 the floor off; param 2: which fences (a FENCE_TYPE mask, 0 all)."""
    return s.vehicle.fence_enable(as_uint16(c.p1), as_uint16(c.p2) & 0xFF)


HANDLERS = {
    mav.MAV_CMD_DO_FENCE_ENABLE: do_fence_enable,
}

"""DO_SET_ROI_LOCATION, DO_SET_ROI and DO_SET_ROI_NONE in a mission: the nose turns to the item's
location and stays on it through the legs that follow (ArduCopter's do_roi); a location of all
zeros (ROI_NONE always has one) clears it. DO_SET_ROI's mode (param 1) is not read: ArduCopter
points at the location whatever it says. With a gimbal that pans, the gimbal looks instead
(payload/mount.py's take_roi); one that only tilts tilts to it as the nose turns."""
from __future__ import annotations

from functools import partial
from typing import TYPE_CHECKING

from ...payload.mount import take_roi
from . import AutoItem

if TYPE_CHECKING:
    from ...mission.store import MissionItem
    from ..auto import Auto
    from ..context import ModeContext


class SetRoi(AutoItem):
    def start(self, auto: Auto, ctx: ModeContext, index: int, item: MissionItem) -> bool:
        face = partial(auto.set_roi, ctx)
        if item.x == 0 and item.y == 0 and item.z == 0:
            take_roi(ctx.mount, face, None)
        else:
            n, e, _ = ctx.ned_of(item.x * 1e-7, item.y * 1e-7, ctx.origin_alt_m)
            take_roi(ctx.mount, face, (n, e, item.z))  # the item's altitude: above home
        return True

"""DO_SET_ROI_LOCATION, DO_SET_ROI and DO_SET_ROI_NONE in a mission: the nose turns to the item's
location and stays on it through the legs that follow (ArduCopter's do_roi); a location of all
zeros (ROI_NONE always has one) clears it. DO_SET_ROI's mode (param 1) is not read: ArduCopter
points at the location whatever it says."""
from __future__ import annotations

from typing import TYPE_CHECKING

from . import AutoItem

if TYPE_CHECKING:
    from ...mission.store import MissionItem
    from ..auto import Auto
    from ..context import ModeContext


class SetRoi(AutoItem):
    def start(self, auto: Auto, ctx: ModeContext, index: int, item: MissionItem) -> bool:
        if item.x == 0 and item.y == 0 and item.z == 0:
            auto.set_roi(ctx, None)
        else:
            n, e, _ = ctx.ned_of(item.x * 1e-7, item.y * 1e-7, ctx.origin_alt_m)
            auto.set_roi(ctx, (n, e))
        return True

"""DO_FENCE_ENABLE in a mission: AP_Mission switches every configured fence on (param 1 = 1) or
off (0), or the floor off (2), and says which ("Max Alt, Circle and Polygon fences enabled");
ArduCopter's AUTO then reports the item reached."""
from __future__ import annotations

from typing import TYPE_CHECKING

from ...c_casts import as_uint16
from . import AutoItem

if TYPE_CHECKING:
    from ...mission.store import MissionItem
    from ..auto import Auto
    from ..context import ModeContext


class FenceEnable(AutoItem):
    def start(self, auto: Auto, ctx: ModeContext, index: int, item: MissionItem) -> bool:
        ctx.fence_enable_item(as_uint16(item.p1))  # AP_Mission's p1: param 1 as a uint16
        return True

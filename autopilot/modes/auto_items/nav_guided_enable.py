"""NAV_GUIDED_ENABLE: param 1 > 0 hands navigation to a companion computer: ArduCopter's AUTO runs
GUIDED inside itself (guided_inside.py) and takes the companion's targets; the item ends when the
limits of the last DO_GUIDED_LIMITS (guided_limits.py) are broken, counted from the item's start,
and with none set it never does. Param 1 0 (off) ends it at once."""
from __future__ import annotations

from typing import TYPE_CHECKING

from ...c_casts import as_uint16
from ..context import ModeContext
from .guided_inside import GuidedInside

if TYPE_CHECKING:
    from ...mission.store import MissionItem
    from ..auto import Auto


class NavGuidedEnable(GuidedInside):
    _on: bool
    _auto: Auto

    def start(self, auto: Auto, ctx: ModeContext, index: int, item: MissionItem) -> bool:
        self._on = as_uint16(item.p1) > 0  # AP_Mission keeps param 1 as a uint16
        self._auto = auto
        return super().start(auto, ctx, index, item)

    def done(self, ctx: ModeContext) -> bool:
        return not self._on or self._auto.guided_limits.broken(ctx, self.start_s, self.start_ne)

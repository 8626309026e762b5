"""NAV_SCRIPT_TIME: ArduCopter hands the vehicle to a Lua script (param 1 its command, 2 the
timeout [s], 3..4 and x, y its arguments) and holds it as GUIDED's start does, until the script
says it is done or the timeout passes. Firefly runs no scripts: the timeout ends it; with no
timeout (0) the mission waits here, as ArduCopter's does with no script to answer. Meanwhile AUTO
is GUIDED (guided_inside.py): a companion's targets steer it, as a script's would."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ..context import ModeContext
from .guided_inside import GuidedInside

if TYPE_CHECKING:
    from ...mission.store import MissionItem
    from ..auto import Auto


class NavScriptTime(GuidedInside):
    _timeout_s: int

    def start(self, auto: Auto, ctx: ModeContext, index: int, item: MissionItem) -> bool:
        super().start(auto, ctx, index, item)
        # AP_Mission stores the timeout as a uint8 of whole seconds
        self._timeout_s = int(item.p2) & 0xFF if math.isfinite(item.p2) else 0
        return True

    def done(self, ctx: ModeContext) -> bool:
        return self._timeout_s > 0 and ctx.time_s - self.start_s > self._timeout_s

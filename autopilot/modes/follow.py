"""FOLLOW: ArduCopter refuses it until FOLL_ENABLE is 1 (saying so). Enabled, it is entered in
every state; with no lead vehicle heard it holds where it is (zero velocity, height held), which
is what Firefly flies. Following a lead vehicle (FOLL_SYSID's positions) is not built yet."""
from __future__ import annotations

from ..results import Severity
from .context import ModeContext
from .loiter import Brake
from .numbers import ModeNumber


class Follow(Brake):
    number = ModeNumber.FOLLOW

    def enter(self, ctx: ModeContext) -> str | None:
        if not ctx.params["FOLL_ENABLE"]:
            ctx.notify("Set FOLL_ENABLE = 1", Severity.WARNING)
            return "init failed"
        return super().enter(ctx)

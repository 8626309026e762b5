"""SYSTEMID: ArduCopter's system identification, which shakes one axis with a frequency sweep.
Entered as ArduCopter's is: SID_AXIS set, flying (armed, auto-armed, off the ground), and for
axes 1-13 from a manual-throttle mode, for 14-19 from LOITER; each refusal says why. Once in,
Firefly flies it as STABILIZE (the sweep itself is not injected)."""
from __future__ import annotations

from ..results import Severity
from .context import ModeContext
from .manual import Stabilize
from .numbers import ModeNumber

POSITION_AXES = range(14, 20)  # the position-controller axes: entered from LOITER only
MANUAL_THROTTLE_MODES = (ModeNumber.STABILIZE, ModeNumber.ACRO)


class SystemId(Stabilize):
    number = ModeNumber.SYSTEMID
    allows_arming = False

    def enter(self, ctx: ModeContext) -> str | None:
        axis = int(ctx.params["SID_AXIS"])
        refusal = None
        if axis == 0:
            refusal = "No axis selected, SID_AXIS = 0"
        elif not ctx.armed or not ctx.auto_armed or ctx.landed:
            refusal = "Aircraft must be flying"
        elif axis in POSITION_AXES:
            if ctx.mode_number != ModeNumber.LOITER:
                refusal = "Axis requires switch from Loiter"
        elif ctx.mode_number not in MANUAL_THROTTLE_MODES:
            refusal = "Axis requires manual throttle"
        if refusal is not None:
            ctx.notify(refusal, Severity.WARNING)
            return "init failed"
        ctx.notify(f"SystemID Starting: axis={axis}")
        return None

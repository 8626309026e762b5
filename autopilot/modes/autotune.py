"""AUTOTUNE: entered, as ArduCopter's, only in flight (armed, auto-armed, off the ground) from
STABILIZE, ALT_HOLD, LOITER or POSHOLD, with the throttle stick off the bottom; anything else is
"init failed" (ArduCopter SITL's receiver holds the throttle at the bottom, so a ground station
alone never gets in). Once in, Firefly holds as the mode it came from would with the sticks
centred (position too, from LOITER or POSHOLD); the tuning twitches themselves are not flown.
"""
from __future__ import annotations

from .base import Mode, Setpoint
from .context import ModeContext
from .loiter import Loiter
from .manual import AltHold
from .numbers import ModeNumber

TUNES_FROM = (ModeNumber.STABILIZE, ModeNumber.ALT_HOLD, ModeNumber.LOITER, ModeNumber.POSHOLD)
HOLDS_POSITION_FROM = (ModeNumber.LOITER, ModeNumber.POSHOLD)


class AutoTune(Mode):
    number = ModeNumber.AUTOTUNE

    def __init__(self) -> None:
        self._hold: Mode = AltHold()

    def enter(self, ctx: ModeContext) -> str | None:
        if ctx.mode_number not in TUNES_FROM or ctx.pilot.throttle <= 0.0:
            return "init failed"
        if not ctx.armed or not ctx.auto_armed or ctx.landed:
            return "init failed"
        self._hold = Loiter() if ctx.mode_number in HOLDS_POSITION_FROM else AltHold()
        self._hold.enter(ctx)
        ctx.notify("AutoTune: Started")
        return None

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        self._hold.update(ctx, sp, dt)

    def exit(self, ctx: ModeContext) -> None:
        ctx.notify("AutoTune: Stopped")

    def controls_position(self, ctx: ModeContext) -> bool:
        return self._hold.controls_position(ctx)

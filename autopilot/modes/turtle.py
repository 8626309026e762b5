"""TURTLE: flips a crashed, upside-down vehicle back by running motors in reverse, which needs
DShot ESCs. ArduCopter refuses it ("init failed") when armed or with no DShot ESC type
(SERVO_DSHOT_ESC 0, its SITL's default), and Firefly's simulated motors cannot reverse: it is
refused in every state."""
from __future__ import annotations

from .base import Mode, Setpoint
from .context import ModeContext
from .numbers import ModeNumber


class Turtle(Mode):
    number = ModeNumber.TURTLE
    manual_throttle = True

    def enter(self, ctx: ModeContext) -> str | None:
        return "init failed"

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        raise AssertionError("TURTLE is never entered")

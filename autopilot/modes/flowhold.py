"""FLOWHOLD: holds position by optical flow. ArduCopter refuses it ("init failed") unless an
optical flow sensor is enabled (FLOW_TYPE) and healthy; Firefly's sim has no such sensor, so
it is refused in every state, as ArduCopter SITL refuses it with FLOW_TYPE 0."""
from __future__ import annotations

from .base import Mode, Setpoint
from .context import ModeContext
from .numbers import ModeNumber


class FlowHold(Mode):
    number = ModeNumber.FLOWHOLD
    allows_arming = True

    def enter(self, ctx: ModeContext) -> str | None:
        return "init failed"  # no flow sensor to be healthy, whatever FLOW_TYPE says

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        raise AssertionError("FLOWHOLD is never entered")

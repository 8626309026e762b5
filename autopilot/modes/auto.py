"""AUTO: flies the stored mission. The mission engine arrives with the mission protocol; until
then entering AUTO is refused with a reason the ground station shows."""
from __future__ import annotations

from .base import Mode, Setpoint


class Auto(Mode):
    number, name = 3, "AUTO"
    requires_position = True

    def enter(self, ctx) -> str | None:
        return "no mission engine yet"

    def update(self, ctx, sp: Setpoint, dt: float) -> None:  # pragma: no cover - never entered
        sp.clear()

"""Loop rates, as integer ratios of the physics rate, checked once (ArduCopter's scheduler idea)."""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class LoopRates:
    physics_hz: int = 400
    attitude_hz: int = 400  # rate + angle loops, U2..U4
    position_hz: int = 100  # position/altitude loops, flight-mode update, land detector

    def ratio(self, loop_hz: int) -> int:
        return self.physics_hz // loop_hz

    def check(self) -> None:
        for name in ("attitude_hz", "position_hz"):
            hz = getattr(self, name)
            if hz <= 0 or self.physics_hz % hz:
                raise ValueError(f"{name}={hz} must divide physics_hz={self.physics_hz}")
        if self.position_hz > self.attitude_hz:
            raise ValueError("position_hz must not exceed attitude_hz")

"""Loop rates, as integer ratios of the physics rate, checked once (ArduCopter's scheduler idea).

The control cascade (position -> attitude -> rate -> allocation) runs at physics rate by default;
only the flight mode, which turns commands into setpoints, and the land detector run slower.
"""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class LoopRates:
    physics_hz: int = 400
    attitude_hz: int = 400  # rate + angle loops, U2..U4
    mode_hz: int = 100  # flight-mode update (setpoints), land detector, failsafes at a tenth of it
    position_hz: int = 0  # position/altitude loops, U1 and lean targets; 0 = with the attitude loops

    def __post_init__(self):
        if self.position_hz == 0:
            object.__setattr__(self, "position_hz", self.attitude_hz)

    def ratio(self, loop_hz: int) -> int:
        return self.physics_hz // loop_hz

    def check(self) -> None:
        for name in ("attitude_hz", "position_hz", "mode_hz"):
            hz = getattr(self, name)
            if hz <= 0 or self.physics_hz % hz:
                raise ValueError(f"{name}={hz} must divide physics_hz={self.physics_hz}")
        if self.position_hz > self.attitude_hz:
            raise ValueError("position_hz must not exceed attitude_hz")
        if self.mode_hz > self.position_hz:
            raise ValueError("mode_hz must not exceed position_hz")

"""Pilot stick input from MANUAL_CONTROL or RC_CHANNELS_OVERRIDE, normalised.

roll, pitch, yaw in -1..1 (pitch positive = nose down / forward), throttle 0..1. When no input
has arrived recently the sticks read centred and, as ArduCopter does without an RC receiver,
the climb-rate stick reads "hold" and the manual throttle reads zero.
"""
from __future__ import annotations

from dataclasses import dataclass

PILOT_TIMEOUT_S = 2.0


@dataclass
class PilotInput:
    roll: float = 0.0
    pitch: float = 0.0
    yaw: float = 0.0
    throttle: float = 0.0
    last_update_s: float = -1e9

    def present(self, now_s: float) -> bool:
        return now_s - self.last_update_s <= PILOT_TIMEOUT_S

    def update(self, roll: float, pitch: float, yaw: float, throttle: float, now_s: float) -> None:
        clip = lambda v, lo, hi: min(max(v, lo), hi)  # noqa: E731
        self.roll, self.pitch, self.yaw = clip(roll, -1, 1), clip(pitch, -1, 1), clip(yaw, -1, 1)
        self.throttle = clip(throttle, 0, 1)
        self.last_update_s = now_s


CENTRED = PilotInput(throttle=0.5)
CENTRED_MANUAL = PilotInput(throttle=0.0)

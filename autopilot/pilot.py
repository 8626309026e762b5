"""The pilot's sticks, normalised, as the flight modes read them (made by autopilot/rc/radio.py
from the receiver and the ground station's overrides).

roll, pitch, yaw in -1..1 (pitch positive = stick forward = nose down), throttle 0..1 past the
throttle channel's dead zone; throttle_mid is where the stick's centre reads (ArduCopter's
get_throttle_mid), the middle of ALT_HOLD's climb-rate dead band. ArduPilot SITL's receiver, with
no transmitter, holds the sticks centred and the throttle closed: CENTRED_MANUAL, which ALT_HOLD
and the other climb-rate modes read as "descend".
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
    throttle_mid: float = 0.5

    def present(self, now_s: float) -> bool:
        return now_s - self.last_update_s <= PILOT_TIMEOUT_S

    def update(self, roll: float, pitch: float, yaw: float, throttle: float, now_s: float) -> None:
        clip = lambda v, lo, hi: min(max(v, lo), hi)  # noqa: E731
        self.roll, self.pitch, self.yaw = clip(roll, -1, 1), clip(pitch, -1, 1), clip(yaw, -1, 1)
        self.throttle = clip(throttle, 0, 1)
        self.last_update_s = now_s


CENTRED = PilotInput(throttle=0.5)  # sticks centred, throttle at mid: hold (tests, scripted sticks)
CENTRED_MANUAL = PilotInput(throttle=0.0)  # SITL's receiver at rest

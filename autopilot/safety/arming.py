"""Arming: ArduCopter's pre-arm checks as a table, the rules that refuse an ARM, and the state
that arming starts (armed, and ArduCopter's auto_armed flag).

The checks read the vehicle through its public facade (estimate, params, home, failsafes); each
returns the words ArduCopter puts after "PreArm: ", or None when it passes.
"""
from __future__ import annotations

import math

from ..modes.numbers import ModeNumber

FORCE_ARM_MAGIC = 2989  # COMPONENT_ARM_DISARM param2 that skips the checks (ArduPilot's)
FORCE_DISARM_MAGIC = 21196  # ... and that disarms even in flight
THROTTLE_ARM_MAX = 0.1  # manual-throttle modes refuse to arm with the stick above this


def _need_3d_fix(v):
    return None if v.has_position() else "Need 3D Fix"


def _gps_glitching(v):
    return "GPS glitching" if v.failsafes.ekf.gps_glitching else None


def _waiting_for_home(v):
    return "Waiting for home" if v.home_ned is None else None


def _leaning(v):
    roll, pitch, _ = v.attitude
    return "Leaning" if max(abs(roll), abs(pitch)) > math.radians(v.params["ANGLE_MAX"] / 100.0) else None


def _battery_low(v):
    low = v.params["BATT_LOW_VOLT"]
    return "Battery below minimum arming voltage" if low > 0 and v.estimate.battery.voltage_v < low else None


PREARM_CHECKS = (_need_3d_fix, _gps_glitching, _waiting_for_home, _leaning, _battery_low)


def prearm_failure(v) -> str | None:
    """The first failing pre-arm check, or None (all pass, or ARMING_CHECK is 0)."""
    if v.params["ARMING_CHECK"] == 0:
        return None
    for check in PREARM_CHECKS:
        reason = check(v)
        if reason is not None:
            return reason
    return None


def arm_refusal(v, force: bool) -> str | None:
    """The STATUSTEXT that refuses an ARM in the vehicle's state, or None to arm."""
    if v.mode.number == ModeNumber.AUTO and not v.mission_progress.items():
        return "Arm: Mode requires mission"  # ArduCopter's first word on arming in an empty AUTO
    if not v.mode.allows_arming:
        return f"Arm: {v.mode.name} mode not armable"
    if force:
        return None
    reason = prearm_failure(v)
    if reason is not None:
        return f"PreArm: {reason}"
    if v.mode.manual_throttle and v.pilot.throttle > THROTTLE_ARM_MAX:
        return "Arm: Throttle too high"
    return None


class Arming:
    """Whether the motors are armed, and ArduCopter's auto_armed: AUTO may start its
    mission from the ground (set by MISSION_START while armed and by a takeoff; cleared on disarm)."""

    def __init__(self):
        self.armed = False
        self.auto_armed = False

    def arm(self) -> None:
        self.armed = True

    def disarm(self) -> None:
        self.armed = False
        self.auto_armed = False

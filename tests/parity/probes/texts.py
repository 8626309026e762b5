"""What a vehicle said, reduced to what a client's logic would look at: background chatter that
comes and goes with timing (EKF lane messages, GPS detection, pre-arm reminders repeated every
30 s) is dropped, repeats are folded, and the rest kept in order."""
from __future__ import annotations

import re

BACKGROUND = [re.compile(p) for p in (
    r"^EKF\d", r"^AHRS:", r"^GPS \d", r"^u-blox", r"^Field Elevation", r"^Barometer",
    r"^PreArm: ", r"^ArduCopter V", r"^Frame: ", r"^RCOut:", r"^IMU\d", r"^Param space",
    r"^fmuv", r"^Loaded", r"^Ready to FLY", r"^Init ",
    r"^SIM ",  # the reference simulator's own remarks (ground contact), not the autopilot's
    r"^EKF variance$",  # said when its estimate degrades after GPS loss: timing, not a reply
    r"^[0-9a-f]{32}$",  # the board id the reference prints beside its banner: differs per instance
)]


def said(texts: list[str]) -> list[str]:
    kept: list[str] = []
    for text in texts:
        if any(p.search(text) for p in BACKGROUND):
            continue
        if not kept or kept[-1] != text:
            kept.append(text)
    return kept

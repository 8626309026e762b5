"""The heading ArduCopter keeps when a mode flies a thrust vector and "holds" its heading by
handing back its attitude target's Euler yaw (ModeFollow with no heading to turn to): the wanted
attitude is rebuilt each loop as the tilt times that yaw, and a tilt about an axis the heading is
not on moves the Euler yaw toward that axis: tan(yaw - axis) shrinks by cos(tilt). The target
follows the wanted attitude with ATC_INPUT_TC's time constant, so the nose drifts at that step
over ATC_INPUT_TC until the vehicle leans purely sideways (its tilt axis ahead). Measured on
ArduCopter 4.7 SITL in FOLLOW with FOLL_YAW_BEHAVE 0: 45 degrees to 10 within 5 s of flying east.
"""
from __future__ import annotations

import math

INPUT_TC_DEFAULT_S = 0.15  # ATC_INPUT_TC
LEVEL_COS = 0.99999  # cos of the tilt below which nothing moves (the axis is undefined when level)


def tilted_heading(attitude: tuple[float, float, float], held: float, dt: float,
                   input_tc_s: float = INPUT_TC_DEFAULT_S) -> float:
    """The heading target `held` [rad] after dt of that rebuilding, the vehicle leaning at
    `attitude` (roll, pitch, yaw) [rad]."""
    roll, pitch, yaw = attitude
    cos_tilt = math.cos(roll) * math.cos(pitch)
    if cos_tilt > LEVEL_COS:
        return held
    # The thrust direction's horizontal part (body up in the earth frame, north and east)
    sr, cr, sp, sy, cy = math.sin(roll), math.cos(roll), math.sin(pitch), math.sin(yaw), math.cos(yaw)
    tn = -(cy * sp * cr + sy * sr)
    te = -(sy * sp * cr - cy * sr)
    axis = math.atan2(-tn, te)  # up x thrust: the horizontal axis the tilt turns about
    off = math.remainder(held - axis, 2.0 * math.pi)
    step = math.atan2(math.sin(off) * cos_tilt, math.cos(off)) - off  # one rebuilding's change
    return math.remainder(held + step * min(1.0, dt / max(input_tc_s, dt)), 2.0 * math.pi)

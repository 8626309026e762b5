"""ArduCopter's motor throttle (0..1, MOT_THST_HOVER hovers) and Firefly's throttle stick (0..1,
mid-stick hovers: the setpoint's `throttle`), each to the other.

Modes that add to the throttle as ArduCopter's do (FLIP's +0.2 while rolling, DRIFT's climb
assist, THROW's 0.5 while uprighting) reckon in motor throttle; both scales are piecewise linear
through zero, hover and full, as Firefly's thrust curve (control/position.py thrust_from_stick).
"""
from __future__ import annotations

from ..params import ParamStore


def hover_throttle(params: ParamStore) -> float:
    return min(max(params["MOT_THST_HOVER"], 0.05), 0.95)


def motor_from_stick(stick: float, params: ParamStore) -> float:
    """ArduCopter's get_pilot_desired_throttle: mid-stick is the hover throttle."""
    hover = hover_throttle(params)
    stick = min(max(stick, 0.0), 1.0)
    if stick <= 0.5:
        return stick * 2.0 * hover
    return hover + (stick - 0.5) * 2.0 * (1.0 - hover)


def stick_from_motor(throttle: float, params: ParamStore) -> float:
    hover = hover_throttle(params)
    throttle = min(max(throttle, 0.0), 1.0)
    if throttle <= hover:
        return 0.5 * throttle / hover
    return 0.5 + 0.5 * (throttle - hover) / (1.0 - hover)

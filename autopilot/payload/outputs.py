"""The outputs a payload drives by function, as ArduPilot's SRV_Channel and AP_Relay give them: every
output whose SERVOn_FUNCTION is the payload's, every relay whose RELAYn_FUNCTION is (and that has a
pin). Read afresh each time, so that a function assigned while the vehicle runs takes effect.

A range output (a sprayer's pump) goes from SERVOn_MIN at 0 to SERVOn_MAX at 1, the other way
round when SERVOn_REVERSED, cut to whole microseconds; its "minimum" is SERVOn_MIN (MAX when
reversed).
"""
from __future__ import annotations

from collections.abc import Callable

from ..params import ParamStore

CHANNELS, RELAYS = 16, 6


def outputs_of(params: ParamStore, function: int) -> tuple[int, ...]:
    """The outputs (1-based) whose SERVOn_FUNCTION is `function`."""
    return tuple(n for n in range(1, CHANNELS + 1) if int(params.get(f"SERVO{n}_FUNCTION", 0)) == function)


def relays_of(params: ParamStore, function: int) -> tuple[int, ...]:
    """The relays (0-based) whose RELAYn_FUNCTION is `function` and that have a pin."""
    return tuple(r for r in range(RELAYS) if int(params.get(f"RELAY{r + 1}_FUNCTION", 0)) == function
                 and int(params.get(f"RELAY{r + 1}_PIN", -1)) != -1)


def _reversed(params: ParamStore, output: int) -> bool:
    return bool(params.get(f"SERVO{output}_REVERSED", 0))


def range_pwm(params: ParamStore, output: int, fraction: float) -> int:
    """The PWM [us] for `fraction` (0..1) of the output's range."""
    low, high = int(params[f"SERVO{output}_MIN"]), int(params[f"SERVO{output}_MAX"])
    share = min(max(fraction, 0.0), 1.0)
    if _reversed(params, output):
        share = 1.0 - share
    return low + int(share * (high - low))


def minimum_pwm(params: ParamStore, output: int) -> int:
    """The output's minimum [us]: SERVOn_MIN, or SERVOn_MAX when reversed."""
    return int(params[f"SERVO{output}_MAX" if _reversed(params, output) else f"SERVO{output}_MIN"])


class Constrain:
    """ArduPilot's constrain_float for what a payload puts out: a NaN becomes the middle of the
    range, and its internal error (the vehicle's constraining_nan, `on_nan`)."""

    def __init__(self, on_nan: Callable[[], None]):
        self.on_nan = on_nan

    def __call__(self, v: float, low: float, high: float) -> float:
        if v != v:
            self.on_nan()
            return (low + high) / 2
        return low if v < low else high if v > high else v

"""One RC channel's calibration and what its PWM means, as ArduPilot's RC_Channel computes it."""
from __future__ import annotations

from dataclasses import dataclass

PWM_LOWEST, PWM_HIGHEST = 800, 2200  # RC_MIN_LIMIT_PWM / RC_MAX_LIMIT_PWM: outside, a switch reads nothing
SWITCH_LOW_BELOW, SWITCH_HIGH_ABOVE = 1200, 1800  # AUX_SWITCH_PWM_TRIGGER_LOW / _HIGH
LOW, MIDDLE, HIGH = 0, 1, 2  # an aux switch's positions (AuxSwitchPos)
# The 6-position flight-mode switch: position k while the PWM is below the k-th edge (read_6pos_switch)
MODE_SWITCH_EDGES = (1231, 1361, 1491, 1621, 1750)


@dataclass(frozen=True)
class Calibration:
    min_us: int = 1000
    trim_us: int = 1500
    max_us: int = 2000
    dead_zone_us: int = 0
    reversed: bool = False

    @classmethod
    def of(cls, params, channel: int) -> Calibration:
        """RCn_* of channel n (1-based)."""
        p = f"RC{channel}_"
        return cls(int(params[p + "MIN"]), int(params[p + "TRIM"]), int(params[p + "MAX"]),
                   int(params[p + "DZ"]), bool(params[p + "REVERSED"]))


def stick(pwm: int, cal: Calibration) -> float:
    """A centred stick in -1..1 (pwm_to_angle_dz_trim over its full scale): the dead zone around
    the trim reads 0, the PWM is held within MIN..MAX."""
    high, low = cal.trim_us + cal.dead_zone_us, cal.trim_us - cal.dead_zone_us
    sign = -1.0 if cal.reversed else 1.0
    r = min(max(pwm, cal.min_us), cal.max_us)
    if r > high and cal.max_us != high:
        return sign * (r - high) / (cal.max_us - high)
    if r < low and low != cal.min_us:
        return sign * (r - low) / (low - cal.min_us)
    return 0.0


def throttle(pwm: int, cal: Calibration) -> float:
    """A throttle in 0..1 (pwm_to_range_dz): the dead zone sits at the bottom."""
    r = min(max(pwm, cal.min_us), cal.max_us)
    if cal.reversed:
        r = cal.max_us - (r - cal.min_us)
    bottom = cal.min_us + cal.dead_zone_us
    if r > bottom and cal.max_us != bottom:
        return (r - bottom) / (cal.max_us - bottom)
    return 0.0


def throttle_mid(cal: Calibration) -> float:
    """Where a throttle stick's centre reads (get_control_mid, in ArduPilot's whole thousandths)."""
    bottom = cal.min_us + cal.dead_zone_us
    if cal.max_us == bottom:
        return 0.5
    return int(1000 * ((cal.min_us + cal.max_us) // 2 - bottom) / (cal.max_us - bottom)) / 1000.0


def switch_position(pwm: int, reversed_switch: bool = False) -> int | None:
    """LOW, MIDDLE or HIGH of a 3-position switch; None for a PWM no receiver sends."""
    if pwm <= PWM_LOWEST or pwm >= PWM_HIGHEST:
        return None
    if pwm < SWITCH_LOW_BELOW:
        return HIGH if reversed_switch else LOW
    if pwm > SWITCH_HIGH_ABOVE:
        return LOW if reversed_switch else HIGH
    return MIDDLE


def mode_switch_position(pwm: int) -> int | None:
    """0..5 of the flight-mode switch (FLTMODE1..6); None for a PWM no receiver sends."""
    if pwm <= PWM_LOWEST or pwm >= PWM_HIGHEST:
        return None
    return next((k for k, edge in enumerate(MODE_SWITCH_EDGES) if pwm < edge), len(MODE_SWITCH_EDGES))


def stick_pwm(value: float, cal: Calibration) -> int:
    """The PWM a transmitter sends for a stick at `value` (-1..1): stick()'s inverse."""
    sign = -1.0 if cal.reversed else 1.0
    value *= sign
    if value > 0:
        high = cal.trim_us + cal.dead_zone_us
        return round(high + value * (cal.max_us - high))
    if value < 0:
        low = cal.trim_us - cal.dead_zone_us
        return round(low + value * (low - cal.min_us))
    return cal.trim_us


def throttle_pwm(value: float, cal: Calibration) -> int:
    """The PWM a transmitter sends for a throttle at `value` (0..1): throttle()'s inverse."""
    bottom = cal.min_us + cal.dead_zone_us
    pwm = round(bottom + value * (cal.max_us - bottom)) if value > 0 else cal.min_us
    return cal.max_us - (pwm - cal.min_us) if cal.reversed else pwm

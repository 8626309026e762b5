"""The winch, as ArduCopter runs AP_Winch with its PWM backend (WINCH_TYPE 1), measured on its SITL.

The winch is made at boot from WINCH_TYPE (1 PWM; 2, Daiwa's serial winch, is made too and takes
commands, but is not modelled: here it is never healthy, as it would be with no winch talking on
its serial port; not measured on ArduCopter). Made, it takes DO_WINCH: relax
(no output), release a length relative to the line out now (position control), or run at a rate
(rate control, +ve lowers the line). It is healthy while some output has SERVOn_FUNCTION 88; then
its 50 Hz update drives that output:

  relaxed   the output at 0 (no pulses) and the rate it remembers for its ramp back at 0;
  position  the rate asked becomes (target - line) x WINCH_POS_P, held to +-WINCH_RATE_MAX;
  rate      the output follows the rate ramped at 2 x WINCH_RATE_MAX per second (at least 0.1),
            scaled -WINCH_RATE_MAX..+WINCH_RATE_MAX to -1000..+1000 of an angle output (SERVOn_TRIM
            at 0, SERVOn_MAX at +1000, SERVOn_MIN at -1000).

There is no sensor: the line is the autopilot's own estimate, the rate asked (not the ramped one)
integrated over each update, as AP_Winch_PWM assumes the winch runs exactly as asked. ArduCopter's
SITL has no winch in its simulation either: nothing hangs below the vehicle.

A channel with RCn_OPTION 45 (WinchControl; the first such) is the pilot's: its dead zone defaults
to 30 us once the winch is made (RCn_DZ reads 30 unless set), and a move of more than the dead
zone from where the stick was last read hands the winch to it: the rate is then the stick's
share of its travel beyond the dead zone times WINCH_RATE_MAX, until a command takes over (and
the stick moves past the dead zone again). With the radio lost the stick's rate is 0. A channel
given back to a receiver that sends nothing reads 0 us: past the dead zone, full speed in.

WINCH_OPTIONS (default 7): bit 0 starts it relaxed (otherwise at rate 0), bit 1 says each length
asked ("Winch: lowering  2.0m to  2.0m"); bit 2 is the Daiwa's. Rates are held to
+-max(WINCH_RATE_MAX, 0) when asked; a NaN rate or target makes a rate of 0 (ArduPilot's
constrain_float gives the middle of its range for NaN, and counts an internal error).
"""
from __future__ import annotations

from collections.abc import Callable

from ..c_casts import float32
from ..params import ParamStore
from ..results import Severity
from .outputs import Constrain, outputs_of

WINCH_FUNCTION = 88  # SERVOn_FUNCTION: winch
PWM_TYPE, DAIWA_TYPE = 1, 2  # WINCH_TYPE
UPDATE_S = 0.02  # AP_Winch::update's 50 Hz
SCALED_MAX = 1000.0  # the angle output's range (SRV_Channels::set_angle(k_winch, 1000))
SPIN_FREELY_ON_STARTUP, VERBOSE = 1, 2  # WINCH_OPTIONS bits
RELAXED, POSITION, RATE, RATE_FROM_RC = 0, 1, 2, 3  # AP_Winch's ControlMode
WINCH_CONTROL = 45  # RCn_OPTION: the winch's stick
STICK_DEAD_ZONE_US = 30  # the default AP_Winch gives that channel's RCn_DZ
CHANNELS = 16


class Winch:
    def __init__(self, params: ParamStore, servo_pwm: list[int], notify: Callable[[str, int], None],
                 constraining_nan: Callable[[], None], radio: Callable[[], tuple[list[int], bool]]):
        self.params = params
        self._servo_pwm = servo_pwm  # the outputs it drives (servo_relay.py's)
        self._notify = notify
        self._constrain = Constrain(constraining_nan)  # a NaN held to a range: ArduPilot's internal error
        self._radio = radio  # (every channel's PWM as last read, whether the radio is to be trusted)
        self._stick_was_us: int | None = None  # the stick where last read (AP_Winch's previous_radio_in)
        self.kind = int(params["WINCH_TYPE"]) if int(params["WINCH_TYPE"]) in (PWM_TYPE, DAIWA_TYPE) else 0
        self.mode = RELAXED
        self.length_desired_m = 0.0
        self.rate_desired_m_s = 0.0
        self.line_m = 0.0  # the line out, as the autopilot reckons it
        self._previous_rate = 0.0  # the ramped rate last output
        self._updated_ms: int | None = None
        self.next_update_s = 0.0
        if self.kind:
            stick = self._stick_channel()
            if stick is not None:
                params.set_default(f"RC{stick}_DZ", STICK_DEAD_ZONE_US)
            if self._option(SPIN_FREELY_ON_STARTUP):
                self.relax()
            else:
                self.set_rate(0.0)

    @property
    def fitted(self) -> bool:
        """Made at boot (AP_Winch::enabled: a type and a backend)."""
        return self.kind != 0 and int(self.params["WINCH_TYPE"]) > 0

    @property
    def healthy(self) -> bool:
        return self.kind == PWM_TYPE and bool(outputs_of(self.params, WINCH_FUNCTION))

    def prearm_failure(self) -> str | None:
        """AP_Winch::pre_arm_check: with WINCH_TYPE set (now, made or not), it must be healthy."""
        if int(self.params["WINCH_TYPE"]) == 0 or self.healthy:
            return None
        return "winch unhealthy"

    def _option(self, bit: int) -> bool:
        return bool(int(self.params["WINCH_OPTIONS"]) & bit)

    def _rate_max(self) -> float:
        return float(self.params["WINCH_RATE_MAX"])

    # ----- what DO_WINCH, a mission's DO_WINCH and the aux switch ask --------------------------
    def relax(self) -> None:
        self.mode = RELAXED

    def release_length(self, length_m: float) -> None:
        """Let out `length_m` more (negative: wind it in) from the line out now."""
        if not self.kind:
            return
        self.length_desired_m = float32(self.line_m + length_m)
        self.mode = POSITION
        if self._option(VERBOSE):
            way = "raising" if length_m < 0 else "lowering"
            self._notify(f"Winch: {way} {abs(length_m):4.1f}m to {self.length_desired_m:4.1f}m", Severity.INFO)

    def set_rate(self, rate_m_s: float) -> None:
        """Run at `rate_m_s` (+ve lowers), held to the maximum rate."""
        top = max(self._rate_max(), 0.0)
        self.rate_desired_m_s = float32(self._constrain(rate_m_s, -top, top))
        self.mode = RATE

    # ----- the pilot's stick (AP_Winch_Backend::read_pilot_desired_rate) -----------------------
    def _stick_channel(self) -> int | None:
        return next((n for n in range(1, CHANNELS + 1) if int(self.params.get(f"RC{n}_OPTION", 0)) == WINCH_CONTROL),
                    None)

    def _read_stick(self) -> None:
        n = self._stick_channel()
        if n is None:
            return
        channels, valid = self._radio()
        if not valid and self.mode == RATE_FROM_RC:
            self.rate_desired_m_s = 0.0
            return
        pwm = int(channels[n - 1])
        if self._stick_was_us is None:
            self._stick_was_us = pwm
        dead_zone = int(self.params[f"RC{n}_DZ"])
        if self.mode != RATE_FROM_RC and abs(pwm - self._stick_was_us) > dead_zone:
            self.mode = RATE_FROM_RC
        if self.mode == RATE_FROM_RC:
            self.rate_desired_m_s = float32(_stick_share(self.params, n, pwm, dead_zone) * self._rate_max())
            self._stick_was_us = pwm

    # ----- the 50 Hz update ------------------------------------------------------------------
    def update(self, now_s: float) -> None:
        self.next_update_s = now_s + UPDATE_S
        if not self.fitted or not self.healthy:
            return
        self._read_stick()
        now_ms = int(now_s * 1000.0 + 1e-6)
        dt = 0.0 if self._updated_ms is None else (now_ms - self._updated_ms) * 0.001
        if dt > 1.0:
            dt = 0.0
        self._updated_ms = now_ms
        outputs = outputs_of(self.params, WINCH_FUNCTION)
        if self.mode == RELAXED:
            for output in outputs:
                self._servo_pwm[output - 1] = 0
            self._previous_rate = 0.0
            return
        top = self._rate_max()
        if self.mode == POSITION:
            error = self.length_desired_m - self.line_m
            self.rate_desired_m_s = float32(self._constrain(error * self.params["WINCH_POS_P"], -top, top))
        step = max(top * 2.0, 0.1) * dt
        low, high = self._previous_rate - step, self._previous_rate + step
        ramped = self._constrain(self.rate_desired_m_s, low, high)
        self._previous_rate = ramped
        scaled = _interpolate(-SCALED_MAX, SCALED_MAX, ramped, -top, top)
        for output in outputs:
            self._servo_pwm[output - 1] = _angle_pwm(self.params, output, scaled)
        self.line_m = float32(self.line_m + self.rate_desired_m_s * dt)


def _stick_share(params: ParamStore, n: int, pwm: int, dead_zone: int) -> float:
    """RC_Channel::norm_input_dz: the stick's share (-1..1) of its travel beyond the dead zone
    around RCn_TRIM, the other way round when RCn_REVERSED."""
    trim, low, high = (int(params[f"RC{n}_{name}"]) for name in ("TRIM", "MIN", "MAX"))
    sign = -1 if params.get(f"RC{n}_REVERSED", 0) else 1
    below, above = trim - dead_zone, trim + dead_zone
    if pwm < below and below > low:
        share = sign * (pwm - below) / (below - low)
    elif pwm > above and high > above:
        share = sign * (pwm - above) / (high - above)
    else:
        share = 0.0
    return min(max(share, -1.0), 1.0)


def _interpolate(out_low: float, out_high: float, value: float, low: float, high: float) -> float:
    """AP_Math's linear_interpolate: `value` from low..high onto out_low..out_high, held at the ends."""
    if value <= low:
        return out_low
    if value >= high:
        return out_high
    return out_low + (value - low) / (high - low) * (out_high - out_low)


def _angle_pwm(params: ParamStore, output: int, scaled: float) -> int:
    """SRV_Channel::pwm_from_angle for a range of +-1000: TRIM at 0, MAX and MIN at the ends."""
    trim, low, high = (int(params[f"SERVO{output}_{name}"]) for name in ("TRIM", "MIN", "MAX"))
    if params.get(f"SERVO{output}_REVERSED", 0):
        scaled = -scaled
    scaled = min(max(scaled, -SCALED_MAX), SCALED_MAX)
    if scaled > 0:
        return trim + int(scaled * (high - trim) / SCALED_MAX)
    return trim - int(-scaled * (trim - low) / SCALED_MAX)

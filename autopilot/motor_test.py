"""A ground station's motor test (MAV_CMD_DO_MOTOR_TEST), as ArduCopter runs one: the motors
armed on the ground, one motor (or a run of them in the test order) at a throttle given as a
percentage, a PWM or the pilot's throttle stick, for a timeout, then disarmed.

Sans-IO and in sim time: the vehicle checks whether a test may start and says what it says;
this keeps the test's state and gives, at each update, the PWM of each output (motor_outputs.py's
numbering) or the word that the test is over. Measured on ArduCopter SITL (tests/parity/probes/
motor_test.py): the test order of the quad runs clockwise from the front, outputs 3, 1, 4, 2;
a throttle that makes a PWM outside 800-2200 (a percentage over 100, an unknown throttle type)
ends the test at its first update; with a count, each motor runs for the timeout and all rest
for half of it before the next; a second command while a test runs takes over its motor,
throttle and timeout without starting anew.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .c_casts import as_uint32, float32

PERCENT, PWM, PILOT, COMPASS_CAL = 0, 1, 2, 3  # MOTOR_TEST_THROTTLE_TYPE
TIMEOUT_MAX_S = 600.0  # MOTOR_TEST_TIMEOUT_SEC
PWM_LIMITS = (800, 2200)  # RC_Channel's RC_MIN_LIMIT_PWM, RC_MAX_LIMIT_PWM
DELAY_TEXT_EVERY_S = 5.0  # ArduPilot's blocking-delay callback says "Initialising ArduPilot" this often
OUTPUT_OF_TEST_SEQ = {1: 3, 2: 1, 3: 4, 4: 2}  # QUAD PLUS's testing order -> its output (front, right, back, left)


@dataclass
class Throttle:
    kind: int
    value: float


class MotorTest:
    def __init__(self) -> None:
        self.running = False
        self.seq = 0
        self.count = 0
        self.throttle = Throttle(PERCENT, 0.0)
        self.started_ms = 0
        self.timeout_ms = 0
        self.pwm = [0, 0, 0, 0]  # outputs 1-4 as the test last wrote them (0: never written)

    def start(self, seq: int, kind: int, value: float, timeout_s: float, count: int, now_s: float) -> bool:
        """Take a test's settings (the vehicle has checked it may run); True when this starts a
        test rather than changing the one running."""
        starting = not self.running
        if starting:
            self.running = True
            self.pwm = [0, 0, 0, 0]
        self.started_ms = _ms(now_s)
        # MIN(timeout, 600) in float, times 1000, into a uint32 (NaN compares false: 600 wins)
        capped = timeout_s if timeout_s < TIMEOUT_MAX_S else TIMEOUT_MAX_S
        self.timeout_ms = as_uint32(float32(float32(capped) * 1000.0))
        self.seq = seq & 0xFF
        self.count = (count & 0xFF) or 1
        self.throttle = Throttle(kind & 0xFF, float32(value))
        return starting

    def update(self, now_s: float, pwm_range: tuple[float, float], pilot_throttle_us: int) -> bool:
        """The outputs for now; False when the test is over (the vehicle says so and disarms)."""
        if not self.running:
            return False
        now = _ms(now_s)
        elapsed = (now - self.started_ms) & 0xFFFFFFFF
        if elapsed >= self.timeout_ms:
            if self.count > 1:
                if elapsed < self.timeout_ms * 1.5:
                    self._rest(pwm_range)
                else:
                    self.seq = (self.seq + 1) & 0xFF
                    self.count -= 1
                    self.started_ms = now
                return True
            return self.stop()
        pwm = self._pwm(pwm_range, pilot_throttle_us)
        if pwm is None or not PWM_LIMITS[0] <= pwm <= PWM_LIMITS[1]:
            return self.stop()
        output = OUTPUT_OF_TEST_SEQ.get(self.seq)
        if output is not None:
            self.pwm[output - 1] = pwm
        return True

    def stop(self) -> bool:
        self.running = False
        return False

    def outputs(self, pwm_min: int) -> list[int]:
        """Outputs 1-4 while the test runs: a motor it never wrote rests at the minimum."""
        return [pwm or pwm_min for pwm in self.pwm]

    def _rest(self, pwm_range: tuple[float, float]) -> None:
        self.pwm = [int(pwm_range[0])] * 4

    def _pwm(self, pwm_range: tuple[float, float], pilot_throttle_us: int) -> int | None:
        kind, value = self.throttle.kind, self.throttle.value
        if kind in (PERCENT, COMPASS_CAL):
            if not value <= 100.0:  # NaN too: no PWM, the test ends
                return 0
            low, high = pwm_range
            return _int16(float32(low + (high - low) * value * float32(0.01)))
        if kind == PWM:
            return _int16(value)
        if kind == PILOT:
            return pilot_throttle_us
        return None


def _ms(now_s: float) -> int:
    return int(round(now_s * 1000.0)) & 0xFFFFFFFF


def _int16(value: float) -> int:
    """(int16_t) of a float, as x86 truncates it (NaN and the out of range become -32768)."""
    if not (math.isfinite(value) and -2**31 <= value < 2**31):
        return -32768
    v = int(value) & 0xFFFF
    return v - 0x10000 if v >= 0x8000 else v

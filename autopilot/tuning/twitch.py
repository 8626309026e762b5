"""One twitch, measured as ArduCopter's AC_AutoTune_Multi measures it: a rate step (the Rate D and
Rate P tunes) or an angle step (the Angle P tunes) about one axis, watched until it has shown what
it can (the peak, the bounce back) or runs out of time or room.

Units are ArduCopter's: centidegrees and centidegrees per second, so that its thresholds read
the same here. Angles and rates are signed along the twitch's direction."""
from __future__ import annotations

import math
from enum import Enum

STEP_TIMEOUT_S = 2.0      # AUTOTUNE_TESTING_STEP_TIMEOUT_MS
RISE_FRACTION = 0.6321    # one time constant: a twitch not there by 1/3 of the time left is cut short


class Outcome(Enum):
    RUNNING = 0
    UPDATE_GAINS = 1   # measured: the gains move by the rules
    ABORT = 2          # ran out of room: no verdict, level and try again
    SHRINK = 3         # ABORT, and the next rate steps smaller (the lean limit came too soon)


class Twitch:
    """Feed update() the angle turned since the start [cd, along the twitch] and the body rate
    [cd/s] each tick until it returns something other than RUNNING; then read the peaks."""

    def __init__(self, steps_angle: bool, target_rate: float, target_angle: float, angle_abort: float,
                 aggressiveness: float, rate_start: float, filter_hz: float, start_s: float,
                 test_target: float, accel_offset: float = 0.0):
        self.steps_angle = steps_angle
        self.target_rate, self.target_angle, self.angle_abort = target_rate, target_angle, angle_abort
        self.aggressiveness = aggressiveness
        self.test_target = test_target  # the peak that ends the twitch (rate or angle)
        self.start_s = start_s
        self.timeout_s = STEP_TIMEOUT_S
        self.rc = 1.0 / (2.0 * math.pi * filter_hz)
        self.filtered = rate_start
        self.rate_max = self.rate_min = 0.0
        self.angle_max = self.angle_min = 0.0
        self.accel_offset = accel_offset  # an angle step's starting rate, left out of its acceleration
        self.accel_rate_max = 0.0
        self.accel_max = 0.0  # cd/s/s: the peak rate over the time it took to reach it

    def update(self, angle: float, rate: float, now_s: float, dt: float) -> Outcome:
        self.filtered += dt / (dt + self.rc) * (rate - self.filtered)
        rate = self.filtered
        elapsed = now_s - self.start_s
        accel_rate = rate - self.accel_offset
        if self.accel_rate_max < accel_rate:
            self.accel_rate_max = accel_rate
            self.accel_max = accel_rate / max(elapsed, 1e-3)
        if self.steps_angle:
            return self._angle_step(angle, rate, elapsed)
        outcome = self._rate_step(angle, rate, elapsed)
        return self._out_of_room(angle, rate, outcome)

    def _rate_step(self, angle: float, rate: float, elapsed: float) -> Outcome:
        if rate > self.rate_max:
            self.rate_max = self.rate_min = rate
            self.angle_min = angle
        if rate < self.rate_min and self.rate_max > self.test_target * 0.25:
            self.rate_min = rate
            self.angle_min = angle
        return self._verdict(self.rate_max, self.rate_min, elapsed)

    def _verdict(self, peak: float, low: float, elapsed: float) -> Outcome:
        """Done once past the target, once it has fallen back from its peak by more than the
        aggressiveness, or at the time-out: three times the time to rise 63 % (while below it)."""
        if peak < self.test_target * RISE_FRACTION:
            self.timeout_s = min(elapsed * 3.0, STEP_TIMEOUT_S)
        done = peak > self.test_target or peak - low > peak * self.aggressiveness or elapsed >= self.timeout_s
        return Outcome.UPDATE_GAINS if done else Outcome.RUNNING

    def _out_of_room(self, angle: float, rate: float, outcome: Outcome) -> Outcome:
        """The lean limit reached mid-twitch: a verdict if the bounce back has begun, else the
        step was too big for the room (ArduCopter's twitching_abort_rate)."""
        if angle < self.angle_abort:
            return outcome
        if rate == self.rate_min or self.angle_min > 0.95 * self.angle_abort:
            return Outcome.SHRINK
        return Outcome.UPDATE_GAINS

    def _angle_step(self, angle: float, rate: float, elapsed: float) -> Outcome:
        if angle > self.angle_max:
            self.angle_max = self.angle_min = angle
        if angle < self.angle_min and self.angle_max > self.test_target * 0.25:
            self.angle_min = angle
        if rate > self.rate_max:
            self.rate_max = self.rate_min = rate
        if rate < self.rate_min:
            self.rate_min = rate
        return self._verdict(self.angle_max, self.angle_min, elapsed)

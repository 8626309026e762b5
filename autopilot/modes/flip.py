"""FLIP: a full roll (or pitch) at 400 deg/s, then back to the mode it was entered from.

As ArduCopter's: entered only from ACRO, STABILIZE or ALT_HOLD while flying, with the throttle
open in the manual-throttle modes and the roll stick under 40 degrees' worth; it rolls right
unless the sticks ask for left, forward or back. The throttle is the pilot's, raised while it
starts and recovers, lowered while inverted. It recovers to the attitude it started from and
hands back once within 5 degrees of it, or gives up (abandons) after 2.5 s or on a big stick.
"""
from __future__ import annotations

import math

from ..pilot import PilotInput
from ..results import Result
from .acro import angle_gains
from .attitude_target import AttitudeTarget, rate_shaping
from .base import Mode, Setpoint
from .context import ModeContext
from .motor_throttle import motor_from_stick, stick_from_motor
from .numbers import ModeNumber

FLIPS_FROM = (ModeNumber.ACRO, ModeNumber.STABILIZE, ModeNumber.ALT_HOLD)  # ArduCopter's allows_flip() (and FLOWHOLD)
NEEDS_OPEN_THROTTLE = (ModeNumber.ACRO, ModeNumber.STABILIZE)
ROTATION_RATE = math.radians(400.0)
THROTTLE_UP = 0.20  # motor throttle added while starting and recovering
THROTTLE_DOWN = 0.24  # taken off while inverted
TIMEOUT_S = 2.5
RECOVERED = math.radians(5.0)
BIG_STICK = 4000.0 / 4500.0  # ArduCopter's 40 degrees of its 45-degree stick
DIRECTION_STICK = 300.0 / 4500.0  # pitch stick past this flips forward or back


def flip_refusal(ctx: ModeContext) -> bool:
    """Whether ArduCopter's ModeFlip::init refuses (it says only "init failed")."""
    pilot = ctx.pilot
    if ctx.mode_number not in FLIPS_FROM:
        return True
    if ctx.mode_number in NEEDS_OPEN_THROTTLE and pilot.throttle <= 0.0:
        return True
    return abs(pilot.roll) >= BIG_STICK or not ctx.armed or ctx.landed


class Flip(Mode):
    number = ModeNumber.FLIP
    checks_for_crashes = False

    def __init__(self) -> None:
        self._target = AttitudeTarget()
        self.state = "START"  # START, ROLL, PITCH_A, PITCH_B, RECOVER
        self.from_mode = ModeNumber.STABILIZE
        self.roll_dir = self.pitch_dir = 0
        self._started_s = 0.0
        self._orig = (0.0, 0.0, 0.0)

    def enter(self, ctx: ModeContext) -> str | None:
        if flip_refusal(ctx):
            return "init failed"
        pilot = ctx.pilot
        self.from_mode = ModeNumber(ctx.mode_number)
        self.state = "START"
        self._started_s = ctx.time_s
        self.roll_dir = self.pitch_dir = 0
        # Firefly's pitch stick is positive forward; ArduCopter's control_in positive back.
        if -pilot.pitch > DIRECTION_STICK:
            self.pitch_dir = 1  # back
        elif -pilot.pitch < -DIRECTION_STICK:
            self.pitch_dir = -1  # forward
        else:
            self.roll_dir = 1 if pilot.roll >= 0.0 else -1
        angle_max = math.radians(ctx.params["ANGLE_MAX"] / 100.0)
        roll, pitch, yaw = ctx.attitude
        self._orig = (min(max(roll, -angle_max), angle_max), min(max(pitch, -angle_max), angle_max), yaw)
        b = ctx.body
        # The target's rate carries on from the mode before: about the vehicle's own.
        self._target.reset((b.qw, b.qx, b.qy, b.qz), (b.p_rad_s, b.q_rad_s, b.r_rad_s))
        return None

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        sp.clear()
        pilot, params = ctx.pilot, ctx.params
        throttle = motor_from_stick(pilot.throttle, params)
        if self._abandoned(ctx, pilot):
            self._recover(sp)
            sp.throttle = stick_from_motor(throttle, params)
            self._hand_back(ctx)
            return
        roll, pitch, _ = ctx.attitude
        angle = roll * self.roll_dir if self.roll_dir else pitch * self.pitch_dir
        state = self.state
        if state == "START":
            self._rotate(ctx, sp, (ROTATION_RATE * self.roll_dir, ROTATION_RATE * self.pitch_dir, 0.0), dt)
            throttle += THROTTLE_UP
            if angle >= math.radians(45.0):
                self.state = "ROLL" if self.roll_dir else "PITCH_A"
        elif state == "ROLL":
            self._rotate(ctx, sp, (ROTATION_RATE * self.roll_dir, 0.0, 0.0), dt)
            throttle = max(throttle - THROTTLE_DOWN, 0.0)
            if -math.radians(90.0) < angle < math.radians(45.0):
                self.state = "RECOVER"
        elif state in ("PITCH_A", "PITCH_B"):
            self._rotate(ctx, sp, (0.0, ROTATION_RATE * self.pitch_dir, 0.0), dt)
            throttle = max(throttle - THROTTLE_DOWN, 0.0)
            if state == "PITCH_A" and abs(roll) > math.radians(90.0) and angle > math.radians(45.0):
                self.state = "PITCH_B"
            elif state == "PITCH_B" and abs(roll) < math.radians(90.0) and angle > -math.radians(45.0):
                self.state = "RECOVER"
        else:
            self._recover(sp)
            throttle += THROTTLE_UP
            error = self._orig[0] - roll if self.roll_dir else self._orig[1] - pitch
            if abs(error) <= RECOVERED:
                sp.throttle = stick_from_motor(throttle, params)
                self._hand_back(ctx)
                return
        sp.throttle = stick_from_motor(throttle, params)

    def _abandoned(self, ctx: ModeContext, pilot: PilotInput) -> bool:
        return (not ctx.armed or abs(pilot.roll) >= BIG_STICK or abs(pilot.pitch) >= BIG_STICK
                or ctx.time_s - self._started_s > TIMEOUT_S)

    def _rotate(self, ctx: ModeContext, sp: Setpoint, rates: tuple[float, float, float], dt: float) -> None:
        b = ctx.body
        sp.rates = self._target.rate_command(rates, (b.qw, b.qx, b.qy, b.qz), angle_gains(ctx.params), dt,
                                             rate_shaping(ctx.params))

    def _recover(self, sp: Setpoint) -> None:
        """Back to the attitude the flip started from, by the angle controller."""
        sp.lean = (self._orig[0], self._orig[1])
        sp.yaw = self._orig[2]

    def _hand_back(self, ctx: ModeContext) -> None:
        if ctx.set_mode(self.from_mode) != Result.ACCEPTED:  # should never fail: it flew just now
            ctx.set_mode(ModeNumber.STABILIZE)

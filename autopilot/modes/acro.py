"""ACRO: the sticks ask for body rates (ACRO_RP_RATE, ACRO_Y_RATE, with ACRO_*_EXPO), the
throttle is the pilot's as in STABILIZE. ACRO_TRAINER: 0 off, 1 the vehicle levels itself when
the sticks are let go (ACRO_BAL_ROLL/PITCH), 2 (ArduCopter's default) levels and also limits the
lean to ANGLE_MAX. As ArduCopter's, the rates turn an attitude target the vehicle is steered to,
so with the sticks centred it holds its attitude rather than drifting.
"""
from __future__ import annotations

import math

from ..control.position import sqrt_controller
from ..params import ParamStore
from ..pilot import PilotInput
from .attitude_target import AttitudeTarget, euler_rates_to_body, rate_shaping
from .base import Mode, Setpoint, stick_deadzone
from .context import ModeContext
from .numbers import ModeNumber

LEVEL_MAX_ANGLE = math.radians(30.0)  # the trainer levels at most this lean's worth of rate
LEVEL_MAX_OVERSHOOT = math.radians(10.0)  # trainer 2: full stick holds the lean this far past ANGLE_MAX
TRAINER_LEVELLING, TRAINER_LIMITED = 1, 2
RATE_LOOP_ONLY = 2  # ACRO_OPTIONS bit: rates without the attitude target's correction


def input_expo(stick: float, expo: float) -> float:
    """ArduPilot's stick expo: softer around the centre, full at the ends."""
    stick = min(max(stick, -1.0), 1.0)
    if expo < 0.95:
        return (1.0 - expo) * stick / (1.0 - expo * abs(stick))
    return stick


def angle_gains(params: ParamStore) -> tuple[float, float, float]:
    return (params["ATC_ANG_RLL_P"], params["ATC_ANG_PIT_P"], params["ATC_ANG_YAW_P"])


def acro_rates(params: ParamStore, pilot: PilotInput, target_euler: tuple[float, float, float],
               pitch: float) -> tuple[float, float, float]:
    """The body rates [rad/s] the sticks ask for, with the trainer's levelling (ArduCopter's
    get_pilot_desired_rates); target_euler is the attitude target, pitch the vehicle's."""
    roll_in, pitch_in, yaw_in = stick_deadzone(pilot.roll), -stick_deadzone(pilot.pitch), stick_deadzone(pilot.yaw)
    length = math.hypot(roll_in, pitch_in)
    if length > 1.0:
        roll_in, pitch_in = roll_in / length, pitch_in / length
    rp_rate = math.radians(params["ACRO_RP_RATE"])
    rp_expo = params["ACRO_RP_EXPO"]
    asked = (rp_rate * input_expo(roll_in, rp_expo), rp_rate * input_expo(pitch_in, rp_expo),
             math.radians(params["ACRO_Y_RATE"]) * input_expo(yaw_in, params["ACRO_Y_EXPO"]))
    trainer = int(params["ACRO_TRAINER"])
    if trainer not in (TRAINER_LEVELLING, TRAINER_LIMITED):
        return asked
    roll_t, pitch_t, _ = target_euler
    level = [-min(max(roll_t, -LEVEL_MAX_ANGLE), LEVEL_MAX_ANGLE) * params["ACRO_BAL_ROLL"],
             -min(max(pitch_t, -LEVEL_MAX_ANGLE), LEVEL_MAX_ANGLE) * params["ACRO_BAL_PITCH"], 0.0]
    if trainer == TRAINER_LIMITED:
        angle_max = math.radians(params["ANGLE_MAX"] / 100.0)
        gain = rp_rate / LEVEL_MAX_OVERSHOOT
        for axis, angle, accel in ((0, roll_t, params["ATC_ACCEL_R_MAX"]), (1, pitch_t, params["ATC_ACCEL_P_MAX"])):
            if abs(angle) > angle_max:
                level[axis] += sqrt_controller(math.copysign(angle_max, angle) - angle, gain,
                                               math.radians(accel / 100.0))
    level_bf = euler_rates_to_body(roll_t, pitch_t, (level[0], level[1], level[2]))
    if trainer == TRAINER_LIMITED:
        return (asked[0] + level_bf[0], asked[1] + level_bf[1], asked[2] + level_bf[2])
    # Levelling only: it fades out as a stick moves, and never reverses the rate asked for.
    mix = min(max(1.0 - max(abs(roll_in), abs(pitch_in), abs(yaw_in)), 0.0), 1.0) * math.cos(pitch)
    rates = []
    for want, lev in zip(asked, level_bf):
        lev *= mix
        limit = abs(abs(want) - abs(lev))
        rates.append(min(max(want + lev, -limit), limit))
    return (rates[0], rates[1], rates[2])


class Acro(Mode):
    number = ModeNumber.ACRO
    checks_for_crashes = False
    allows_arming = True
    manual_throttle = True

    def __init__(self) -> None:
        self._target = AttitudeTarget()

    def enter(self, ctx: ModeContext) -> str | None:
        b = ctx.body
        self._target.reset((b.qw, b.qx, b.qy, b.qz), (b.p_rad_s, b.q_rad_s, b.r_rad_s))
        return None

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        sp.clear()
        pilot, params, b = ctx.pilot, ctx.params, ctx.body
        actual = (b.qw, b.qx, b.qy, b.qz)
        sp.throttle = pilot.throttle
        # On the ground, or with the throttle closed (ArduCopter's ground idle), the target is
        # where the vehicle is: nothing winds up to be flown out when it lifts.
        if ctx.landed or pilot.throttle <= 0.0 or int(params["ACRO_OPTIONS"]) & RATE_LOOP_ONLY:
            self._target.reset(actual)
        rates = acro_rates(params, pilot, self._target.euler(), ctx.attitude[1])
        sp.rates = self._target.rate_command(rates, actual, angle_gains(params), dt,
                                             rate_shaping(params, "ACRO_Y_RATE_TC"))

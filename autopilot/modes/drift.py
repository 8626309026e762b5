"""DRIFT: flown like a car. The pitch stick leans forward and back (let go, the vehicle brakes to
a stop over a few seconds); the roll stick turns (a yaw rate, less of it the faster it goes);
the roll itself cancels sideways slip, or slides sideways as the yaw stick asks; the throttle
is the pilot's, with an assist that damps the climb rate while the stick is near the middle.
ArduCopter's numbers (mode_drift.cpp), which work in centidegrees and cm/s.
"""
from __future__ import annotations

import math

from .base import Mode, Setpoint, stick_deadzone
from .context import ModeContext
from .motor_throttle import motor_from_stick, stick_from_motor
from .numbers import ModeNumber

SPEED_GAIN = 8.0
SPEED_LIMIT_CM_S = 560.0
FORWARD_SPEED_MIN_CM_S = 2000.0  # the yaw rate's fade with forward speed stops here
ROLL_MAX_CD = 4500.0
BRAKE_STEP = 0.03  # per update: full braking after about 2.7 s at 100 Hz
THR_ASSIST_GAIN = 0.0018  # motor throttle per cm/s of climb
THR_ASSIST_MAX = 0.3
THR_ASSIST_BAND = (0.213, 0.787)  # the assist acts only while the throttle is between these
STICK_CD = 4500.0  # a full stick, in ArduCopter's control units


def throttle_assist(climb_cm_s: float, throttle: float) -> float:
    """The pilot's motor throttle, nudged against the climb rate near mid-stick."""
    assist = 0.0
    if THR_ASSIST_BAND[0] < throttle < THR_ASSIST_BAND[1]:
        assist = min(max(1.2 - abs(throttle - 0.5) / 0.24, 0.0), 1.0) * -THR_ASSIST_GAIN * climb_cm_s
        assist = min(max(assist, -THR_ASSIST_MAX), THR_ASSIST_MAX)
    return min(max(throttle + assist, 0.0), 1.0)


class Drift(Mode):
    number = ModeNumber.DRIFT
    requires_position = True
    allows_arming = True
    # ArduCopter treats DRIFT's throttle as the pilot's for arming and mode-change checks.
    manual_throttle = True

    def __init__(self) -> None:
        self._braker = 0.0
        self._slide_cd = 0.0  # the yaw stick, filtered

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        sp.clear()
        pilot, params, b = ctx.pilot, ctx.params, ctx.body
        lean_max_cd = params["ANGLE_MAX"]
        roll_cd = stick_deadzone(pilot.roll) * lean_max_cd
        pitch_cd = -stick_deadzone(pilot.pitch) * lean_max_cd  # stick forward: nose down
        yaw = ctx.attitude[2]
        c, s = math.cos(yaw), math.sin(yaw)
        vn, ve = b.vn_m_s * 100.0, b.ve_m_s * 100.0
        right = ve * c - vn * s
        forward = ve * s + vn * c
        fade = min(abs(forward), FORWARD_SPEED_MIN_CM_S) / 5000.0
        yaw_rate_cd = roll_cd * (1.0 - fade) * params["ACRO_Y_RATE"] / 45.0
        right = min(max(right, -SPEED_LIMIT_CM_S), SPEED_LIMIT_CM_S)
        forward = min(max(forward, -SPEED_LIMIT_CM_S), SPEED_LIMIT_CM_S)
        self._slide_cd = self._slide_cd * 0.96 + stick_deadzone(pilot.yaw) * STICK_CD * 0.04
        roll_cd = min(max((right - self._slide_cd / SPEED_GAIN) * -SPEED_GAIN, -ROLL_MAX_CD), ROLL_MAX_CD)
        if pitch_cd == 0.0:  # sticks let go: brake, harder and harder
            self._braker = min(self._braker + BRAKE_STEP, SPEED_GAIN)
            pitch_cd = forward * self._braker
        else:
            self._braker = 0.0
        sp.lean = (math.radians(roll_cd / 100.0), math.radians(pitch_cd / 100.0))
        sp.yaw_rate = math.radians(yaw_rate_cd / 100.0)
        throttle = throttle_assist(-b.vd_m_s * 100.0, motor_from_stick(pilot.throttle, params))
        sp.throttle = stick_from_motor(throttle, params)

"""ArduCopter's thrust-loss check (crash_check.cpp): descending while nearly level, with the
throttle high or a motor at its limit, and attitude still under control, for a second, means a
motor or propeller has lost thrust. It is announced as "Potential Thrust Loss (N)", N being the
motor that works hardest (ArduCopter's number, motor_outputs.py). ArduCopter then engages
"thrust boost" (yaw gives way to roll, pitch and thrust); this allocator always ranks them so, so
announcing is all that is left to do.
"""
from __future__ import annotations

import math

from ..motor_outputs import OUTPUT_OF_MOTOR
from ..results import Severity
from ..views import ThrustLossView

TRIGGER_S = 1.0  # THRUST_LOSS_CHECK_TRIGGER_SEC
LEAN_MAX_RAD = math.radians(15.0)  # THRUST_LOSS_CHECK_ANGLE_DEVIATION_CD
THROTTLE_HIGH = 0.9  # THRUST_LOSS_CHECK_MINIMUM_THROTTLE
THROTTLE_LOW = 0.25  # below this, a thrust limit is the pilot's doing, not a loss
ATTITUDE_ERROR_MAX_RAD = math.radians(30.0)  # CRASH_CHECK_ANGLE_DEVIATION_DEG
SATURATED = 0.999  # a motor commanded at this share of its top speed is at its limit


class ThrustLossCheck:
    def __init__(self) -> None:
        self._seconds = 0.0
        self.announced = False  # stays until no motor is at its limit (ArduCopter's thrust boost)

    def check(self, v: ThrustLossView, dt: float) -> None:
        """Called with the failsafe checks, at a tenth of the flight-mode rate (10 Hz)."""
        commands = v.motor_commands
        at_limit = max(commands) >= SATURATED * v.omega_max_rad_s
        if self.announced:
            self.announced = at_limit
            return
        if self._suspected(v, at_limit):
            self._seconds += dt
        else:
            self._seconds = 0.0
        if self._seconds >= TRIGGER_S - 1e-9:
            self._seconds = 0.0
            self.announced = True
            motor = OUTPUT_OF_MOTOR[commands.index(max(commands))]
            v.notify(f"Potential Thrust Loss ({motor})", Severity.EMERGENCY)

    @staticmethod
    def _suspected(v: ThrustLossView, at_limit: bool) -> bool:
        if not v.armed or v.landed:
            return False
        roll_t, pitch_t = v.lean_target
        if math.hypot(roll_t, pitch_t) > LEAN_MAX_RAD:
            return False
        throttle = v.thrust_demand_n / v.thrust_max_n
        if throttle < THROTTLE_LOW or (throttle < THROTTLE_HIGH and not at_limit):
            return False
        if v.body.vd_m_s <= 0.0:  # not descending
            return False
        roll, pitch, _ = v.attitude
        return max(abs(roll - roll_t), abs(pitch - pitch_t)) < ATTITUDE_ERROR_MAX_RAD

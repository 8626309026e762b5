"""The EKF failsafe and the GPS glitch check, as ArduCopter's ekf_check.cpp and gpsglitch_check().

The estimate here is ideal (the sim's own state), so there are no variances to watch. What is
honest to model is what the estimate cannot do without GPS: know its horizontal position. So the
check counts, at 10 Hz, while the estimate has no position (ArduCopter: EKF position not ok,
with no optical flow; DEAD_RECKONING_S after the last GPS fix, estimate.py), and after
EKF_CHECK_ITERATIONS_MAX bad checks in a row says "EKF variance" and takes FS_EKF_ACTION. It counts back down once the fix returns and clears at zero. A fix that
jumps away from the estimate by more than GPS_GLITCH_GATE_M is a glitch the EKF would reject:
announced as ArduCopter does, and refused at arming, while the estimate itself is unaffected.
"""
from __future__ import annotations

import math

from ..modes.numbers import ModeNumber
from ..results import Result, Severity
from ..views import FailsafeView

EKF_CHECK_ITERATIONS_MAX = 10  # 1 s of bad checks at 10 Hz
GPS_GLITCH_GATE_M = 5.0  # horizontal GPS-to-estimate distance beyond which a fix is rejected
ACTION_LAND, ACTION_ALT_HOLD, ACTION_LAND_EVEN_STABILIZE = 1, 2, 3


class EkfCheck:
    def __init__(self) -> None:
        self.fail_count = 0
        self.failsafe = False  # ArduCopter's failsafe.ekf
        self.acted = False  # an action was taken (ArduCopter's AP_Notify failsafe_ekf flag)
        self.gps_glitching = False

    def check(self, v: FailsafeView) -> None:
        """Called at 10 Hz."""
        self._check_glitch(v)
        if not v.armed or v.params["FS_EKF_THRESH"] <= 0:
            self.fail_count = 0
            self._clear(v)
            return
        if not v.has_position():
            if not self.failsafe:
                self.fail_count += 1
                if self.fail_count >= EKF_CHECK_ITERATIONS_MAX:
                    v.notify("EKF variance", Severity.CRITICAL)
                    self._trip(v)
        elif self.fail_count > 0:
            self.fail_count -= 1
            if self.fail_count == 0:
                self._clear(v)

    def _trip(self, v: FailsafeView) -> None:
        self.failsafe = True
        action = int(v.params["FS_EKF_ACTION"])
        if not v.mode_requires_position and action != ACTION_LAND_EVEN_STABILIZE:
            return
        if v.mode_number == ModeNumber.LAND:
            return
        if action != ACTION_ALT_HOLD or v.set_mode(ModeNumber.ALT_HOLD) != Result.ACCEPTED:
            v.set_mode(ModeNumber.LAND)
        self.acted = True
        v.notify(f"EKF Failsafe: changed to {v.mode_name} Mode", Severity.CRITICAL)

    def _clear(self, v: FailsafeView) -> None:
        if not self.failsafe:
            return
        self.failsafe = False
        if self.acted:
            self.acted = False
            v.notify("EKF Failsafe Cleared", Severity.CRITICAL)

    def _check_glitch(self, v: FailsafeView) -> None:
        gps, b = v.gps, v.body
        glitching = gps.fix_type >= 3 and math.hypot(gps.n_m - b.n_m, gps.e_m - b.e_m) > GPS_GLITCH_GATE_M
        if glitching != self.gps_glitching:
            self.gps_glitching = glitching
            v.notify("GPS Glitch or Compass error" if glitching else "Glitch cleared", Severity.CRITICAL)

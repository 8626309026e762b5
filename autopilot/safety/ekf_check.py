"""The EKF failsafe, the GPS glitch check and the vibration check, as ArduCopter's ekf_check.cpp,
gpsglitch_check() and check_vibration().

The estimate here is ideal (the sim's own state), so most of EKF3's variances have nothing to
watch. Three things are modelled, each as ArduCopter's check sees it:
- the horizontal position, which the estimate cannot know without a source: counted as bad
  while the estimate has no position (ArduCopter: EKF position not ok, with no optical flow;
  DEAD_RECKONING_S after the last fix, estimate.py);
- the velocity variance: EKF3 reports the square root of its GPS velocity test ratio, which
  grows with the distance between the GPS's velocity and the estimate's. Measured on ArduCopter
  SITL under SIM_GPS1_JAM, 3.1 to 4.9 m/s of velocity innovation per unit (VEL_INNOVATION_M_S);
  like EKF3's it holds between fused fixes. It is filtered at FS_EKF_FILT, as ekf_check's;
- the position variance: the fix's distance from the estimate over GPS_GLITCH_GATE_M (EKF3's gate
  as measured, where its test ratio reaches 1). ArduCopter's check counts a high position
  variance only with one other over the threshold, so a glitch alone trips nothing, as measured.
The two test ratios also make EKF3's GPS glitch flag, with its hysteresis (_check_glitch).
After EKF_CHECK_ITERATIONS_MAX bad checks the failsafe says "EKF variance" and takes FS_EKF_ACTION;
it counts back down once the checks pass, and clears at zero.

The vibration check is ArduCopter's: the filtered velocity variance above 1 for a second, armed
in a mode without manual throttle, turns vibration compensation on (FS_VIBE_ENABLE); 15 s
without it, off. Firefly says so and keeps the state; its altitude controller has no vibration
to resist, so its gains stay. ArduCopter also wants the vertical velocity and height
innovations positive, which an ideal estimate cannot give: left out, as measured, for ArduCopter
said it in each of four jammed flights (SIM_GPS1_JAM), within 20 s.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ..modes.numbers import ModeNumber
from ..results import Result, Severity
from ..views import FailsafeView

if TYPE_CHECKING:
    from firefly.sim.rigid_body import BodyState
    from firefly.sim.sensors import GpsReading

EKF_CHECK_ITERATIONS_MAX = 10  # 1 s of bad checks at 10 Hz
CHECK_DT_S = 0.1  # the checks run at 10 Hz
GPS_GLITCH_GATE_M = 5.0  # horizontal GPS-to-estimate distance beyond which a fix is rejected
# EKF3's innovation check (calcGpsGoodForFlight): failing for a second makes a glitch, passing for
# ten seconds ends it; a test ratio above this fails, below 1 (both) passes
GLITCH_DETECT_S, GLITCH_CLEAR_S, INNOVATION_FAIL_RATIO = 1.0, 10.0, 0.7
VEL_INNOVATION_M_S = 3.5  # GPS velocity innovation per unit of EKF3's reported velocity variance
VIBE_DETECT_S, VIBE_CLEAR_S = 1.0, 15.0  # check_vibration's times to switch compensation on and off
ACTION_REPORT_ONLY, ACTION_LAND, ACTION_ALT_HOLD, ACTION_LAND_EVEN_STABILIZE = 0, 1, 2, 3


class EkfCheck:
    def __init__(self) -> None:
        self.fail_count = 0
        self.failsafe = False  # ArduCopter's failsafe.ekf
        self.acted = False  # ArduCopter's AP_Notify failsafe_ekf flag: tripped while armed
        self.gps_glitching = False
        self.vel_variance = self.pos_variance = 0.0  # EKF3's (square roots of its test ratios), from the last fix
        self.vel_variance_filt = 0.0
        self.vibe_comp = False  # ArduCopter's vibration_check.high_vibes
        self._vibe_since_s: float | None = None  # bad since then (None: not bad at the last check)
        self._vibe_last_s = 0.0
        self._filt_hz, self._alpha = math.nan, 1.0  # FS_EKF_FILT and its filter's gain
        self._innovations_passed_s = self._innovations_failed_s = 0.0
        self.ever_passed = False  # ArduCopter's has_ever_passed: nothing is counted before

    @property
    def test_ratios(self) -> tuple[float, float]:
        """The velocity and position variances of the last fix (EKF_STATUS_REPORT's)."""
        return self.vel_variance, self.pos_variance

    def check(self, v: FailsafeView) -> None:
        """Called at 10 Hz."""
        gps, body, params = v.gps, v.body, v.params
        thresh = params["FS_EKF_THRESH"]
        over = self._variances_over(gps, body, params["FS_EKF_FILT"], thresh)
        self._check_glitch(v, gps)
        if self.vel_variance_filt > 1.0 or self.vibe_comp:
            self._check_vibration(v)
        else:  # (most checks: nothing to time)
            self._vibe_since_s = None
        if not self.ever_passed:  # as ArduCopter's: no origin yet, or the checks never passed (no GPS
            # from power-on): no failsafe to count towards (measured: arming so says no "EKF Failsafe")
            self.ever_passed = v.ekf_has_origin() and not over and v.has_position()
            if not self.ever_passed:
                return
        if not v.armed or thresh <= 0:
            self.fail_count = 0
            self._clear(v)
            return
        if over or not v.has_position():
            if not self.failsafe:
                self.fail_count += 1
                if self.fail_count >= EKF_CHECK_ITERATIONS_MAX:
                    v.notify("EKF variance", Severity.CRITICAL)
                    self._trip(v)
        elif self.fail_count > 0:
            self.fail_count -= 1
            if self.fail_count == 0:
                self._clear(v)

    def _variances_over(self, gps: GpsReading, b: BodyState, filt_hz: float, thresh: float) -> bool:
        """ekf_over_threshold(): the velocity variance (filtered) at twice the threshold, or at it
        with the position's; the magnetometers never are."""
        if gps.fix_type >= 3:  # a fix fused (or tested): its innovations
            dn, de, dd = gps.vn_m_s - b.vn_m_s, gps.ve_m_s - b.ve_m_s, gps.vd_m_s - b.vd_m_s
            self.vel_variance = math.sqrt(dn * dn + de * de + dd * dd) / VEL_INNOVATION_M_S
            self.pos_variance = math.hypot(gps.n_m - b.n_m, gps.e_m - b.e_m) / GPS_GLITCH_GATE_M
        if filt_hz != self._filt_hz:
            self._filt_hz = filt_hz  # ArduPilot's LowPassFilterFloat at the check's rate
            self._alpha = CHECK_DT_S / (CHECK_DT_S + 1.0 / (2.0 * math.pi * filt_hz)) if filt_hz > 0 else 1.0
        filt = self.vel_variance_filt = self.vel_variance_filt + self._alpha * (self.vel_variance - self.vel_variance_filt)
        if filt < thresh:
            return False
        return filt >= 2.0 * thresh or self.pos_variance >= thresh

    def _check_vibration(self, v: FailsafeView) -> None:
        now = v.time_s
        bad = (self.vel_variance_filt > 1.0 and v.armed and not v.mode_manual_throttle
               and v.params["FS_VIBE_ENABLE"] == 1)
        if not self.vibe_comp:
            if not bad or self._vibe_since_s is None:  # timed from the last check that was not bad
                self._vibe_since_s = now - CHECK_DT_S if bad else None
            elif now - self._vibe_since_s > VIBE_DETECT_S:
                self.vibe_comp, self._vibe_last_s = True, now
                v.notify("Vibration compensation ON", Severity.CRITICAL)
        else:
            if bad:
                self._vibe_last_s = now
            elif now - self._vibe_last_s > VIBE_CLEAR_S:
                self.vibe_comp = False
                self._vibe_since_s = None
                v.notify("Vibration compensation OFF", Severity.CRITICAL)

    def _trip(self, v: FailsafeView) -> None:
        """failsafe_ekf_event(): a mode that needs no position (and LAND) only hears of it."""
        self.failsafe = True
        self.acted = True
        action = int(v.params["FS_EKF_ACTION"])
        no_action_here = not v.mode_requires_position and action != ACTION_LAND_EVEN_STABILIZE
        if action == ACTION_REPORT_ONLY or v.mode_number == ModeNumber.LAND or no_action_here:
            v.notify("EKF Failsafe", Severity.CRITICAL)
            return
        if action != ACTION_ALT_HOLD or v.set_mode(ModeNumber.ALT_HOLD) != Result.ACCEPTED:
            v.set_mode(ModeNumber.LAND)
        v.notify(f"EKF Failsafe: changed to {v.mode_name} Mode", Severity.CRITICAL)

    def _clear(self, v: FailsafeView) -> None:
        if not self.failsafe:
            return
        self.failsafe = False
        if self.acted:
            self.acted = False
            v.notify("EKF Failsafe Cleared", Severity.CRITICAL)

    def _check_glitch(self, v: FailsafeView, gps: GpsReading) -> None:
        """EKF3's GPS accuracy check: the fix's innovations judged with hysteresis, failing for a
        second to call the GPS glitching, passing for GLITCH_CLEAR_S to call it well again. The
        position's test ratio is its distance from the estimate over GPS_GLITCH_GATE_M, squared;
        the velocity's, the velocity variance squared."""
        if gps.fix_type < 3:  # no fix, nothing to judge: EKF3's flag stays as the last fix left it
            return
        now = v.time_s
        pos_ratio, vel_ratio = self.pos_variance * self.pos_variance, self.vel_variance * self.vel_variance
        if pos_ratio < 1.0 and vel_ratio < 1.0:
            self._innovations_passed_s = now
        elif pos_ratio > INNOVATION_FAIL_RATIO or vel_ratio > INNOVATION_FAIL_RATIO:
            self._innovations_failed_s = now
        if self.gps_glitching:
            if now - self._innovations_failed_s > GLITCH_CLEAR_S:
                self.gps_glitching = False
                v.notify("Glitch cleared", Severity.CRITICAL)
        elif now - self._innovations_passed_s > GLITCH_DETECT_S:
            self.gps_glitching = True
            v.notify("GPS Glitch or Compass error", Severity.CRITICAL)

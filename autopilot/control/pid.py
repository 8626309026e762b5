"""PID with derivative on measurement (or, with d_on_error, on the error: ArduCopter's AC_PID with an
unfiltered target, FLTT 0), integrator limit and anti-windup on output saturation."""
from __future__ import annotations

import math


class Pid:
    def __init__(self, kp: float, ki: float = 0.0, kd: float = 0.0, imax: float = math.inf,
                 out_limit: float = math.inf, d_filter_hz: float = 20.0):
        self.kp, self.ki, self.kd = kp, ki, kd
        self.imax, self.out_limit, self.d_filter_hz = imax, out_limit, d_filter_hz
        self.d_on_error = 0.0  # 1.0: D acts on the error, so a stepped target kicks it
        self.integrator = 0.0
        self._last_measurement: float | None = None
        self._d_filtered = 0.0

    def reset(self, integrator: float = 0.0) -> None:
        """Bumpless take-over: forget history, optionally preload the integrator."""
        self.integrator = max(-self.imax, min(self.imax, integrator))
        self._last_measurement = None
        self._d_filtered = 0.0

    def set_d_on_error(self, on_error: float, d_filter_hz: float) -> None:
        """D on the error (1.0) or on the measurement (0.0), filtered at d_filter_hz; a switch
        forgets the D history, whose last input was of the other kind (the integrator is kept)."""
        self.d_filter_hz = d_filter_hz
        if on_error != self.d_on_error:
            self.d_on_error = on_error
            self._last_measurement = None
            self._d_filtered = 0.0

    def update(self, target: float, measurement: float, dt: float) -> float:
        error = target - measurement
        d_input = -measurement if self.d_on_error == 0.0 else error
        if self._last_measurement is None or self.kd == 0.0:
            d_term = 0.0
        else:
            raw = (d_input - self._last_measurement) / dt
            alpha = dt / (dt + 1.0 / (2.0 * math.pi * self.d_filter_hz))
            self._d_filtered += alpha * (raw - self._d_filtered)
            d_term = self.kd * self._d_filtered
        self._last_measurement = d_input
        unsat = self.kp * error + self.integrator + d_term
        out = max(-self.out_limit, min(self.out_limit, unsat))
        # Anti-windup: integrate only when that does not push further into saturation.
        if out == unsat or (unsat > out) != (error > 0.0):
            self.integrator = max(-self.imax, min(self.imax, self.integrator + self.ki * error * dt))
        return out

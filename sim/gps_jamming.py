"""A jammed GPS receiver, as ArduPilot SITL's SIM_GPS1_JAM makes one (libraries/SITL/SIM_GPS.cpp).

What the receiver reports while jammed, from the true reading, at SITL's GPS rate (5 Hz):
- for the first 1 to 6 seconds (a random span, drawn again at every sample), no lock at all;
- then, at random moments, each quantity changes at its own mean rate: the satellites in view
  (3 Hz: 2 to 16, and with 4 or more a lock half the time, else none), the vertical speed
  (0.5 Hz: anything within +-400 m/s), the horizontal speed (0.8 Hz: the same), the position
  (1.1 Hz: a step of up to 200 m north and east from where it was). SITL also changes the
  reported accuracies (3 Hz); Firefly's receiver reports none, so they are left out.
  A changed number or speed is reported in that sample only; the position stays where it was
  stepped to, starting from where the vehicle was when the jamming began.
A jamming that stops for more than a second starts afresh. The draws come from the receiver's
own generator, so a jammed run is as repeatable as any other.
"""
from __future__ import annotations

import numpy as np

from .sensors import FIX_3D, NO_FIX, GpsReading

SAMPLE_S = 0.2  # SIM_GPS1_HZ 5: how often SITL's receiver makes a reading
RESTART_S = 1.0  # a pause in the jamming this long starts it again from the true position
LOSS_MIN_S, LOSS_SPAN_S = 1.0, 5.0  # the total loss at the start: 1 s plus up to 5 s more
SATS_HZ, VD_HZ, VEL_HZ, POS_HZ = 3.0, 0.5, 0.8, 1.1  # how often each quantity changes
SPEED_MAX_M_S = 400.0
STEP_MAX_M = 200.0
SATS_WITHOUT_LOCK = 3  # what SITL's receivers report in view without a lock


class GpsJamming:
    def __init__(self, rng: np.random.Generator):
        self._rng = rng
        self._last_s = -np.inf  # the last jammed sample
        self._start_s = 0.0
        self._n = self._e = 0.0  # where the jammed position stands
        self._changed = {"sats": 0.0, "vd": 0.0, "vel": 0.0, "pos": 0.0}
        self._reading: GpsReading | None = None  # the last jammed reading, held between samples

    def _rand(self) -> float:
        """ArduPilot's rand_float(): uniform in [-1, 1]."""
        return float(self._rng.uniform(-1.0, 1.0))

    def _due(self, what: str, hz: float, now_s: float) -> bool:
        """Whether `what` changes now: SITL's test, the time since its last change against twice a
        random fraction of its mean period."""
        if now_s - self._changed[what] > 2.0 * abs(self._rand()) / hz:
            self._changed[what] = now_s
            return True
        return False

    def read(self, true: GpsReading, now_s: float) -> GpsReading:
        if self._reading is not None and now_s - self._last_s < SAMPLE_S - 1e-9:
            return self._reading  # between SITL's samples the receiver says nothing new
        if now_s - self._last_s > RESTART_S:
            self._start_s = now_s
            self._n, self._e = true.n_m, true.e_m
        self._last_s = now_s
        sats, fix = true.satellites, true.fix_type
        vn, ve, vd = true.vn_m_s, true.ve_m_s, true.vd_m_s
        if now_s - self._start_s < LOSS_MIN_S + LOSS_SPAN_S * float(self._rng.random()):
            sats, fix = SATS_WITHOUT_LOCK, NO_FIX
        else:
            if self._due("sats", SATS_HZ, now_s):
                sats = 2 + int(self._rng.integers(15))
                fix = FIX_3D if sats >= 4 and self._rng.random() < 0.5 else NO_FIX
                if fix == NO_FIX:
                    sats = SATS_WITHOUT_LOCK
            if self._due("vd", VD_HZ, now_s):
                vd = self._rand() * SPEED_MAX_M_S
            if self._due("vel", VEL_HZ, now_s):
                vn, ve = self._rand() * SPEED_MAX_M_S, self._rand() * SPEED_MAX_M_S
            if self._due("pos", POS_HZ, now_s):
                self._n += self._rand() * STEP_MAX_M
                self._e += self._rand() * STEP_MAX_M
        if true.fix_type != FIX_3D:  # a receiver switched off stays off
            sats, fix = true.satellites, true.fix_type
        self._reading = GpsReading(self._n, self._e, true.d_m, vn, ve, vd, sats, fix)
        return self._reading

"""The downward rangefinder as a terrain source, as ArduCopter's AP_SurfaceDistance and
update_rangefinder_terrain_offset make one for its waypoint navigator.

A reading is healthy when good three times in a row (RANGEFINDER_HEALTH_MIN); its height is the
range times the body's tilt (at most 45 degrees' worth: 0.707), and a change of 2 m or more from
the last one kept is a glitch until three come in a row (then taken). The terrain offset, the
ground's height above the local origin, is the vehicle's altitude less that height, low-passed with
SURFTRAK_TC; reset to the raw value after a second without a healthy reading or a glitch taken.
"""
from __future__ import annotations

HEALTH_MIN = 3  # RANGEFINDER_HEALTH_MIN
GLITCH_M = 2.0  # RANGEFINDER_GLITCH_ALT_CM
GLITCH_SAMPLES = 3  # RANGEFINDER_GLITCH_NUM_SAMPLES
TIMEOUT_S = 1.0  # RANGEFINDER_TIMEOUT_MS
TILT_FLOOR = 0.707


class SurfaceDistance:
    def __init__(self) -> None:
        self.healthy = False
        self.offset_m: float | None = None  # the terrain's height above the origin; None before any
        self._kept_m = 0.0  # alt_cm_glitch_protected
        self._glitches = 0
        self._last_healthy_s = -1e9

    def update(self, now_s: float, good: bool, valid_count: int, distance_m: float, cos_tilt: float,
               altitude_m: float, dt: float, tc_s: float) -> None:
        """A reading (at ArduCopter's 20 Hz): whether good, the good ones in a row, its range, the
        body's down axis' share of the vertical, and the vehicle's altitude above the origin."""
        self.healthy = good and valid_count >= HEALTH_MIN
        height = max(TILT_FLOOR, cos_tilt) * distance_m
        jump = height - self._kept_m
        reset = False
        if abs(jump) >= GLITCH_M:
            self._glitches = max(self._glitches + 1, 1) if jump > 0 else min(self._glitches - 1, -1)
        else:
            self._glitches, self._kept_m = 0, height
        if abs(self._glitches) >= GLITCH_SAMPLES:
            self._glitches, self._kept_m, reset = 0, height, True
        if self.healthy:
            if now_s - self._last_healthy_s > TIMEOUT_S:
                reset = True
            self._last_healthy_s = now_s
        target = altitude_m - self._kept_m
        if reset or self.offset_m is None:
            self.offset_m = target
        else:
            self.offset_m += (target - self.offset_m) * dt / max(tc_s, dt)

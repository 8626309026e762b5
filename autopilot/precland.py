"""Precision landing, as ArduCopter's AC_PrecLand finds a landing target and its LAND flies to it
(measured on ArduCopter SITL, parity area precland).

PLND_TYPE is read at boot, with PLND_ENABLED: 4 is SITL's beacon (sim/precland.py), 1 a
companion's LANDING_TARGET. Each reading is a line of sight to the target; with a rangefinder
reading (RNGFND1 facing down, good) or a distance the sensor gives, it places the target: the
rangefinder's height along the line. The estimator (PLND_EST_TYPE 1) takes its first reading
("PrecLand: Target Found") and 2 s of readings, none more than 0.5 s apart, before the target is
acquired ("PrecLand: Init Complete"; a gap first: "PrecLand: Init Failed"); with 0 the target is
acquired at once. No reading for 2 s loses it ("PrecLand: Target Lost").

LAND (RTL's final descent and AUTO's land item too) then flies to the target while it descends, but holds its height while more than
PLND_XY_DIST_MAX from it, and between 2 m and 0.35 m above it slows to between 0.1 m/s and half
LAND_SPEED as its error grows to 15 cm. A target not in sight is precland_retry.py's: a target
never seen while the rangefinder reads between PLND_ALT_MIN and PLND_ALT_MAX is the failsafe
("PrecLand: Failsafe Measures": PLND_STRICT 1 holds 7 s and then comes down where it is, 2 holds,
0 comes down at once); one lost descends PLND_TIMEOUT and then retries (PLND_STRICT 1, 2),
climbing back over where it last saw it, or comes down where it is (0).

SYS_STATUS's vision-position bit is present and enabled with precision landing on, healthy while
the sensor is (SITL's beacon sees the vehicle; a companion's backend always).
"""
from __future__ import annotations

import math
from typing import NamedTuple

from .precland_retry import Action, RetryMachine, TargetState
from .results import Severity

NONE, MAVLINK, SITL = 0, 1, 4  # PLND_TYPE
INIT_S = 2.0  # EKF_INIT_TIME_MS
INIT_GAP_S = 0.5  # EKF_INIT_SENSOR_MIN_UPDATE_MS
TIMEOUT_S = 2.0  # LANDING_TARGET_TIMEOUT_MS
MEASUREMENT_AGE_S = 1.0  # a backend's reading older than this is none
LOST_FOR_GOOD_S = 180.0  # LANDING_TARGET_LOST_TIMEOUT_MS: a target lost this long is never seen
LOST_FAR_M = 30.0  # LANDING_TARGET_LOST_DIST_THRESH_M: nor one lost this far away
LANDING_GAP_S = 0.5  # no landing asked of it this long: the next is a new landing (a mode's init)
SLOW_BAND_M = (0.35, 2.0)  # the target's height within which LAND slows
ACCEPTABLE_ERROR_M = 0.15
SLOWEST_M_S = 0.10


class PrecLand:
    def __init__(self, params):
        self._params = params
        kind = int(params["PLND_TYPE"]) if params["PLND_ENABLED"] else NONE
        self.kind = kind if kind in (MAVLINK, SITL) else NONE  # the backend made at boot
        self.healthy = self.kind == MAVLINK  # a companion's backend is healthy from boot
        self._los: tuple[tuple[float, float, float], float, float] | None = None  # (unit NED, distance, time)
        self._used_los_s = -math.inf
        self._initialised_s: float | None = None  # the estimator's start, or None
        self.acquired = False
        self._last_fused_s = -math.inf
        self.target_ne: tuple[float, float] | None = None  # in the sim's frame
        self.target_height_m = 0.0  # how far below the vehicle, as last measured
        self.ever_seen = False
        self.state = TargetState.NEVER_SEEN  # AC_PrecLand's target state (precland_retry.py)
        self._last_valid_s = -math.inf  # the last update with the target acquired
        self._last_target_ne: tuple[float, float] | None = None  # the target (with its offset) then
        self._last_reading_from_ned = (0.0, 0.0, 0.0)  # where the vehicle was at the last reading
        self.retry = RetryMachine()
        self._landing_called_s = -math.inf
        self._steered_ne: tuple[float, float] | None = None  # the point a landing was last steered to
        self.said_frame = False  # "Plnd: Frame not supported" is said once

    @property
    def enabled(self) -> bool:
        return self.kind != NONE and bool(self._params["PLND_ENABLED"])

    def heard(self, unit_ned: tuple[float, float, float], distance_m: float, now_s: float) -> None:
        """A line of sight to the target (NED, unit length) and the distance along it, 0 unknown."""
        self._los = (unit_ned, distance_m, now_s)

    def update(self, now_s: float, notify, position_ned: tuple[float, float, float],
               rangefinder_m: float | None) -> None:
        """AC_PrecLand::update: a new reading placed and fused; the target's state."""
        los = self._los
        if los is not None and los[2] != self._used_los_s and now_s - los[2] <= MEASUREMENT_AGE_S:
            self._used_los_s = los[2]
            unit, distance, _ = los
            if distance <= 0 and rangefinder_m is not None and rangefinder_m > 0 and unit[2] > 0:
                distance = rangefinder_m / unit[2]  # the rangefinder's height along the line
            if unit[2] > 0 and distance > 0:
                self._fuse(now_s, notify, position_ned, unit, distance)
        if self._initialised_s is not None and not self.acquired:
            if now_s - self._last_fused_s > INIT_GAP_S:
                self._initialised_s = None
                notify("PrecLand: Init Failed", Severity.CRITICAL)
            elif now_s - self._initialised_s > INIT_S:
                self.acquired = True
                notify("PrecLand: Init Complete", Severity.INFO)
        if now_s - self._last_fused_s > TIMEOUT_S and (self.acquired or self._initialised_s is not None):
            if self.acquired:
                notify("PrecLand: Target Lost", Severity.CRITICAL)
            self.acquired, self._initialised_s = False, None
        self._check_target(now_s, position_ned, rangefinder_m)

    def _check_target(self, now_s, position_ned, rangefinder_m) -> None:
        """AC_PrecLand::check_target_status: the target's state after this update."""
        if self.acquired and self.target_ne is not None:
            self.state = TargetState.FOUND
            self._last_valid_s = now_s
            self._last_target_ne = self._offset_target()
            return
        lost = self.state in (TargetState.FOUND, TargetState.RECENTLY_LOST)
        self.state = TargetState.RECENTLY_LOST if lost else TargetState.NEVER_SEEN
        if not self._sensor_in_range(rangefinder_m):
            self.state = TargetState.OUT_OF_RANGE
        elif lost:
            here = position_ned[:2]
            far = max(math.dist(here, self._last_target_ne or here), math.dist(here, self._last_reading_from_ned[:2]))
            if now_s - self._last_valid_s > LOST_FOR_GOOD_S or far > LOST_FAR_M:
                self.state = TargetState.NEVER_SEEN

    def _sensor_in_range(self, rangefinder_m: float | None) -> bool:
        """Whether the sensor should see the target from this height (PLND_ALT_MIN..PLND_ALT_MAX
        on the rangefinder; both 0: always)."""
        low, high = self._params["PLND_ALT_MIN"], self._params["PLND_ALT_MAX"]
        if low == 0 and high == 0:
            return True
        if rangefinder_m is None:
            return False
        return not ((high != 0 and rangefinder_m > high) or (low != 0 and rangefinder_m < low))

    def _fuse(self, now_s, notify, position_ned, unit, distance) -> None:
        self.target_ne = (position_ned[0] + unit[0] * distance, position_ned[1] + unit[1] * distance)
        self.target_height_m = unit[2] * distance
        self._last_fused_s = now_s
        self._last_reading_from_ned = position_ned
        self.ever_seen = True
        if self._initialised_s is None and not self.acquired:
            if int(self._params["PLND_EST_TYPE"]) == 0:
                self.acquired = True  # the raw sensor: no settling, no words
            else:
                self._initialised_s = now_s
                notify("PrecLand: Target Found", Severity.INFO)

    # ----- LAND ------------------------------------------------------------------------------
    def landing(self, now_s: float, notify, rangefinder_m: float | None, position_ned: tuple[float, float, float],
                land_speed_m_s: float) -> Steer:
        """What LAND does with precision landing on (see Steer)."""
        p = self._params
        if now_s - self._landing_called_s > LANDING_GAP_S:  # a landing begun: ArduCopter's mode init
            self.retry.begin()
            self._steered_ne = None
        self._landing_called_s = now_s
        retry_from = self._retry_from()
        action, point = self.retry.update(self.state, now_s, notify, p, self._last_valid_s, retry_from,
                                          position_ned)
        if action == Action.RETRY and point is not None:
            self._steered_ne = point[:2]
            return Steer(self._steered_ne, None, point[2])
        if action == Action.HOLD:
            return Steer(self._steered_ne, 0.0, None)
        if self.acquired and self.target_ne is not None:
            target = self._offset_target()
            self._steered_ne = target
            error = math.hypot(target[0] - position_ned[0], target[1] - position_ned[1])
            xy_max = p["PLND_XY_DIST_MAX"]
            if xy_max > 0 and error > xy_max:
                return Steer(target, 0.0, None)
            low, high = SLOW_BAND_M
            if low < self.target_height_m < high and not int(p["PLND_OPTIONS"]) & 4:
                most = land_speed_m_s / 2
                return Steer(target, max(SLOWEST_M_S, most - error * most / ACCEPTABLE_ERROR_M), None)
            return Steer(target, None, None)
        return Steer(self._steered_ne, None, None)  # down where it was last steered (or LAND's own point)

    def _offset_target(self) -> tuple[float, float]:
        p = self._params
        assert self.target_ne is not None
        return (self.target_ne[0] + p["PLND_LAND_OFS_X"] / 100.0,  # body offsets: heading ignored
                self.target_ne[1] + p["PLND_LAND_OFS_Y"] / 100.0)

    def _retry_from(self) -> tuple[float, float, float]:
        """PLND_RET_BEHAVE's point at the last reading's height: where the vehicle measured the
        target from (0), or the target as last estimated (1)."""
        n, e, d = self._last_reading_from_ned
        if int(self._params["PLND_RET_BEHAVE"]) == 1 and self._last_target_ne is not None:
            return (*self._last_target_ne, d)
        return (n, e, d)


class Steer(NamedTuple):
    """A landing's steer from precision landing: where to fly (None: the landing's own point), the
    descent rate (None: the landing's own; 0 a hold), the height to fly to (down, a retry's)."""
    ne: tuple[float, float] | None
    rate_m_s: float | None
    pos_d: float | None


BODY_FRD, LOCAL_FRD = 12, 20  # the frames a companion's LANDING_TARGET may use


def _body_to_ned(v: tuple[float, float, float], roll: float, pitch: float, yaw: float) -> tuple[float, float, float]:
    cr, sr, cp, sp, cy, sy = math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch), math.cos(yaw), math.sin(yaw)
    x, y, z = v
    return (cp * cy * x + (sr * sp * cy - cr * sy) * y + (cr * sp * cy + sr * sy) * z,
            cp * sy * x + (sr * sp * sy + cr * cy) * y + (cr * sp * sy - sr * cy) * z,
            -sp * x + sr * cp * y + cr * cp * z)


def line_of_sight(frame: int, angle_x: float, angle_y: float, distance: float, xyz: tuple[float, float, float],
                  position_valid: bool, attitude: tuple[float, float, float]
                  ) -> tuple[tuple[float, float, float], float] | None:
    """A LANDING_TARGET as AC_PrecLand_MAVLink reads it: (unit line of sight in NED, distance or 0),
    None when it gives none (a position without a distance). The frame must be BODY_FRD (turned by
    the whole attitude) or LOCAL_FRD (by the heading alone): the caller checks."""
    if position_valid:
        if not distance > 0:
            return None
        vec = (xyz[0] / distance, xyz[1] / distance, xyz[2] / distance)
    else:
        vec = (-math.tan(angle_y), math.tan(angle_x), 1.0)
    length = math.sqrt(vec[0] ** 2 + vec[1] ** 2 + vec[2] ** 2)
    if not (math.isfinite(length) and length > 0):
        return None
    vec = (vec[0] / length, vec[1] / length, vec[2] / length)
    roll, pitch, yaw = attitude
    ned = _body_to_ned(vec, roll, pitch, yaw) if frame == BODY_FRD else _body_to_ned(vec, 0.0, 0.0, yaw)
    return ned, distance if distance > 0 and math.isfinite(distance) else 0.0

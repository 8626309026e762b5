"""The geofence's breaches, as ArduCopter keeps them (AC_Fence::check) and answers them (fence.cpp).

Each enabled fence is checked on its own and a breach is kept per fence until the vehicle is back
inside: "<fences> breached" is said for a new one, "Fence breach cleared" once none is left. A
breach of the ceiling or the circle also sets a second fence 20 m further out; crossing that is a
new breach again (its action again). FENCE_ACTION answers a new breach while armed: on the ground,
or with the throttle closed in a manual-throttle mode below the ceiling, it disarms; more than
100 m outside it lands; otherwise RTL, LAND, SMART_RTL, BRAKE or SMART_RTL-or-LAND, each falling
back as ArduCopter's does. Any mode change during a breach (the action's own too) starts ten
seconds of "manual recovery" in which no new breach is answered. A breach is not a failsafe in
the heartbeat's sense (ArduCopter's any_failsafe_triggered leaves the fence out).
"""
from __future__ import annotations

import math
from collections.abc import Sequence

from ..modes.numbers import ModeNumber
from ..results import Result, Severity
from ..views import FailsafeView
from .fence_shapes import Shape, breached_shapes, closest_point
from .fence_switch import ALT_MAX, ALT_MIN, CIRCLE, POLYGON, fence_names

BACKUP_M = 20.0  # AC_FENCE_ALT_MAX/MIN_BACKUP_DISTANCE and a copter's AC_FENCE_CIRCLE_RADIUS_BACKUP_DISTANCE
GIVE_UP_M = 100.0  # AC_FENCE_GIVE_UP_DISTANCE: this far outside, land where it is
MANUAL_RECOVERY_S = 10.0  # AC_FENCE_MANUAL_RECOVERY_TIME_MIN
REPORT_ONLY, RTL_AND_LAND, ALWAYS_LAND, SMART_RTL, BRAKE, SMART_RTL_OR_LAND = range(6)  # FENCE_ACTION
RTL, LAND = ModeNumber.RTL, ModeNumber.LAND
# FENCE_ACTION -> the modes tried in turn (fence.cpp's fence_check); anything else is RTL_AND_LAND
ACTION_MODES: dict[int, tuple[ModeNumber, ...]] = {
    RTL_AND_LAND: (RTL, LAND), ALWAYS_LAND: (LAND,), SMART_RTL: (ModeNumber.SMART_RTL, RTL, LAND),
    BRAKE: (ModeNumber.BRAKE, LAND), SMART_RTL_OR_LAND: (ModeNumber.SMART_RTL, LAND)}


def _distance_outside(shape: Shape, p: tuple[float, float]) -> float:
    """How far past a breached shape's boundary the point is [m]."""
    if shape.kind == "circle":
        n, e, radius = shape.circle
        return abs(math.hypot(p[0] - n, p[1] - e) - radius)
    vertices = shape.vertices
    return min(math.hypot(q[0] - p[0], q[1] - p[1])
               for q in (closest_point(p, vertices[i], vertices[(i + 1) % len(vertices)])
                         for i in range(len(vertices))))


def destination_within_fence(enabled: int, params, shapes: Sequence[Shape], home: tuple[float, float, float],
                             point: tuple[float, float, float]) -> bool:
    """Whether a GUIDED destination (local NED) lies within every enabled fence, which ArduCopter
    asks before it takes one (AC_Fence::check_destination_within_fence): below the ceiling, above
    the floor, within FENCE_RADIUS of home, inside the inclusion and outside the exclusion shapes."""
    height = home[2] - point[2]
    if enabled & ALT_MAX and height > params["FENCE_ALT_MAX"]:
        return False
    if enabled & ALT_MIN and height < params["FENCE_ALT_MIN"]:
        return False
    if enabled & CIRCLE and math.hypot(point[0] - home[0], point[1] - home[1]) > params["FENCE_RADIUS"]:
        return False
    return not (enabled & POLYGON and breached_shapes(shapes, (point[0], point[1])))


class FenceBreach:
    __slots__ = ("breaches", "count", "time_ms", "_backups", "_distances", "_recovery_from_s")

    def __init__(self) -> None:
        self.breaches = 0  # AC_FENCE_TYPE_* bits of the fences breached now
        self.count = 0  # breaches since boot (FENCE_STATUS), new fences and backup fences alike
        self.time_ms = 0  # boot time of the first breach of the present run of breaches
        self._backups: dict[int, float] = {}  # per fence, how far past it a new breach is told again [m]
        self._distances: dict[int, float] = {}  # how far outside each fence [m] (negative: inside)
        self._recovery_from_s: float | None = None

    # ----- AC_Fence::check -------------------------------------------------------------------------
    def check(self, v: FailsafeView, now_s: float) -> int:
        """The fences breached anew (bits), the kept breaches brought up to date."""
        p = v.params
        configured = int(p["FENCE_TYPE"])
        self.breaches &= configured
        enabled = v.fence.enabled_fences
        if not configured or not (enabled or self.breaches):  # (most vehicles: no fence, nothing kept)
            return 0
        b = v.body
        home = v.home_ned or (0.0, 0.0, 0.0)
        height = home[2] - b.d_m
        new = 0
        if enabled & ALT_MAX:
            new |= self._check_limit(ALT_MAX, height - p["FENCE_ALT_MAX"], now_s)
        if enabled & ALT_MIN:
            new |= self._check_limit(ALT_MIN, p["FENCE_ALT_MIN"] - height, now_s)
        if enabled & CIRCLE:
            new |= self._check_limit(CIRCLE, math.hypot(b.n_m - home[0], b.e_m - home[1]) - p["FENCE_RADIUS"], now_s)
        shapes = v.fence_shapes() if enabled & POLYGON else ()
        if shapes:
            new |= self._check_polygons(shapes, (b.n_m, b.e_m), now_s)
        else:
            self.breaches &= ~POLYGON
        if self._recovery_from_s is not None:
            if now_s - self._recovery_from_s < MANUAL_RECOVERY_S:
                return 0  # the pilot is bringing it back: nothing is answered
            self._recovery_from_s = None
        return new

    def _record(self, fence: int, now_s: float) -> int:
        if not self.breaches:
            self.time_ms = int(now_s * 1000)
        self.count = min(self.count + 1, 65500)
        self.breaches |= fence
        return fence

    def _check_limit(self, fence: int, beyond_m: float, now_s: float) -> int:
        """The ceiling, the floor or the circle, `beyond_m` past it (negative: inside): a breach
        kept until back inside, and a new one each time past the backup fence set 20 m further
        out (check_fence_alt_max / _alt_min / _circle)."""
        self._distances[fence] = beyond_m
        if beyond_m >= 0.0:
            backup = self._backups.get(fence)
            if not self.breaches & fence or (backup is not None and beyond_m >= backup):
                self._backups[fence] = beyond_m + BACKUP_M
                return self._record(fence, now_s)
            return 0
        if self.breaches & fence:
            self.breaches &= ~fence
            self._backups.pop(fence, None)
        return 0

    def _check_polygons(self, shapes: Sequence[Shape], here: tuple[float, float], now_s: float) -> int:
        outside = breached_shapes(shapes, here)
        if outside:
            self._distances[POLYGON] = max(_distance_outside(s, here) for s in outside)
            return 0 if self.breaches & POLYGON else self._record(POLYGON, now_s)
        self._distances[POLYGON] = 0.0
        self.breaches &= ~POLYGON
        return 0

    def distance_outside(self, fences: int) -> float:
        """The farthest the vehicle is outside any of `fences` (AC_Fence::get_breach_distance)."""
        return max((d for bit, d in self._distances.items() if fences & bit), default=-math.inf)

    # ----- ArduCopter's answer -------------------------------------------------------------------
    def update(self, v: FailsafeView, now_s: float, radio_failsafe: bool) -> None:
        """A check and its answer (Copter::fence_checks_async and fence_check)."""
        before = self.breaches
        new = self.check(v, now_s)
        if not new and before and not self.breaches and not v.landed:
            v.notify("Fence breach cleared", Severity.NOTICE)
        if not new or not v.armed:
            return
        if not v.landed:
            v.notify(f"{fence_names(new)} breached", Severity.NOTICE)
        action = int(v.params["FENCE_ACTION"])
        if action == REPORT_ONLY:
            return
        if v.landed or (v.mode_manual_throttle and v.pilot.throttle <= 0.0 and not radio_failsafe
                        and not self.breaches & ALT_MAX):
            v.disarm("fence breach", force=True)
            return
        modes = (LAND,) if self.distance_outside(new) > GIVE_UP_M else ACTION_MODES.get(action, (RTL, LAND))
        for mode in modes:
            if v.set_mode(mode) == Result.ACCEPTED:
                return

    def mode_changed(self, v: FailsafeView, now_s: float) -> None:
        """A mode change during a breach is the pilot taking over (AC_Fence::manual_recovery_start),
        unless the fence only reports."""
        if self.breaches and int(v.params["FENCE_ACTION"]) != REPORT_ONLY:
            self._recovery_from_s = now_s
            v.notify("Manual recovery started", Severity.INFO)

"""SMART_RTL: fly home back along the way the vehicle came (return_path.py), then land as RTL's last
stages do (ArduCopter's ModeSmartRTL).

Stages, as ArduCopter's: hold where the vehicle can stop while the path is cleaned up (simplified,
loops cut out); follow it point by point from the newest, flying through each point to the next
(the waypoint navigator, as AUTO's legs); the last point (home) is flown to 2 m above it; then
land there (or, with RTL_ALT_FINAL set, come down to that height and stay). Refused ("init
failed") when no path is kept: SRTL_POINTS 0, no position since boot, or the path given up.

As ArduCopter's, it runs its navigation even on the ground: entered armed and landed it climbs
to 2 m over the point it armed at, which ArduCopter's land detector reports as an internal error
(declared here: climbs_without_takeoff).
"""
from __future__ import annotations

from ..results import Severity
from ..views import Vector3
from .base import Mode, Setpoint, stopping_point
from .context import ModeContext
from .land import descend_and_disarm, descent_rate_m_s
from .numbers import ModeNumber
from .waypoint_legs import WaypointLegs

ABOVE_HOME_M = 2.0  # the last point is flown to this far above home before landing
CLEANUP, FOLLOW, PRELAND, DESCEND, LAND = "CLEANUP", "FOLLOW", "PRELAND", "DESCEND", "LAND"


class SmartRtl(Mode):
    number = ModeNumber.SMART_RTL
    text_name = "SMARTRTL"
    plans_paths = True
    requires_position = True
    climbs_without_takeoff = True
    stage: str
    _legs: WaypointLegs
    _reached: bool
    _unreached: Vector3 | None  # the point being flown to, put back on the path if the mode ends
    _final_d: float

    def __init__(self) -> None:
        self.stage = CLEANUP
        self._legs = WaypointLegs(self.plans_paths)

    def enter(self, ctx: ModeContext) -> str | None:
        if not ctx.return_path.active:
            return "init failed"
        (n, e), d = stopping_point(ctx)
        self._legs = WaypointLegs(self.plans_paths)
        self._legs.begin(ctx, (n, e, d), None)
        self._reached = False
        self._unreached = None
        self.stage = CLEANUP
        return None

    def exit(self, ctx: ModeContext) -> None:
        if self.stage == FOLLOW and self._unreached is not None and not ctx.return_path.add_back(self._unreached):
            ctx.notify("SmartRTL: lost one point", Severity.ERROR)
        self._unreached = None

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        sp.clear()
        if self.stage == CLEANUP:
            ctx.return_path.thorough_cleanup()
            self.stage = FOLLOW
        elif self.stage == FOLLOW and self._reached:
            self._next_point(ctx)
        elif self.stage == PRELAND and self._reached:
            final_m = ctx.params["RTL_ALT_FINAL"] / 100.0
            self._final_d = ctx.height_ref_d - final_m
            self.stage = LAND if final_m <= 0 else DESCEND
        if self.stage in (LAND, DESCEND):
            self._land(ctx, sp)
            return
        sp.speed_xy = ctx.nav_speed_m_s
        self._reached = self._legs.update(ctx, sp, dt)

    def _next_point(self, ctx: ModeContext) -> None:
        """The point reached: on to the next one on the path, flying through this one."""
        path = ctx.return_path
        self._unreached = None
        point = path.pop()
        if point is None:  # never without a point left (home stays to the end): land here
            self.stage = PRELAND
            return
        self._unreached = point
        if not path.points:
            self.stage = PRELAND
            self._legs.begin(ctx, _above(point), None)
            return
        following = path.peek()
        if following is not None and len(path.points) == 1:
            following = _above(following)
        self._legs.begin(ctx, point, following)

    def _land(self, ctx: ModeContext, sp: Setpoint) -> None:
        """RTL's last stages over the last point: land and disarm, or come down to RTL_ALT_FINAL."""
        dest = self._legs.destination
        if dest is not None and not ctx.landed:
            sp.pos_ne = (dest[0], dest[1])
        if self.stage == DESCEND:
            sp.pos_d = self._final_d
            sp.speed_dn = descent_rate_m_s(ctx)
            return
        descend_and_disarm(ctx, sp)

    def destination(self) -> tuple[float, float, float | None] | None:
        return None if self.stage == LAND else self._legs.destination

    def nav_distance_bearing(self) -> tuple[float, float] | None:
        """While a path round the fence is flown: the way to the point, not the corner."""
        return self._legs.way_to_final() if self.stage != LAND and self._legs.avoiding else None

    def landed_state_hint(self, ctx: ModeContext) -> str | None:
        return "LANDING" if self.stage == LAND and not ctx.landed else None


def _above(point: Vector3) -> Vector3:
    return point[0], point[1], point[2] - ABOVE_HOME_M

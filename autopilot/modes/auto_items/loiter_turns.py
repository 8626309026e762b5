"""NAV_LOITER_TURNS (18): circle the item's point a number of turns, as ArduCopter's AUTO does with
its circle navigator (circle_nav.py, shared with CIRCLE mode).

The item as AP_Mission stores it: param 1 the turns (a whole number up to 255, or a fraction
below 1 in 256ths), param 3 the radius in whole metres (above 255 m in tens of metres), its sign
the direction (negative: counter-clockwise). A radius of 0 keeps the radius the last such item
set (0 after boot: the vehicle turns on the spot). The rate is the size of CIRCLE_RATE's default
(ArduCopter's AC_Circle copies it when built: a CIRCLE_RATE set later is not flown here), signed
by the direction. More than 3 m from the centre, the vehicle first flies a waypoint leg to the nearest
point of the circle at the item's height (nose along the leg from outside the circle, else held);
then it circles from where it is, holding that height, and says "Mission: starting circle k/n"
as each turn begins. Done (reported reached, with no "Reached command" text) once the turns are
flown: 0 turns is done as soon as the circle begins.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ...views import Vector3
from ..base import Setpoint, stopping_point
from ..circle_nav import CircleNav
from ..context import ModeContext
from ..waypoint_legs import WaypointLegs
from . import AutoItem

if TYPE_CHECKING:
    from ...mission.store import MissionItem
    from ..auto import Auto

TO_EDGE_MIN_M = 3.0  # closer than this to the centre, the circle starts at once
FACE_LEG_MIN_M = 5.0  # flying in from outside the circle and further than this: nose along the leg
FACE_TRAVEL = 2  # CIRCLE_OPTIONS bit 1


def turns_of(p1: float) -> float:
    """Param 1 as AP_Mission stores it: whole turns in a byte, or 256ths of a turn below 1."""
    if not math.isfinite(p1) or p1 <= 0:
        return 0.0
    if p1 < 1:
        return int(p1 * 256.0) / 256.0
    return float(int(min(p1, 255.0)))


def radius_of(p3: float) -> float:
    """Param 3's size as AP_Mission stores it: whole metres, or tens of metres above 255."""
    size = abs(p3) if math.isfinite(p3) else 0.0
    if size <= 255:
        return float(int(size))
    return float(int(min(255.0, size * 0.1))) * 10.0


class LoiterTurns(AutoItem):
    _auto: Auto
    _index: int
    _turns: float
    _circle: CircleNav
    _to_edge: WaypointLegs | None  # flying to the circle's edge; None once circling
    _edge_yaw: float | None  # the nose held on the way to the edge (None: along the leg)
    _hold_d: float
    _last_announced: int

    def start(self, auto: Auto, ctx: ModeContext, index: int, item: MissionItem) -> bool:
        self._auto, self._index = auto, index
        self._turns = turns_of(item.p1)
        radius = radius_of(item.p3)
        if radius > 0:
            auto.circle_radius_m = radius
        rate = abs(auto.circle_rate_deg_s)
        cn, ce, cd = auto.item_position(ctx, item)
        if item.z == 0:  # no altitude given: the present one
            cd = ctx.body.d_m
        self._circle = CircleNav((cn, ce), auto.circle_radius_m, -rate if item.p3 < 0 else rate, 0.0)
        self._hold_d = cd
        self._last_announced = -1
        self._to_edge, self._edge_yaw = None, None
        edge, dist = self._closest_point(ctx, cd)
        if dist > TO_EDGE_MIN_M:
            legs = self._to_edge = WaypointLegs()
            legs.begin(ctx, edge, None)
            b = ctx.body
            from_centre = math.hypot(b.n_m - cn, b.e_m - ce)
            if not (from_centre > self._circle.radius_m and from_centre > FACE_LEG_MIN_M):
                self._edge_yaw = ctx.attitude[2]
        else:
            self._begin_circle(ctx)
        return True

    def _closest_point(self, ctx: ModeContext, centre_d: float) -> tuple[Vector3, float]:
        """The point of the circle nearest where the vehicle can stop, and that stopping point's
        distance from the centre (in 3D: a height to change brings the point inwards, as
        ArduCopter's, which divides by the 3D distance)."""
        (sn, se), sd = stopping_point(ctx)
        circle = self._circle
        cn, ce = circle.centre
        vn, ve, vd = sn - cn, se - ce, sd - centre_d
        dist = math.sqrt(vn * vn + ve * ve + vd * vd)
        r = circle.radius_m
        if r <= 0:
            return (cn, ce, centre_d), dist
        if dist == 0:
            yaw = ctx.attitude[2]
            return (cn - r * math.cos(yaw), ce - r * math.sin(yaw), centre_d), dist
        return (cn + vn / dist * r, ce + ve / dist * r, centre_d), dist

    def _begin_circle(self, ctx: ModeContext) -> None:
        """Circle from where the vehicle can stop: the angle from the centre to it (behind the
        nose when it is at the centre), the height held."""
        self._to_edge = None
        circle = self._circle
        (sn, se), sd = stopping_point(ctx)
        cn, ce = circle.centre
        if circle.radius_m <= 0:
            circle.angle = ctx.attitude[2]
        elif sn == cn and se == ce:
            circle.angle = ctx.attitude[2] - math.pi
        else:
            circle.angle = math.atan2(se - ce, sn - cn)
        circle.angular_vel = circle.angle_total = 0.0
        self._hold_d = sd

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        legs = self._to_edge
        if legs is not None:
            legs.update(ctx, sp, dt)
            if self._edge_yaw is not None:
                sp.yaw = self._edge_yaw
            return
        params = ctx.params
        circle = self._circle
        circle.advance(params, dt)
        b = ctx.body
        # The point alone, no velocity along the circle, as ArduCopter's circle navigator.
        sp.pos_ne = circle.point()
        sp.pos_d = self._hold_d
        sp.yaw = circle.heading(b.n_m, b.e_m, bool(int(params["CIRCLE_OPTIONS"]) & FACE_TRAVEL),
                                params["ATC_ANG_YAW_P"])

    def done(self, ctx: ModeContext) -> bool:
        legs = self._to_edge
        if legs is not None:
            if legs.nav is not None and legs.nav.reached:
                self._begin_circle(ctx)
            return False
        completed = abs(self._circle.angle_total) / (2 * math.pi)
        if int(completed) != self._last_announced:
            self._last_announced = int(completed)
            ctx.notify(f"Mission: starting circle {int(completed) + 1}/{int(self._turns)}")
        return completed >= self._turns

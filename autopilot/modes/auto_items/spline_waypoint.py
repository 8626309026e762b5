"""NAV_SPLINE_WAYPOINT (82): fly to the item's point along a spline (control/spline.py), as
ArduCopter's AUTO does with its wp_nav.

The curve starts where the leg before ended (a waypoint or spline reached), else where the vehicle
can stop; it leaves that point along the leg that came in (a spline's exit vector, a straight
leg's chord), or from rest. With no hold time (param 1) and a navigation item after it, the curve
arrives moving towards that item's point (from this leg's origin when that item is a spline too,
as ArduCopter's set_spline_destination), and the point counts as reached when the target gets
there; otherwise it stops there and is reached within WPNAV_RADIUS. Then param 1's whole seconds
are held and "Reached command #n" said. Lat/lon 0 is where the leg starts; altitude 0 its height.

Where Firefly differs: a plain waypoint before a spline stops at its point (ArduCopter passes it
at the speed the spline starts with), so the curve's shape is the same but it starts from rest.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ...control.spline import SplineLeg
from ...control.wpnav import WaypointNav
from ...views import Vector3
from ..auto_yaw import AutoYaw
from ..base import Setpoint, stopping_point
from ..context import ModeContext
from ..waypoint_legs import next_nav_index
from . import AutoItem

if TYPE_CHECKING:
    from ...mission.store import MissionItem
    from ..auto import Auto

CMD_NAV_SPLINE_WAYPOINT = 82


def _minus(a: Vector3, b: Vector3) -> Vector3:
    return a[0] - b[0], a[1] - b[1], a[2] - b[2]


def _position(auto: Auto, ctx: ModeContext, item: MissionItem, default: Vector3) -> Vector3:
    """The item's point; lat/lon 0 and altitude 0 taken from `default` (ArduCopter's loc_from_cmd)."""
    n, e, d = auto.item_position(ctx, item)
    if item.x == 0 and item.y == 0:
        n, e = default[0], default[1]
    if item.z == 0:
        d = default[2]
    return n, e, d


class SplineWaypoint(AutoItem):
    _index: int
    _leg: SplineLeg
    _fast: bool  # flown through towards the next item: reached when the target arrives
    _hold_s: float
    _reached_at: float | None
    _said: bool
    _pos: Vector3  # the target now, and its velocity
    _vel: Vector3
    _yaw: AutoYaw

    def start(self, auto: Auto, ctx: ModeContext, index: int, item: MissionItem) -> bool:
        self._index = index
        b = ctx.body
        previous = auto.previous_nav
        origin: Vector3
        origin_vec: Vector3 = (0.0, 0.0, 0.0)
        self._vel = (0.0, 0.0, 0.0)
        self._yaw = AutoYaw()
        if isinstance(previous, SplineWaypoint) and previous._leg.reached:
            origin = previous._leg.destination
            if previous._fast:
                origin_vec, self._vel = previous._leg.exit_vec, previous._vel
            self._yaw = previous._yaw
        elif isinstance(previous, WaypointNav) and previous.reached:
            origin = previous.destination
            origin_vec = _minus(origin, previous.origin)
            self._vel = previous.vel
        else:
            (n, e), _ = stopping_point(ctx)
            origin = (n, e, b.d_m)
        destination = _position(auto, ctx, item, origin)
        self._hold_s = float(int(item.p1)) if math.isfinite(item.p1) and item.p1 > 0 else 0.0
        destination_vec: Vector3 = (0.0, 0.0, 0.0)
        mission = ctx.mission_progress
        items = mission.items()
        following = next_nav_index(items, index, mission.jumps_followed()) if self._hold_s == 0 else None
        if following is not None:
            after = items[following]
            next_point = _position(auto, ctx, after, destination)
            from_point = origin if after.command == CMD_NAV_SPLINE_WAYPOINT else destination
            destination_vec = _minus(next_point, from_point)
        self._fast = any(destination_vec)
        params = ctx.params
        self._leg = SplineLeg(origin, destination, origin_vec, destination_vec, ctx.nav_speed_m_s,
                              params["WPNAV_SPEED_UP"] / 100.0, params["WPNAV_SPEED_DN"] / 100.0,
                              params["WPNAV_ACCEL"] / 100.0, params["WPNAV_ACCEL_Z"] / 100.0)
        self._pos = origin
        self._reached_at, self._said = None, False
        return True

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        leg = self._leg
        if not leg.reached:
            vn, ve, vd = self._vel
            self._pos, self._vel = leg.advance(dt, math.sqrt(vn * vn + ve * ve + vd * vd))
        elif not self._fast:
            self._pos, self._vel = leg.destination, (0.0, 0.0, 0.0)
        p, v = self._pos, self._vel
        sp.pos_ne, sp.vel_ne, sp.accel_ne = (p[0], p[1]), (v[0], v[1]), (0.0, 0.0)
        sp.pos_d, sp.vel_d = p[2], v[2]
        sp.yaw = self._yaw.facing(ctx, v[0], v[1])
        if self._reached_at is None and leg.reached:
            b = ctx.body
            d = leg.destination
            radius = ctx.params["WPNAV_RADIUS"] / 100.0
            if self._fast or (b.n_m - d[0]) ** 2 + (b.e_m - d[1]) ** 2 + (b.d_m - d[2]) ** 2 <= radius * radius:
                self._reached_at = ctx.time_s

    def done(self, ctx: ModeContext) -> bool:
        if self._reached_at is None or ctx.time_s - self._reached_at < self._hold_s:
            return False
        if not self._said:
            self._said = True
            ctx.notify(f"Reached command #{self._index + 1}")
        return True

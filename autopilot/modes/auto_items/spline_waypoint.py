"""NAV_SPLINE_WAYPOINT (82): fly to the item's point along a spline (control/spline.py), as
ArduCopter's AUTO does with its wp_nav.

The curve starts where the leg before ended (a waypoint or spline reached), else where the vehicle
can stop; it leaves that point along the leg that came in when that leg was flown through (a
spline's exit vector, a straight leg's chord), or from rest. A plain waypoint without a hold
before it is passed at the speed the curve can start with (its straight leg ends at that speed:
entry_speed, as ArduCopter's set_spline_destination_next). With no hold time (param 1) and a
navigation item after it, the curve arrives moving towards that item's point (from this leg's
origin when that item is a spline too, as ArduCopter's set_spline_destination), and the point
counts as reached when the target gets there; a straight leg after it then starts at the speed
the target arrives with (hand_over), no faster than that leg cruises. Otherwise it stops there
and is reached within WPNAV_RADIUS. Then param 1's whole seconds are held and "Reached command
#n" said. Lat/lon 0 is where the leg starts; altitude 0 its height.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ...control.spline import SplineLeg
from ...control.wpnav import NavLimits, WaypointNav
from ...views import Vector3
from ..auto_yaw import AutoYaw
from ..base import Setpoint, stopping_point
from ..context import ModeContext
from ..waypoint_legs import NAV_BY_LEGS, next_nav_index
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


def _hold_s(item: MissionItem) -> float:
    return float(int(item.p1)) if math.isfinite(item.p1) and item.p1 > 0 else 0.0


def _leg(auto: Auto, ctx: ModeContext, index: int, item: MissionItem, origin: Vector3,
         origin_vec: Vector3) -> SplineLeg:
    """The curve of spline item `index` from `origin`, leaving it along `origin_vec`, arriving
    towards the next navigation item's point when it has no hold time (ArduCopter's
    get_spline_from_cmd)."""
    destination = _position(auto, ctx, item, origin)
    destination_vec: Vector3 = (0.0, 0.0, 0.0)
    mission = ctx.mission_progress
    items = mission.items()
    following = next_nav_index(items, index, mission.jumps_followed()) if _hold_s(item) == 0 else None
    if following is not None:
        after = items[following]
        next_point = _position(auto, ctx, after, destination)
        from_point = origin if after.command == CMD_NAV_SPLINE_WAYPOINT else destination
        destination_vec = _minus(next_point, from_point)
    params = ctx.params
    leg = SplineLeg(origin, destination, origin_vec, destination_vec, ctx.nav_speed_m_s,
                    params["WPNAV_SPEED_UP"] / 100.0, params["WPNAV_SPEED_DN"] / 100.0,
                    params["WPNAV_ACCEL"] / 100.0, params["WPNAV_ACCEL_Z"] / 100.0)
    if following is not None and items[following].command in NAV_BY_LEGS and leg.destination_speed_max > 0.0:
        # The straight leg after it starts no faster than it cruises (ArduCopter's
        # set_wp_destination_next: the S-curve's set_origin_speed_max caps the spline's end).
        next_point = (destination[0] + destination_vec[0], destination[1] + destination_vec[1],
                      destination[2] + destination_vec[2])
        straight = NavLimits(params, ctx.nav_speed_m_s).leg(destination, next_point)
        leg.destination_speed_max = min(leg.destination_speed_max, straight.peak)
    return leg


def entry_speed(auto: Auto, ctx: ModeContext, index: int, came_from: Vector3, origin: Vector3) -> float:
    """The speed spline item `index` can start with at `origin`, reached along a straight leg
    from `came_from`: the waypoint at `origin` is passed at that speed."""
    item = ctx.mission_progress.items()[index]
    return _leg(auto, ctx, index, item, origin, _minus(origin, came_from)).origin_speed_max


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
            if previous.destination_speed > 0.0:  # passed, not stopped at
                origin_vec = _minus(origin, previous.origin)
                self._vel = previous.vel
        else:
            (n, e), _ = stopping_point(ctx)
            origin = (n, e, b.d_m)
        self._hold_s = _hold_s(item)
        self._leg = _leg(auto, ctx, index, item, origin, origin_vec)
        self._fast = any(self._leg.destination_vec)
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

    def hand_over(self) -> tuple[Vector3, Vector3] | None:
        if self._fast and self._leg.reached:
            return self._leg.destination, self._vel
        return None

    def done(self, ctx: ModeContext) -> bool:
        if self._reached_at is None or ctx.time_s - self._reached_at < self._hold_s:
            return False
        if not self._said:
            self._said = True
            ctx.notify(f"Reached command #{self._index + 1}")
        return True

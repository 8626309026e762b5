"""Waypoint legs flown round the fence by the path planner, as ArduCopter's AC_WPNav_OA flies them.

Every tick the leg's destination (and the next one) is put to the planner (path_planning/), which
answers:
- not required: the leg flies to its own destination (set again if a corner was flown before it);
  when the way on to the next destination crosses the fence, it stops there;
- success: the destination is replaced by the planner's corner, its height taken along the leg
  from the origin to the destination, and flown to as a leg of its own (through it to the next
  corner with OA_OPTIONS' fast waypoints);
- success from BendyRuler: its point, at the height the leg has abreast of the vehicle (the
  vertical search's own height), goes to the position controller itself (AC_WPNav_OA hands it to
  input_pos_NEU_cm, not to the waypoint navigator): the target runs to it within the navigator's
  speeds and accelerations and PSC_JERK_XY / PSC_JERK_Z (position_target.py), the point moving on
  at each plan. When BendyRuler is done the navigator starts afresh from where the vehicle can
  stop (ArduCopter's navigator went unupdated meanwhile);
- processing (a new destination not planned yet) or an error (no path): the vehicle stops where
  it can and holds there; with fast waypoints it flies on while processing.
The leg counts as reached only when no avoidance is needed any more.
"""
from __future__ import annotations

import math

from ..control.wpnav import WaypointNav
from ..path_planning.planner import ERROR, FAST_WAYPOINTS, NOT_REQUIRED, PROCESSING, SUCCESS, Answer
from ..views import Vector3
from .base import Setpoint
from .context import ModeContext
from .position_target import PositionTarget

Vec2 = tuple[float, float]


def _height_along(point: Vec2, origin: Vector3, destination: Vector3) -> Vector3:
    """`point` with the height the leg origin-destination has abreast of it
    (Location::linearly_interpolate_alt)."""
    dn, de = destination[0] - origin[0], destination[1] - origin[1]
    span = dn * dn + de * de
    share = 1.0 if span < 0.001 else ((point[0] - origin[0]) * dn + (point[1] - origin[1]) * de) / span
    share = min(max(share, 0.0), 1.0) if math.isfinite(share) else 1.0
    return point[0], point[1], origin[2] + (destination[2] - origin[2]) * share


JERK_XY_DEFAULT_M_S3 = 5.0  # PSC_JERK_XY's default


class LegAvoidance:
    __slots__ = ("state", "oa_destination", "_origin", "_destination", "_next", "_bendy", "_bendy_point")

    def __init__(self) -> None:
        self.state = NOT_REQUIRED
        self.oa_destination: Vec2 | None = None  # the corner being flown to
        # The leg the mode set, kept while the planner's corners replace its destination
        self._origin: Vector3 = (0.0, 0.0, 0.0)
        self._destination: Vector3 = (0.0, 0.0, 0.0)
        self._next: Vector3 | None = None
        # BendyRuler's: the position controller's target and the point (north, east, up) it runs
        # to; None while the navigator flies
        self._bendy: PositionTarget | None = None
        self._bendy_point: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def reset(self) -> None:
        """The mode set a new destination: planning starts again from it."""
        self.state = NOT_REQUIRED
        self._bendy = None

    @property
    def bendy(self) -> bool:
        """BendyRuler's point is flown: the position controller, not the navigator, has the target."""
        return self._bendy is not None

    @property
    def bendy_point(self) -> Vector3 | None:
        """BendyRuler's point being flown to (local NED), while it flies: what ArduCopter reports
        as the target (AC_WPNav_OA::get_oa_wp_destination)."""
        if self._bendy is None:
            return None
        n, e, up = self._bendy_point
        return n, e, -up

    def destination(self, nav: WaypointNav) -> Vector3:
        """The destination the mode set (not the corner flown to)."""
        return nav.destination if self.state == NOT_REQUIRED else self._destination

    def steer(self, ctx: ModeContext, nav: WaypointNav) -> None:
        """Ask the planner about the leg and fly what it answers (AC_WPNav_OA::update_wpnav)."""
        if self.state == NOT_REQUIRED:
            self._origin, self._destination, self._next = nav.origin, nav.destination, nav.next_destination
        planner, b = ctx.path_planner, ctx.body
        following = None if self._next is None else (self._next[0], self._next[1])
        home = ctx.home_ned
        answer = planner.avoid(ctx.time_s, (b.n_m, b.e_m), (self._destination[0], self._destination[1]), following,
                               (b.vn_m_s, b.ve_m_s), math.degrees(ctx.attitude[2]),
                               (0.0, 0.0, 0.0) if home is None else (home[0], home[1], -home[2]), -b.d_m)
        fast = bool(planner.options & FAST_WAYPOINTS)
        if answer.state == SUCCESS and answer.bendy and answer.destination is not None:
            self._fly_bendy(nav, answer, (b.n_m, b.e_m))
            return
        target = self._bendy
        if target is not None:  # BendyRuler is done: the navigator takes the target back
            (pn, pe), (vn, ve), (an, ae) = target.pos_ne, target.vel_ne, target.accel_ne
            nav.take_over((pn, pe, -target.pos_up), (vn, ve, -target.vel_up), (an, ae, -target.accel_up),
                          ((b.n_m, b.e_m, b.d_m), (b.vn_m_s, b.ve_m_s, b.vd_m_s)))
            self._bendy = None
        if answer.state == NOT_REQUIRED:
            if self.state != NOT_REQUIRED:
                nav.set_destination(self._destination, self._next if answer.dest_to_next_clear and fast else None)
                self.state = NOT_REQUIRED
            if not answer.dest_to_next_clear:
                nav.stop_at_destination()
        elif answer.state == SUCCESS:
            self._fly_corner(nav, answer, fast)
        elif not (answer.state == PROCESSING and fast) and self.state not in (PROCESSING, ERROR):
            point = nav.stopping_point()  # processing or an error: stop, and hold there
            nav.set_destination(point)
            self.oa_destination, self.state = (point[0], point[1]), answer.state

    def _fly_bendy(self, nav: WaypointNav, answer: Answer, here: Vec2) -> None:
        if self._bendy is None:  # the target goes on from the navigator's
            (pn, pe, pd), (vn, ve, vd), (an, ae, ad) = nav.pos, nav.vel, nav.accel
            self._bendy = PositionTarget((pn, pe, -pd), (vn, ve, -vd), (an, ae, -ad))
        point = answer.destination
        assert point is not None
        up = answer.height
        if up is None:  # the horizontal search: the leg's height abreast of the vehicle
            up = -_height_along(here, self._origin, self._destination)[2]
        self._bendy_point = (point[0], point[1], up)
        self.state, self.oa_destination = SUCCESS, point

    def fly_bendy(self, ctx: ModeContext, nav: WaypointNav, sp: Setpoint, dt: float) -> None:
        """Move the position controller's target towards BendyRuler's point (input_pos_NEU_cm)
        and put it in the setpoint."""
        target = self._bendy
        if target is None:
            return
        lim, params = nav.limits, ctx.params
        target.run_to(self._bendy_point, dt, (lim.speed_xy, lim.speed_up, lim.speed_down), lim.accel_xy,
                      params.get("PSC_JERK_XY", JERK_XY_DEFAULT_M_S3), lim.accel_z, params["PSC_JERK_Z"])
        sp.pos_ne, sp.vel_ne, sp.accel_ne = target.pos_ne, target.vel_ne, target.accel_ne
        sp.pos_d, sp.vel_d = -target.pos_up, -target.vel_up

    def _fly_corner(self, nav: WaypointNav, answer: Answer, fast: bool) -> None:
        corner = answer.destination
        if corner is None or (self.state == SUCCESS and self.oa_destination is not None
                              and math.dist(corner, self.oa_destination) < 0.01):
            return
        after = answer.next_destination if fast else None
        nav.set_destination(_height_along(corner, self._origin, self._destination),
                            None if after is None else _height_along(after, self._origin, self._destination))
        self.state, self.oa_destination = SUCCESS, corner

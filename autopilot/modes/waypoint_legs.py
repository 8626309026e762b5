"""AUTO's waypoint legs: the mission items flown by the waypoint navigator (control/wpnav.py),
as ArduCopter's AUTO flies them with its wp_nav.

A waypoint without a hold time flies through its point into the next leg when the next
navigation item is a waypoint or a loiter (ArduCopter's "fast" waypoint); otherwise, and for the
loiters themselves, the leg stops at the point. The navigator is kept from one leg to the next,
so a corner in progress goes on; any other navigation item (takeoff, land, RTL) ends it, and the
next waypoint starts afresh from where the vehicle can stop.

A leg to a waypoint at a height above terrain (MAV_FRAME_GLOBAL_TERRAIN_ALT) is flown as
ArduCopter's WPNAV flies one with terrain data: the navigator's path is planned in heights above
the terrain, and the terrain's height under the vehicle (its terrain database's, extrapolated over
a gap) is added to the target at every step, so the leg rises and falls with the ground beneath.
With no terrain offset at all (TERRAIN_ENABLE 0, an unhealthy rangefinder) the target stops where
it was and the terrain failsafe's timer runs (safety/failsafe.py), as ArduCopter's navigator
stops advancing it.

Legs of a mode that plans paths (Mode.plans_paths: AUTO, GUIDED) go round the fence by the
path planner, OA_TYPE's (leg_avoidance.py), as ArduCopter's AC_WPNav_OA flies every leg.
"""
from __future__ import annotations

import math

from ..control.wpnav import NavLimits, WaypointNav
from ..mission.commands import is_nav
from ..mission.jumps import jump_of
from ..path_planning.planner import NOT_REQUIRED
from ..views import Vector3
from .auto_yaw import AutoYaw
from .base import Setpoint
from .context import ModeContext
from .leg_avoidance import LegAvoidance

CMD_WAYPOINT, CMD_LOITER_UNLIM, CMD_LOITER_TIME = 16, 17, 19
NAV_BY_LEGS = {CMD_WAYPOINT, CMD_LOITER_UNLIM, CMD_LOITER_TIME}


def next_nav_index(items, index: int, jumps_done: dict) -> int | None:
    """The navigation item that will follow item `index`, following DO_JUMPs (and DO_JUMP_TAGs) as AUTO will take
    them (`jumps_done`: jumps taken so far by index); None if the mission ends first."""
    i = index + 1
    for _ in range(len(items) + 1):  # a loop of DO_JUMPs ends the look-ahead, not the vehicle
        if i >= len(items):
            return None
        item = items[i]
        if is_nav(item.command):  # as AP_Mission looks ahead: also an item AUTO will skip
            return i
        jump = jump_of(items, item)
        if jump is not None:
            target, repeat = jump
            if 0 <= target < len(items) and (repeat < 0 or jumps_done.get(i, 0) < repeat):
                i = target
                continue
        i += 1
    return None


def flies_through(item, next_item) -> bool:
    """Whether `item`'s point is flown through (no stop) on the way to `next_item`."""
    return (item.command == CMD_WAYPOINT and not item.p1 > 0 and next_item is not None
            and next_item.command in NAV_BY_LEGS and not (next_item.x == 0 and next_item.y == 0))


class WaypointLegs:
    def __init__(self, plans_paths: bool = False) -> None:
        self.nav: WaypointNav | None = None
        self.avoidance = LegAvoidance() if plans_paths else None
        self.auto_yaw = AutoYaw()  # kept from leg to leg, as ArduCopter's heading is
        self.vertical_speeds: tuple[float | None, float | None] = (None, None)  # DO_CHANGE_SPEED's up, down
        # The next leg's jerk, once, when it resumes a paused one: ArduCopter takes its track up
        # again at its position controller's jerk (PSC_JERK_XY), not as a new leg (WPNAV_JERK).
        self.resume_jerk: float | None = None
        self.planned_for = 0.0  # the horizontal speed the legs were planned at [m/s]
        # The position controller's speed limit while they are flown: ArduCopter's follows the
        # legs' own speed, also where a speed change left one above the new limit.
        self.speed_cap = math.inf
        # Flown above terrain: the navigator's down axis is then down from the terrain under the
        # vehicle less its height above the origin (`offset_m`, metres up, as last known).
        self.terrain = False
        self.offset_m = 0.0

    @property
    def destination(self) -> Vector3 | None:
        """The point the current leg flies to (local NED): a corner of the path round the fence
        while one is flown, BendyRuler's point while it flies."""
        if self.nav is None:
            return None
        point = self.avoidance.bendy_point if self.avoidance is not None else None
        return self.nav.destination if point is None else point

    @property
    def final_destination(self) -> Vector3 | None:
        """The point the mode sent the leg to, also while the path planner's corners are flown."""
        if self.nav is None:
            return None
        return self.nav.destination if self.avoidance is None else self.avoidance.destination(self.nav)

    def way_to_final(self) -> tuple[float, float] | None:
        """NAV_CONTROLLER_OUTPUT's (distance [m], bearing [deg]) from where the vehicle was last
        seen to final_destination."""
        final = self.final_destination
        if final is None or self.nav is None:
            return None
        here = self.nav.vehicle_position
        dn, de = final[0] - here[0], final[1] - here[1]
        return math.hypot(dn, de), round(math.degrees(math.atan2(de, dn)))

    @property
    def avoiding(self) -> bool:
        """The path planner replaced (or stopped) the leg's destination."""
        return self.avoidance is not None and self.nav is not None and self.avoidance.state != NOT_REQUIRED

    def end(self) -> None:
        """Another kind of item took over: the next leg starts afresh."""
        self.nav = None

    def begin(self, ctx: ModeContext, target: Vector3, next_target: Vector3 | None,
              speed_m_s: float | None = None, start: tuple[Vector3, Vector3] | None = None,
              terrain: bool = False) -> None:
        """Start the leg to `target` (local NED), flying through it to `next_target` if given,
        at `speed_m_s` (default: the navigation speed, WPNAV_SPEED or DO_CHANGE_SPEED's). With
        no leg flown before it, it starts where the vehicle can stop, or from `start` (a point
        and the velocity a spline's target left it with) at that speed. `terrain`: the targets'
        down coordinates are heights above terrain (negated); a change of frame starts afresh
        (ArduCopter re-plans the origin in the new frame)."""
        if terrain != self.terrain:
            self.nav, start = None, None
            self.terrain = terrain
        if terrain:
            self._follow_terrain(ctx)
        limits = self._limits(ctx, ctx.nav_speed_m_s if speed_m_s is None else speed_m_s)
        if self.resume_jerk is not None:
            limits.jerk, self.resume_jerk = self.resume_jerk, None
            limits.clock_tc = max(limits.accel_xy / limits.jerk, 0.01)
        if self.nav is None:
            b = ctx.body
            self.nav = WaypointNav(limits, (b.n_m, b.e_m, b.d_m + self.offset_m if terrain else b.d_m),
                                   (b.vn_m_s, b.ve_m_s, b.vd_m_s))
            if start is not None:
                point, (vn, ve, vd) = start
                self.nav.continue_at(point, math.sqrt(vn * vn + ve * ve + vd * vd))
        else:
            self.nav.limits = limits
        self.nav.set_destination(target, next_target)
        if self.avoidance is not None:
            self.avoidance.reset()
        self.planned_for = limits.speed_xy
        self.speed_cap = max(limits.speed_xy, self.nav.planned_speed)

    def _follow_terrain(self, ctx: ModeContext) -> float:
        """The terrain's height above the origin under the vehicle [m], the last known if none now
        (AC_WPNav::get_terrain_offset, extrapolating as ArduCopter's does)."""
        offset = ctx.terrain_offset_m()
        if offset is not None:
            self.offset_m = offset
        return self.offset_m

    def _limits(self, ctx: ModeContext, speed_m_s: float) -> NavLimits:
        limits = NavLimits(ctx.params, speed_m_s)
        up, down = self.vertical_speeds
        if up is not None:
            limits.speed_up = up
        if down is not None:
            limits.speed_down = down
        return limits

    def change_speed(self, ctx: ModeContext) -> None:
        """The navigation speed changed (DO_CHANGE_SPEED) while legs are flown: they change
        speed as ArduCopter's do (WaypointNav.set_speed), and the next ones start at it."""
        limits = self._limits(ctx, ctx.nav_speed_m_s)
        self.planned_for = limits.speed_xy
        if self.nav is not None:
            self.nav.set_speed(limits)
            self.speed_cap = max(limits.speed_xy, self.nav.planned_speed)

    def _hold_target(self, ctx: ModeContext, sp: Setpoint) -> None:
        """No terrain offset: ArduCopter's advance_wp_target_along_track fails and moves nothing,
        so its target stays where it was (at the last offset known) with the velocity it last
        had: the vehicle comes to rest past it, where the position error's pull back meets that
        velocity (measured: 12 m on from a return at speed)."""
        nav = self.nav
        if nav is None:
            b = ctx.body
            p, v = (b.n_m, b.e_m, b.d_m + self.offset_m), (0.0, 0.0, 0.0)
        else:
            p, v = nav.pos, nav.vel
        sp.pos_ne, sp.vel_ne, sp.accel_ne = (p[0], p[1]), (v[0], v[1]), (0.0, 0.0)
        sp.pos_d, sp.vel_d = p[2] - self.offset_m, v[2]
        sp.yaw = self.auto_yaw.facing(ctx, v[0], v[1])

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> bool:
        """Fill the setpoint with the navigator's target; returns whether the leg's point is
        reached."""
        b = ctx.body
        nav = self.nav
        if nav is None:
            raise RuntimeError("waypoint leg flown before begin() (or after end())")
        avoidance = self.avoidance
        if avoidance is not None:
            avoidance.steer(ctx, nav)
            if avoidance.bendy:  # BendyRuler's point, for the position controller itself
                avoidance.fly_bendy(ctx, nav, sp, dt)
                sp.yaw = self.auto_yaw.facing(ctx, sp.vel_ne[0], sp.vel_ne[1])
                return False
        shift, rate = 0.0, 0.0
        if self.terrain:  # into the navigator's frame above the terrain and back
            before = self.offset_m
            found = ctx.terrain_offset_m()
            # Missing for long, it is the terrain failsafe (ArduCopter's update_wpnav fails and
            # its mode calls failsafe_terrain_set_status)
            ctx.terrain_status(found is not None)
            if found is None:
                self._hold_target(ctx, sp)
                return False
            self.offset_m = shift = found
            rate = (shift - before) / dt if dt > 0.0 else 0.0
        else:
            ctx.terrain_status(True)
        reached = nav.update(dt, (b.n_m, b.e_m, b.d_m + shift), (b.vn_m_s, b.ve_m_s, b.vd_m_s + rate))
        if avoidance is not None and avoidance.state != NOT_REQUIRED:
            reached = False
        p, v, a = nav.pos, nav.vel, nav.accel
        sp.pos_ne, sp.vel_ne, sp.accel_ne = (p[0], p[1]), (v[0], v[1]), (a[0], a[1])
        sp.pos_d, sp.vel_d = p[2] - shift, v[2] - rate
        sp.yaw = self.auto_yaw.facing(ctx, v[0], v[1])
        return reached

"""Waypoint navigation as ArduCopter flies it: straight S-curve legs (scurve.py) between
waypoints, blended into the next leg before the corner when the next waypoint is known.

Each tick the navigator advances its own clock along the legs and hands out a position,
velocity and acceleration target for the position controller to follow with feed-forward.

Corners ("fast" waypoints): while decelerating towards a waypoint whose successor is known, the
next leg's acceleration is started early, and from then on the target is the sum of the two
legs' motions. The start is chosen so the two overlap symmetrically about the waypoint: with
`r` seconds of this leg left, the turn's mid point is this leg r/2 before its end plus the next
leg r/2 after its start. The next leg starts once that mid point is within the waypoint radius,
slower than the cruise speed and within the corner acceleration, so the corner is cut on the
inside. The waypoint counts as reached at the mid point of the turn. Without a successor (or
with a hold time) the leg stops at the waypoint, which is reached once the leg is over and the
vehicle is within the radius.

Next to a spline (ArduCopter's AC_WPNav joining its S-curves to its splines): a leg before one
ends at the speed the spline can start with and counts as reached when its target gets there; a
leg after one starts at the speed the spline's target left with (continue_at).

A leg interrupted before its end (a new destination mid-leg) is left from the vehicle's stopping
point as ArduCopter's position controller computes it: from the vehicle's own position and
velocity (not the target's), by the square-root controller's stopping distance, which at low
speed is a whole second of travel (v/P) rather than v^2/(2a).

The clock runs slower when the vehicle falls behind its target (as ArduCopter's track time
scaling does), so a lagging vehicle is not left chasing a target running away from it.
"""
from __future__ import annotations

import math

from firefly.sim.airframe import GRAVITY_M_S2

from .position import stopping_distance, stopping_point_ne
from .scurve import SCurve

WPNAV_RADIUS_MIN_M = 0.05
WPNAV_SPEED_MIN_M_S = 0.2
STOPPING_UP_MAX_M = 3.0     # ArduCopter's cap on the vertical stopping distance, climbing
STOPPING_DOWN_MAX_M = 2.0   # and descending


class NavLimits:
    """The navigator's limits from the parameters (ArduCopter's names, SI units here)."""
    __slots__ = ("speed_xy", "speed_up", "speed_down", "accel_xy", "accel_z", "jerk", "radius",
                 "corner_accel", "pos_p", "pos_z_p", "clock_tc", "change_jerk_time")

    def __init__(self, params, speed_xy: float | None = None):
        wp_speed = params["WPNAV_SPEED"] / 100.0 if speed_xy is None else speed_xy
        self.speed_xy = max(wp_speed, WPNAV_SPEED_MIN_M_S)
        self.speed_up = params["WPNAV_SPEED_UP"] / 100.0
        self.speed_down = params["WPNAV_SPEED_DN"] / 100.0
        self.accel_xy = params["WPNAV_ACCEL"] / 100.0
        self.accel_z = params["WPNAV_ACCEL_Z"] / 100.0
        # Jerk also within what the roll rate limit can lean the vehicle at (0 = no limit).
        rate_max = math.radians(params["ATC_RATE_R_MAX"])
        self.jerk = min(params["WPNAV_JERK"], rate_max * GRAVITY_M_S2) if rate_max > 0.0 else params["WPNAV_JERK"]
        self.radius = max(params["WPNAV_RADIUS"] / 100.0, WPNAV_RADIUS_MIN_M)
        corner = params["WPNAV_ACCEL_C"] / 100.0
        self.corner_accel = corner if corner > 0.0 else 2.0 * self.accel_xy
        self.pos_p = params["PSC_POSXY_P"]
        self.pos_z_p = params["PSC_POSZ_P"]
        # The navigator's clock changes its rate over the time a change of acceleration takes.
        self.clock_tc = max(self.accel_xy / self.jerk, 0.01)
        # The jerk time a speed change mid-leg is sized by: ArduCopter's SCurve takes it as
        # min(1 s, jerk / snap), and its snap limit makes jerk / snap the attitude time constant.
        self.change_jerk_time = min(1.0, max(params.get("ATC_INPUT_TC", 0.15), 0.1))

    def leg(self, origin: tuple, destination: tuple) -> SCurve:
        return SCurve(origin, destination, self.speed_xy, self.speed_up, self.speed_down,
                      self.accel_xy, self.accel_z, self.jerk)


class WaypointNav:
    """Legs: `_prev` (the leg being left, still contributing its end after a blended corner),
    `_this` (towards the current destination) and `_next` (towards the next one, when known).
    Outputs after `update`: pos, vel, accel (NED tuples) and reached."""

    def __init__(self, limits: NavLimits, start: tuple, velocity: tuple = (0.0, 0.0, 0.0)):
        """Starts at `start` moving at `velocity`: the first leg begins where that stops."""
        self.limits = limits
        self._this = limits.leg(start, start)
        self._t_this = 0.0
        self._prev: SCurve | None = None
        self._t_prev = 0.0
        self._next: SCurve | None = None
        self._t_next = 0.0
        self._time_scale = 1.0
        self.pos, self.vel, self.accel = start, velocity, (0.0, 0.0, 0.0)
        self._vehicle = (start, velocity)  # the vehicle's position and velocity, as last seen
        self.reached = False
        self._origin_speed = 0.0  # the speed the next leg starts at (continue_at)

    def continue_at(self, point: tuple, speed: float) -> None:
        """The target is at `point` moving at `speed` (a spline ended there, flown through): the
        next leg starts there at that speed, as far as it can (SCurve.set_origin_speed)."""
        self._this, self._t_this = self.limits.leg(point, point), 0.0
        self._prev = self._next = None
        self.reached, self._origin_speed = True, speed

    def set_destination(self, destination: tuple, next_destination: tuple | None = None) -> None:
        """Fly to `destination` from the current one; through it towards `next_destination` if
        given (a corner), else stopping there. A leg already started as the previous leg's next
        one is kept as it is, so the corner goes on without a jump."""
        old = self._this
        if self._next is not None and self._next.destination == destination and self._t_next > 0.0:
            self._prev, self._t_prev = old, self._t_this
            self._this, self._t_this = self._next, self._t_next
        else:
            # From the old destination once it was reached, else from where the target can stop.
            if self.reached:
                origin = old.destination
            else:  # interrupted: ArduCopter starts the navigator afresh, its clock at full rate
                origin, self._time_scale = self.stopping_point(), 1.0
            self._prev = None
            self._this, self._t_this = self.limits.leg(origin, destination), 0.0
            if self._origin_speed > 0.0:
                self._this.set_origin_speed(self._origin_speed)
        self._origin_speed = 0.0
        self._next, self._t_next = None, 0.0
        if next_destination is not None and next_destination != destination:
            self._next = self.limits.leg(destination, next_destination)
        self.reached = False

    def take_over(self, pos: tuple, vel: tuple, accel: tuple, vehicle: tuple) -> None:
        """The target was flown by something else (BendyRuler's points, handed to the position
        controller) and is now at pos, moving at vel: the next destination is flown to from where
        the vehicle (its position and velocity) can stop, as after an interrupted leg."""
        self._prev = self._next = None
        self._this, self._t_this = self.limits.leg(pos, pos), 0.0
        self.pos, self.vel, self.accel = pos, vel, accel
        self._vehicle = vehicle
        self.reached, self._origin_speed = False, 0.0

    def set_destination_speed(self, speed: float) -> None:
        """Pass the current destination at `speed` rather than stopping there (ArduCopter's
        set_spline_destination_next: a spline follows); reached when the target gets there."""
        self._this.set_destination_speed(speed)

    @property
    def destination_speed(self) -> float:
        """The speed the current leg passes its destination at (0: it stops there)."""
        return self._this.speed_end

    @property
    def destination(self) -> tuple:
        return self._this.destination

    @property
    def vehicle_position(self) -> tuple:
        """Where the vehicle was at the last update."""
        return self._vehicle[0]

    @property
    def next_destination(self) -> tuple | None:
        """Where the leg after this one goes (None: the vehicle stops at the destination)."""
        return self._next.destination if self._next is not None else None

    def stop_at_destination(self) -> None:
        """Stop at the destination rather than fly through it, unless the turn has begun."""
        if self._next is not None and self._t_next == 0.0:
            self._next = None

    @property
    def origin(self) -> tuple:
        """Where the current leg started (its chord is destination - origin)."""
        return self._this.origin

    def set_speed(self, limits: NavLimits) -> None:
        """New limits with a new horizontal speed: the legs being flown change speed as
        ArduCopter's set_speed_NE_cms changes them (SCurve.set_speed_max)."""
        self.limits = lim = limits
        for leg, t in ((self._this, self._t_this), (self._next, self._t_next)):
            if leg is not None:
                leg.set_speed_max(lim.speed_xy, lim.speed_up, lim.speed_down, t, lim.change_jerk_time)

    @property
    def planned_speed(self) -> float:
        """The fastest horizontal speed the legs being flown are planned to reach [m/s]."""
        fastest = 0.0
        for leg in (self._prev, self._this, self._next):
            if leg is not None:
                fastest = max(fastest, leg.peak * math.hypot(leg.unit[0], leg.unit[1]))
        return fastest

    def stopping_point(self) -> tuple:
        """Where the position controller brings the vehicle to rest from its present motion:
        along its horizontal velocity (capped at the leg speed), and vertically within
        ArduCopter's caps."""
        lim = self.limits
        (pn, pe, pd), (vn, ve, vd) = self._vehicle
        pn, pe = stopping_point_ne(pn, pe, vn, ve, lim.pos_p, lim.accel_xy, lim.speed_xy)
        if lim.pos_z_p > 0.0 and lim.accel_z > 0.0:
            up = stopping_distance(-vd, lim.pos_z_p, lim.accel_z)
            pd -= min(max(up, -STOPPING_DOWN_MAX_M), STOPPING_UP_MAX_M)
        return (pn, pe, pd)

    def _scaled_dt(self, dt: float, pos: tuple, vel: tuple) -> float:
        """dt on the navigator's clock: slowed while the vehicle is behind its target."""
        tvn, tve, tvd = self.vel
        speed = math.sqrt(tvn * tvn + tve * tve + tvd * tvd)
        wanted = 1.0
        if speed > 1e-6:
            tp = self.pos
            ahead = ((tp[0] - pos[0]) * tvn + (tp[1] - pos[1]) * tve + (tp[2] - pos[2]) * tvd) / speed
            along = (vel[0] * tvn + vel[1] * tve + vel[2] * tvd) / speed
            wanted = min(1.0, max(0.0, 0.05 + (along - self.limits.pos_p * ahead) / speed))
        if wanted != self._time_scale:
            self._time_scale += (wanted - self._time_scale) * dt / self.limits.clock_tc
        return dt * self._time_scale

    def update(self, dt: float, pos: tuple, vel: tuple) -> bool:
        """Advance by dt seconds given the vehicle's position and velocity; returns reached."""
        self._vehicle = (pos, vel)
        step = self._scaled_dt(dt, pos, vel)
        this = self._this
        self._t_this = t = min(self._t_this + step, this.duration)
        s, v, a = this.along(t)
        (un, ue, ud), o = this.unit, this.origin
        pn, pe, pd = o[0] + un * s, o[1] + ue * s, o[2] + ud * s
        vn, ve, vd = un * v, ue * v, ud * v
        an, ae, ad = un * a, ue * a, ud * a
        prev = self._prev
        if prev is not None:  # the leg being left: its motion short of its end
            self._t_prev = tp = min(self._t_prev + step, prev.duration)
            s, v, a = prev.along(tp)
            s -= prev.length
            un, ue, ud = prev.unit
            pn, pe, pd = pn + un * s, pe + ue * s, pd + ud * s
            vn, ve, vd = vn + un * v, ve + ue * v, vd + ud * v
            an, ae, ad = an + un * a, ae + ue * a, ad + ud * a
            if tp >= prev.duration:
                self._prev = None
        finished = t >= this.duration
        nxt = self._next
        if nxt is not None:
            remaining = this.duration - t
            if self._t_next == 0.0:
                if t >= this.decel_start and remaining <= nxt.accel_end and self._corner_ok(nxt, remaining):
                    self._t_next = step
            else:
                self._t_next = min(self._t_next + step, nxt.duration)
            if self._t_next > 0.0:
                s, v, a = nxt.along(self._t_next)
                un, ue, ud = nxt.unit
                pn, pe, pd = pn + un * s, pe + ue * s, pd + ud * s
                vn, ve, vd = vn + un * v, ve + ue * v, vd + ud * v
                an, ae, ad = an + un * a, ae + ue * a, ad + ud * a
                finished = self._t_next >= remaining
        self.pos, self.vel, self.accel = (pn, pe, pd), (vn, ve, vd), (an, ae, ad)
        if not self.reached and finished:
            if nxt is not None or this.speed_end > 0.0:
                self.reached = True
            else:
                d = this.destination
                dn, de, dd = pos[0] - d[0], pos[1] - d[1], pos[2] - d[2]
                self.reached = dn * dn + de * de + dd * dd <= self.limits.radius ** 2
        return self.reached

    def _corner_ok(self, nxt: SCurve, remaining: float) -> bool:
        """Whether the turn onto `nxt`, started now, keeps its mid point within the waypoint
        radius, below the cruise speed and within the corner (and vertical) acceleration."""
        this, lim = self._this, self.limits
        half = remaining / 2.0
        s1, v1, a1 = this.along(this.duration - half)
        s2, v2, a2 = nxt.along(half)
        (n1, e1, d1), (n2, e2, d2) = this.unit, nxt.unit
        off1 = s1 - this.length
        pn, pe, pd = n1 * off1 + n2 * s2, e1 * off1 + e2 * s2, d1 * off1 + d2 * s2
        if pn * pn + pe * pe + pd * pd >= lim.radius * lim.radius:
            return False
        vn, ve, vd = n1 * v1 + n2 * v2, e1 * v1 + e2 * v2, d1 * v1 + d2 * v2
        speed_min = min(this.speed_max, nxt.speed_max)
        an, ae, ad = n1 * a1 + n2 * a2, e1 * a1 + e2 * a2, d1 * a1 + d2 * a2
        return (vn * vn + ve * ve + vd * vd < speed_min * speed_min
                and an * an + ae * ae < lim.corner_accel * lim.corner_accel and abs(ad) < lim.accel_z)

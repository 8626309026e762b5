"""GUIDED: the vehicle goes where the ground station says: a takeoff, a position, a position with
a velocity and acceleration, a velocity (with an acceleration), an acceleration, an attitude.

As ArduCopter's ModeGuided: each kind of target is a sub-mode; a velocity, acceleration or
attitude stream that stops for GUID_TIMEOUT stops the vehicle (velocity and acceleration to
zero, the attitude level); none of them moves a landed vehicle (only a takeoff, or an attitude
target's climb, leaves the ground); DO_PAUSE_CONTINUE stops it where it is and lets it go on.

A position target is flown by the position controller, or with GUID_OPTIONS bit 6 as a waypoint
leg of the waypoint navigator (ArduCopter's WP sub-mode), which goes round the fence by the path
planner (OA_TYPE) and reports its arrival as MISSION_ITEM_REACHED 0. A destination outside an
enabled fence is refused either way.
"""
from __future__ import annotations

import math

from ..control.wpnav import WPNAV_SPEED_MIN_M_S
from ..views import Vector3
from .auto_yaw import AutoYaw
from .base import Mode, Setpoint, shifted, stopping_point
from .context import ModeContext
from .guided_angle import AttitudeTarget, guided_timeout_s
from .guided_stop import JerkLimitedStop
from .guided_yaw import DEFAULT, SLEW_YAW_DEFAULT_CDEG_S, TURNING, GuidedYaw
from .numbers import ModeNumber
from .takeoff_climb import TakeoffClimb
from .waypoint_legs import WaypointLegs

VELOCITY_TIMEOUT_S = 3.0  # GUID_TIMEOUT's default: ArduCopter stops if velocity setpoints stop arriving
FACE_TARGET_BEYOND_M = 1.0  # nearer than this the heading stays: an overshoot does not turn it
# Taking over climbing or sinking faster than this, the height is held only once the climb or
# sink has been stopped (below VERTICAL_STILL_M_S): ArduCopter's GUIDED starts as a velocity of
# zero, so it stops where its vertical controller brings it to rest (a drop in THROW handing
# over at 7.5 m/s down: 6.3 m lower, measured), never flying back to the height it entered at.
VERTICAL_MOVING_M_S = 0.5
VERTICAL_STILL_M_S = 0.2
# Sub-modes (ArduCopter's ModeGuided::SubMode): what the last target asked for
POS, POS_VEL_ACCEL, VEL_ACCEL, ACCEL, ANGLE, WP = "pos", "pos_vel_accel", "vel_accel", "accel", "angle", "wp"
WPNAV_FOR_POSITION = 1 << 6  # GUID_OPTIONS: a position target is a waypoint leg
ZERO3: Vector3 = (0.0, 0.0, 0.0)


class Guided(Mode):
    takes_speed_change = True
    number = ModeNumber.GUIDED
    plans_paths = True
    requires_position = True
    allows_arming = True
    has_user_takeoff = True
    in_guided_mode = True
    requires_terrain_failsafe = True
    takeoff: TakeoffClimb | None  # a user takeoff, until another target replaces it
    submode: str
    target_ne: tuple[float, float]
    target_d: float
    target_vel: Vector3
    target_accel: Vector3
    updated_s: float  # sim time of the last velocity / acceleration target
    yaw: GuidedYaw  # the heading a target or CONDITION_YAW asked for
    auto_yaw: AutoYaw  # the heading when no target sets one (WP_YAW_BEHAVIOR)
    has_waypoint: bool  # a position target was given (ArduCopter's WP/Pos sub-modes, its get_wp)
    paused_d: float | None  # DO_PAUSE_CONTINUE: the height it stopped at, until resumed
    stopping_vertically: bool  # entered climbing or sinking: the height is held once that stops
    stopping: JerkLimitedStop | None  # slowing to a stop: paused, or a velocity stream that stopped
    target_terrain: bool  # target_d is down from the terrain under the vehicle, less the height above it
    terrain_offset: float  # the terrain's height above the origin [m] under the vehicle, as last known
    speed_up: float | None  # DO_CHANGE_SPEED's climb and descent speeds [m/s] (None: WPNAV_SPEED_UP/DN)
    speed_dn: float | None
    legs: WaypointLegs | None = None  # the WP sub-mode's leg
    reach_untold = False  # the WP sub-mode's arrival is still to be reported

    def __init__(self) -> None:
        self.angle = AttitudeTarget()
        self.submode = POS
        self.stopping_vertically = False

    def enter(self, ctx: ModeContext) -> str | None:
        self.begin(ctx)
        self._default_speeds(ctx)
        return None

    def begin(self, ctx: ModeContext) -> None:
        """ArduCopter's ModeGuided::init, which AUTO's guided items also call: stop and hold, no
        takeoff, not paused; the speeds are left as they are."""
        self.yaw = GuidedYaw()
        self.hold(ctx)
        self.takeoff = None
        self.paused_d = None
        self.speed_up = self.speed_dn = None

    def _default_speeds(self, ctx: ModeContext) -> None:
        """A new kind of target starts ArduCopter's controller afresh, at WPNAV_SPEED(_UP/_DN):
        what DO_CHANGE_SPEED set is forgotten."""
        self.speed_up = self.speed_dn = None
        default = ctx.params["WPNAV_SPEED"] / 100.0
        if ctx.nav_speed_m_s != default:
            ctx.set_speed(default)

    def hold(self, ctx: ModeContext) -> None:
        """Stop: hold the point the vehicle comes to rest at (ArduCopter's init: zero velocity)."""
        if self.submode == ANGLE:
            ctx.restart_position_control()
        self.submode = POS
        self.target_ne, self.target_d = stopping_point(ctx)
        self.target_terrain, self.terrain_offset = False, 0.0
        self.stopping_vertically = not ctx.landed and abs(ctx.body.vd_m_s) > VERTICAL_MOVING_M_S
        self.target_vel = self.target_accel = ZERO3
        self.updated_s = ctx.time_s
        self.auto_yaw = AutoYaw()  # the heading is held until the vehicle moves
        self.has_waypoint = False
        self.stopping = None
        self.yaw = GuidedYaw()
        self.legs, self.reach_untold = None, False

    def stop(self, ctx: ModeContext) -> bool:
        """A target ArduCopter finds invalid: it stops (re-initialises the mode)."""
        self.takeoff = None
        self.hold(ctx)
        return True

    # Commands from the ground station -------------------------------------------------------
    def user_takeoff(self, ctx: ModeContext, alt_above_home_m: float) -> None:
        self.hold(ctx)
        self.stopping_vertically = False
        self.target_d = ctx.height_ref_d - alt_above_home_m  # above home, or the boot ground before it
        self.takeoff = TakeoffClimb(ctx, self.target_d)

    def goto(self, ctx: ModeContext, n: float, e: float, d: float | None, yaw: float | None = None,
             vel_ff: Vector3 = ZERO3, terrain: bool = False) -> bool:
        """A position (d None: keep the height), with a velocity: ArduCopter's PosVelAccel."""
        if d is None and self.target_terrain:  # the height kept, in the frame it was given in
            terrain = True
        return self.set_target(ctx, (n, e, self.target_d if d is None else d), None if vel_ff == ZERO3 else vel_ff,
                               None, yaw, None, terrain=terrain)

    def set_velocity(self, ctx: ModeContext, vn: float, ve: float, vd: float, yaw: float | None = None) -> bool:
        self.set_target(ctx, None, (vn, ve, vd), None, yaw, None)
        return True

    def set_target(self, ctx: ModeContext, pos: Vector3 | None, vel: Vector3 | None, accel: Vector3 | None,
                   yaw: float | None, yaw_rate: float | None, yaw_relative: bool = False,
                   terrain: bool = False) -> bool:
        """A SET_POSITION_TARGET's parts (local NED; None = ignored), as ArduCopter takes them:
        position [+ velocity [+ acceleration]], velocity [+ acceleration], or acceleration.
        `terrain`: the position is above the terrain (its down: less the height above it), flown
        with the terrain's height under the vehicle added (a position alone: ArduCopter's pos
        controller has no terrain offset with a velocity); without any terrain there it stops
        and refuses the target, as ArduCopter's set_destination does."""
        offset = 0.0
        if pos is not None and terrain:
            found = ctx.terrain_offset_m()
            if found is None or vel is not None or accel is not None:
                self.stop(ctx)
                return False
            offset = found
        if pos is not None and not ctx.destination_within_fence(pos[0], pos[1], pos[2] - offset):
            return False  # ArduCopter refuses it, and flies on as it was
        self.takeoff = None
        self.stopping = None
        before = self.submode
        if pos is not None:
            self.stopping_vertically = False
            if vel is None and int(ctx.params["GUID_OPTIONS"]) & WPNAV_FOR_POSITION:
                self._set_waypoint(ctx, pos, before, terrain)
            else:
                self.submode = POS if vel is None else POS_VEL_ACCEL
                self.legs = None
            self.target_ne, self.target_d = (pos[0], pos[1]), pos[2]
            self.target_terrain, self.terrain_offset = terrain, offset
            self.has_waypoint = vel is None
        elif vel is None:  # the acceleration moves a velocity on: from the present one at its start
            if self.submode != ACCEL:
                b = ctx.body
                self.target_vel = (b.vn_m_s, b.ve_m_s, b.vd_m_s)
            self.submode = ACCEL
            self.has_waypoint = False
        else:
            self.submode = VEL_ACCEL
            self.has_waypoint = False
        if pos is None:
            self.legs = None
        if vel is not None or pos is not None:
            self.target_vel = vel or ZERO3
        self.target_accel = accel or ZERO3
        self.updated_s = ctx.time_s
        if self.submode != before:  # ArduCopter's controller starts afresh: speeds, the heading held
            self._default_speeds(ctx)
            self.auto_yaw = AutoYaw()
            if before == ANGLE:
                ctx.restart_position_control()
        self._set_yaw(ctx, yaw, yaw_rate, yaw_relative)
        return True

    def _set_waypoint(self, ctx: ModeContext, pos: Vector3, before: str, terrain: bool) -> None:
        """The WP sub-mode's leg to `pos`: from where the vehicle can stop when it starts, else
        on from the leg being flown (ArduCopter's wp_control_start and set_wp_destination)."""
        if before != WP or self.legs is None:
            self.legs = WaypointLegs(self.plans_paths)
        self.submode = WP
        self.legs.begin(ctx, pos, None, terrain=terrain)
        self.reach_untold = True

    def _set_yaw(self, ctx: ModeContext, yaw: float | None, rate: float | None, relative: bool) -> None:
        heading = ctx.attitude[2]
        if yaw is not None and relative:
            self.yaw.set_fixed(heading, yaw, 0.0, 0, True, self._slew_max(ctx))
        elif yaw is not None:
            self.yaw.set_angle_rate(yaw, rate or 0.0)
        elif rate is not None:
            self.yaw.set_rate(rate)
        else:
            self.yaw = GuidedYaw()

    @staticmethod
    def _slew_max(ctx: ModeContext) -> float:
        return math.radians(ctx.params.get("ATC_SLEW_YAW", SLEW_YAW_DEFAULT_CDEG_S) / 100.0)

    def set_attitude(self, ctx: ModeContext, attitude: Vector3 | None, rates: Vector3, climb_or_thrust: float,
                     use_thrust: bool) -> bool:
        """SET_ATTITUDE_TARGET (guided_angle.AttitudeTarget)."""
        if self.submode != ANGLE:
            self.submode = ANGLE
            self.takeoff = None
            self.has_waypoint = False
            self.angle.start(ctx, ctx.attitude[2])
        self.angle.set(ctx, attitude, rates, climb_or_thrust, use_thrust)
        return True

    def set_heading(self, ctx: ModeContext, yaw_rad: float) -> bool:
        self.yaw.set_angle_rate(yaw_rad, 0.0)
        return True

    def turn(self, ctx: ModeContext, angle: float, rate: float, direction: int, relative: bool) -> bool:
        """CONDITION_YAW: turn to (or by) `angle` at `rate` [rad/s] (0: ATC_SLEW_YAW)."""
        self.yaw.set_fixed(ctx.attitude[2], angle, rate, direction, relative, self._slew_max(ctx))
        return True

    def set_roi(self, ctx: ModeContext, roi_ne: tuple[float, float] | None) -> bool:
        """Face the point until a target or a turn says otherwise; None: the default heading."""
        if roi_ne is None:
            self.yaw = GuidedYaw()
        else:
            self.yaw.set_roi(roi_ne)
        return True

    def pause(self, ctx: ModeContext, paused: bool) -> bool:
        """Slow to a stop and hold (ArduCopter's pause); the target stays for the resume."""
        if not paused:
            self.paused_d = None
            self.stopping = None
        elif self.paused_d is None:
            self.paused_d = ctx.body.d_m
            self.stopping = JerkLimitedStop(ctx)
        return True

    def set_vertical_speed(self, ctx: ModeContext, up_m_s: float | None, dn_m_s: float | None) -> bool:
        if up_m_s is not None:
            self.speed_up = up_m_s
        if dn_m_s is not None:
            self.speed_dn = dn_m_s
        return True

    def position_reset(self, dn: float, de: float) -> None:
        """The point held after a takeoff (measured) or where GUIDED stopped moves with the
        estimate; a position the ground station sent is its point in the local frame, fed to
        the controller again every tick (ArduCopter's guided_pos_target), so it stays."""
        if self.takeoff is not None:
            self.takeoff.hold_ne = shifted(self.takeoff.hold_ne, dn, de)
        if self.takeoff is not None or (self.submode == POS and not self.has_waypoint):
            self.target_ne = shifted(self.target_ne, dn, de)

    def destination(self) -> tuple[float, float, float | None] | None:
        """Only a position target is a destination: holding where it entered, taking off or
        flying a velocity, ArduCopter's GUIDED has no waypoint to report. A leg round the fence
        reports the corner it flies to."""
        if self.legs is not None and self.legs.avoiding:
            return self.legs.destination
        if not self.has_waypoint:
            return None
        return self.target_ne[0], self.target_ne[1], self.target_d - self.terrain_offset

    def nav_distance_bearing(self) -> tuple[float, float] | None:
        """While a leg round the fence is flown: the way to the target, not to the corner."""
        return self.legs.way_to_final() if self.legs is not None and self.legs.avoiding else None

    # Loop --------------------------------------------------------------------------------------
    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        sp.clear()
        if self.submode == ANGLE:
            self.angle.fly(ctx, sp, dt)
            return
        sp.speed_xy = ctx.nav_speed_m_s
        takeoff = self.takeoff
        if ctx.landed and takeoff is None:
            # ArduCopter's guided controllers do nothing on the ground: only a takeoff leaves it.
            self.target_d = sp.pos_d = ctx.body.d_m
            return
        if self.paused_d is not None and self.stopping is not None:
            self.stopping.fly(ctx, sp, dt)
            sp.pos_d = self.paused_d
            sp.yaw = ctx.attitude[2] if self.yaw.kind == DEFAULT else self.yaw.angle
            return
        if (self.submode not in (POS, WP) or self.yaw.kind in TURNING) and ctx.time_s - self.updated_s > guided_timeout_s(ctx):
            self._timed_out(ctx)
        submode = self.submode
        if takeoff is not None:  # climbing, then holding the height it climbed to
            takeoff.fly(ctx, sp, dt)
        elif submode == POS:
            self._fly_position(ctx, sp)
        elif submode == WP and self.legs is not None:
            self._fly_waypoint(ctx, sp, dt, self.legs)
        elif submode == POS_VEL_ACCEL:
            self._fly_pos_vel_accel(ctx, sp, dt)
        else:
            self._fly_vel_accel(ctx, sp, dt)
        # The guards below save two calls a tick in the usual case (no yaw asked, no speed change).
        yaw = self.yaw
        if (yaw.kind == DEFAULT or not yaw.fly(sp, dt, ctx.body)) and sp.yaw is None:
            sp.yaw = self.auto_yaw.facing(ctx, *sp.vel_ne)
        if self.speed_up is not None or self.speed_dn is not None:
            self._limit_vertical(ctx, sp)

    def _timed_out(self, ctx: ModeContext) -> None:
        """The target stream stopped: ArduCopter stops a rate turn, zeroes a velocity and an
        acceleration (a position holds)."""
        self.yaw.stop_turning(ctx.attitude[2])
        if self.submode == POS_VEL_ACCEL:  # the position holds
            self.target_vel = self.target_accel = ZERO3
        elif self.submode != POS:  # a velocity of zero: it slows down from the one it was flying
            vn, ve, _ = self.target_vel
            if self.stopping is None and (vn or ve):
                self.stopping = JerkLimitedStop(ctx, (vn, ve))
            self.submode = VEL_ACCEL
            self.target_vel = self.target_accel = ZERO3
        self.updated_s = ctx.time_s

    def _fly_position(self, ctx: ModeContext, sp: Setpoint) -> None:
        if self.stopping_vertically and abs(ctx.body.vd_m_s) < VERTICAL_STILL_M_S:
            self.stopping_vertically = False
            self.target_d = ctx.body.d_m
        target_d = self.target_d
        if self.target_terrain:  # ArduCopter's pos_control_run: the offset, or the terrain failsafe
            offset = ctx.terrain_offset_m()
            if offset is None:
                ctx.terrain_failsafe()
                return
            self.terrain_offset = offset
            target_d -= offset
        sp.pos_ne, sp.pos_d = self.target_ne, None if self.stopping_vertically else target_d
        if self.yaw.kind != DEFAULT:
            return
        # ArduCopter's desired velocity points at the target until the last centimetres (its
        # path stops there); the vehicle's own would turn it round on a small overshoot.
        b, (n, e) = ctx.body, self.target_ne
        dn, de = n - b.n_m, e - b.e_m
        distance = math.hypot(dn, de)
        if distance > FACE_TARGET_BEYOND_M:
            scale = math.hypot(b.vn_m_s, b.ve_m_s) / distance
            sp.yaw = self.auto_yaw.facing(ctx, dn * scale, de * scale)
        else:
            sp.yaw = self.auto_yaw.yaw

    def _fly_waypoint(self, ctx: ModeContext, sp: Setpoint, dt: float, legs: WaypointLegs) -> None:
        if legs.nav is None:
            return
        if legs.planned_for != max(ctx.nav_speed_m_s, WPNAV_SPEED_MIN_M_S):
            legs.change_speed(ctx)
        sp.speed_xy = legs.speed_cap
        if legs.update(ctx, sp, dt) and self.reach_untold:
            self.reach_untold = False
            ctx.mission_progress.report_reached(0)  # (ArduCopter's "mission item" 0: the guided one)

    def _fly_pos_vel_accel(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        """The position moves on with the velocity, the velocity with the acceleration (as
        ArduCopter's kinematic target between two messages)."""
        vn, ve, vd = self.target_vel
        an, ae, ad = self.target_accel
        if an or ae or ad:
            self.target_vel = (vn + an * dt, ve + ae * dt, vd + ad * dt)
        n, e = self.target_ne
        self.target_ne = (n + vn * dt, e + ve * dt)
        self.target_d += vd * dt
        sp.pos_ne, sp.pos_d = self.target_ne, self.target_d
        sp.vel_ne, sp.vel_d = (vn, ve), vd
        sp.speed_xy = math.inf

    def _fly_vel_accel(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        if self.stopping is not None:
            self.stopping.fly(ctx, sp, dt)
            sp.speed_xy = math.inf
            return
        vn, ve, vd = self.target_vel
        an, ae, ad = self.target_accel
        if an or ae or ad:
            limit = ctx.params["WPNAV_ACCEL"] / 100.0  # ArduCopter shapes an acceleration within it
            size = math.sqrt(an * an + ae * ae)
            if size > limit:
                an, ae = an * limit / size, ae * limit / size
            vn, ve, vd = vn + an * dt, ve + ae * dt, vd + ad * dt
            self.target_vel = (vn, ve, vd)
        # As ArduCopter's: avoidance cuts the target itself, which keeps the cut (and a push back)
        # until the next target arrives.
        avoided = ctx.avoid_velocity((vn, ve, -vd), ctx.params["WPNAV_ACCEL"] / 100.0, dt)
        if avoided[0] != vn or avoided[1] != ve or avoided[2] != -vd:
            vn, ve, vd = avoided[0], avoided[1], -avoided[2]
            self.target_vel = (vn, ve, vd)
        sp.vel_ne, sp.vel_d = (vn, ve), vd
        sp.speed_xy = math.inf

    def _limit_vertical(self, ctx: ModeContext, sp: Setpoint) -> None:
        """DO_CHANGE_SPEED's climb and descent speeds: a height target is approached no faster."""
        up, dn = self.speed_up, self.speed_dn
        if dn is not None:
            sp.speed_dn = dn
        if up is not None and sp.pos_d is not None:
            d = ctx.body.d_m
            if sp.pos_d < d - 1.0:  # beyond a metre's climb: a carrot ahead at the climb speed
                sp.pos_d = max(sp.pos_d, d - up)
        if up is not None and sp.vel_d < -up:
            sp.vel_d = -up

    def landed_state_hint(self, ctx: ModeContext) -> str | None:
        takeoff = self.takeoff
        return "TAKEOFF" if takeoff is not None and not takeoff.done and not ctx.landed else None

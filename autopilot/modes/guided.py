"""GUIDED: the vehicle goes where the ground station says (position, velocity, takeoff)."""
from __future__ import annotations

import math

from ..views import Vector3
from .auto_yaw import AutoYaw
from .base import Mode, Setpoint, stopping_point
from .context import ModeContext
from .numbers import ModeNumber

VELOCITY_TIMEOUT_S = 3.0  # ArduCopter stops if velocity setpoints stop arriving
# The takeoff is over (EXTENDED_SYS_STATE TAKEOFF -> IN_AIR) this close to its altitude: ArduCopter's
# ends at the altitude (measured on its SITL: IN_AIR at 9.99 m of a 10 m takeoff).
TAKEOFF_DONE_M = 0.1
FACE_TARGET_BEYOND_M = 1.0  # nearer than this the heading stays: an overshoot does not turn it


class Guided(Mode):
    takes_speed_change = True
    number = ModeNumber.GUIDED
    requires_position = True
    allows_arming = True
    has_user_takeoff = True
    takeoff_d: float | None  # the height a user takeoff climbs to, until it is reached
    target_ne: tuple[float, float]
    target_d: float
    target_vel_ne: tuple[float, float]
    target_vel_d: float
    target_yaw: float | None
    velocity_mode: bool
    velocity_time_s: float
    auto_yaw: AutoYaw  # the heading when no target sets one (WP_YAW_BEHAVIOR)
    has_waypoint: bool  # a position target was given (ArduCopter's WP/Pos sub-modes, its get_wp)

    def enter(self, ctx: ModeContext) -> str | None:
        self.hold(ctx)
        self.takeoff_d = None
        return None

    def hold(self, ctx: ModeContext) -> None:
        self.target_ne, self.target_d = stopping_point(ctx)
        self.target_vel_ne, self.target_vel_d = (0.0, 0.0), 0.0
        self.target_yaw = None
        self.velocity_mode = False
        self.velocity_time_s = ctx.time_s
        self.auto_yaw = AutoYaw()  # the heading is held until the vehicle moves
        self.has_waypoint = False

    # Commands from the ground station -------------------------------------------------------
    def user_takeoff(self, ctx: ModeContext, alt_above_home_m: float) -> None:
        self.hold(ctx)
        self.takeoff_d = ctx.height_ref_d - alt_above_home_m  # above home, or the boot ground before it
        self.target_d = self.takeoff_d

    def goto(self, ctx: ModeContext, n: float, e: float, d: float | None, yaw: float | None = None,
             vel_ff: Vector3 = (0.0, 0.0, 0.0)) -> bool:
        self.takeoff_d = None
        self.velocity_mode = False
        self.target_ne = (n, e)
        if d is not None:
            self.target_d = d
        self.target_vel_ne, self.target_vel_d = (vel_ff[0], vel_ff[1]), vel_ff[2]
        self.target_yaw = yaw
        self.has_waypoint = vel_ff == (0.0, 0.0, 0.0)  # with a velocity too: ArduCopter's PosVelAccel
        return True

    def set_velocity(self, ctx: ModeContext, vn: float, ve: float, vd: float, yaw: float | None = None) -> bool:
        self.takeoff_d = None
        self.velocity_mode = True
        self.target_vel_ne, self.target_vel_d = (vn, ve), vd
        self.target_yaw = yaw
        self.velocity_time_s = ctx.time_s
        self.has_waypoint = False
        return True

    def set_heading(self, ctx: ModeContext, yaw_rad: float) -> bool:
        self.target_yaw = yaw_rad
        return True

    def destination(self) -> tuple[float, float, float | None] | None:
        """Only a position target is a destination: holding where it entered, taking off or
        flying a velocity, ArduCopter's GUIDED has no waypoint to report."""
        return (self.target_ne[0], self.target_ne[1], self.target_d) if self.has_waypoint else None

    # Loop --------------------------------------------------------------------------------------
    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        sp.clear()
        sp.speed_xy = ctx.nav_speed_m_s
        sp.yaw = self.target_yaw
        if self.velocity_mode:
            if ctx.time_s - self.velocity_time_s > VELOCITY_TIMEOUT_S:
                self.hold(ctx)
            else:
                sp.vel_ne, sp.vel_d = self.target_vel_ne, self.target_vel_d
                if sp.yaw is None:
                    sp.yaw = self.auto_yaw.facing(ctx, *self.target_vel_ne)
                return
        sp.pos_ne, sp.pos_d = self.target_ne, self.target_d
        if sp.yaw is None:
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
        sp.vel_ne, sp.vel_d = self.target_vel_ne, self.target_vel_d
        if ctx.landed and self.takeoff_d is None:
            # On the ground without a takeoff: stay put wherever the target was set.
            self.target_d = ctx.body.d_m
            sp.pos_d = self.target_d
        if self.takeoff_d is not None and abs(ctx.body.d_m - self.takeoff_d) < TAKEOFF_DONE_M:
            self.takeoff_d = None

    def landed_state_hint(self, ctx: ModeContext) -> str | None:
        return "TAKEOFF" if self.takeoff_d is not None and not ctx.landed else None

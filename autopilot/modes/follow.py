"""FOLLOW: fly after another system, as ArduCopter's ModeFollow: to the lead's estimated point
plus the offset (follow_target.py), its velocity and acceleration fed forward, heading per
FOLL_YAW_BEHAVE.

Refused until FOLL_ENABLE is 1 (saying so); entered enabled in every state. As ArduCopter's
position controller takes a moving target, the point flown to is a kinematic target of its own,
shaped toward the lead's point within WPNAV_ACCEL and PSC_JERK_XY, its correction no faster than
WPNAV_SPEED on top of the lead's velocity. With no lead (none heard, silent for 3 s, beyond
FOLL_DIST_MAX) that target is shaped to a stop instead (ArduCopter's zero velocity input) and
held, still in FOLLOW, at the height where the lead was lost; it flies on when the lead speaks.

FOLL_YAW_BEHAVE 1 (face the lead) is ArduCopter 4.7's as measured, not as named: it turns toward
the lead's position in metres less the position target in centimetres (a units slip in
mode_follow.cpp), which points roughly from the vehicle back toward its origin. Firefly turns
the same way, so that a client sees the heading ArduCopter gives (tests/parity, area follow).
NAV_CONTROLLER_OUTPUT carries ArduCopter's own slips too (see _report); POSITION_TARGET_GLOBAL_INT
is the lead's estimated point plus offset.
"""
from __future__ import annotations

import math

from ..control.shaping import advance_2d, shape_pos_vel_accel_2d, shape_vel_accel_2d
from ..follow_target import FLIGHT_DIRECTION_MIN_M_S, YAW_DIR_OF_FLIGHT, YAW_FACE_LEAD, YAW_SAME_AS_LEAD
from ..results import Severity
from .base import Mode, Setpoint
from .context import ModeContext
from .guided_stop import JERK_DEFAULT_M_S3
from ..views import Vector3
from .numbers import ModeNumber
from .tilted_heading import INPUT_TC_DEFAULT_S, tilted_heading

CM_PER_M = 100.0
CM_TO_M = 0.01
FACE_LEAD_BEYOND_M2 = 1.0  # ArduCopter faces the lead only when it is this far (squared) from the origin
Vec2 = tuple[float, float]


class Follow(Mode):
    number = ModeNumber.FOLLOW
    requires_position = True
    _target: tuple[Vec2, Vec2, Vec2] | None  # the shaped point flown to: position, velocity, acceleration
    _hold_d: float  # the height held without a lead
    _heading: float | None  # the heading asked for last
    _point: Vector3 | None  # the lead's estimated point plus offset, while there is a lead
    _nav: tuple[float, float]  # NAV_CONTROLLER_OUTPUT's distance and bearing, as ArduCopter's

    def enter(self, ctx: ModeContext) -> str | None:
        if not ctx.params["FOLL_ENABLE"]:
            ctx.notify("Set FOLL_ENABLE = 1", Severity.WARNING)
            return "init failed"
        self._target = None
        self._hold_d = ctx.body.d_m
        self._heading = None
        self._point, self._nav = None, (0.0, 0.0)
        return None

    def exit(self, ctx: ModeContext) -> None:
        ctx.follow_target.forget_loaded_offset()

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        sp.clear()
        b = ctx.body
        if ctx.landed or not ctx.armed:  # ArduCopter keeps a landed vehicle on the ground here
            self._target = self._heading = None
            self._hold_d = sp.pos_d = b.d_m
            self._report(ctx, None)
            return
        lead = ctx.follow_target
        own = (b.n_m, b.e_m, b.d_m) if ctx.has_position() else None
        if own is not None:
            lead.load_offset_if_needed(own)
        following = lead.update(ctx.time_s, own)
        params = ctx.params
        accel_max = params["WPNAV_ACCEL"] / 100.0
        jerk = params.get("PSC_JERK_XY", JERK_DEFAULT_M_S3)
        if self._target is None:  # starts from the vehicle, as ArduCopter's controller does on entry
            self._target = ((b.n_m, b.e_m), (b.vn_m_s, b.ve_m_s), (0.0, 0.0))
        pos, vel, accel = self._target
        pos, vel = advance_2d(pos, vel, accel, dt)
        self._report(ctx, lead.ofs_pos if following else None)
        if following:
            n, e, d = lead.ofs_pos
            vn, ve, vd = lead.ofs_vel
            an, ae, _ = lead.ofs_accel
            accel = shape_pos_vel_accel_2d((n, e), (vn, ve), (an, ae), pos, vel, accel, accel_max, jerk, dt,
                                           ctx.nav_speed_m_s)
            sp.pos_d, sp.vel_d = d, vd
            self._hold_d = b.d_m
            self._yaw(ctx, sp, pos)
        else:
            accel = shape_vel_accel_2d((0.0, 0.0), (0.0, 0.0), vel, accel, accel_max, jerk, dt)
            sp.pos_d = self._hold_d
        if sp.yaw is None:  # kept as ArduCopter keeps it: its target's Euler yaw, which a lean moves
            held = ctx.attitude[2] if self._heading is None else self._heading
            sp.yaw = tilted_heading(ctx.attitude, held, dt, params.get("ATC_INPUT_TC", INPUT_TC_DEFAULT_S))
        self._heading = sp.yaw
        self._target = (pos, vel, accel)
        sp.pos_ne, sp.vel_ne, sp.accel_ne = pos, vel, accel

    def _report(self, ctx: ModeContext, point: Vector3 | None) -> None:
        """What FOLLOW says of where it flies: the lead's point (POSITION_TARGET_GLOBAL_INT), and
        NAV_CONTROLLER_OUTPUT's distance and bearing as ArduCopter 4.7 makes them: from its origin
        to the point less a hundredth of the vehicle's position (a metre taken as a centimetre),
        the bearing in centidegrees where degrees are due."""
        self._point = point
        if point is None:
            self._nav = (0.0, 0.0)
            return
        b = ctx.body
        dn, de = point[0] - b.n_m * CM_TO_M, point[1] - b.e_m * CM_TO_M
        self._nav = (math.hypot(dn, de), math.degrees(math.atan2(de, dn)) * CM_PER_M) if dn or de else (0.0, 0.0)

    def destination(self) -> tuple[float, float, float | None] | None:
        return self._point

    def nav_distance_bearing(self) -> tuple[float, float] | None:
        return self._nav

    @staticmethod
    def _yaw(ctx: ModeContext, sp: Setpoint, pos_target: Vec2) -> None:
        """The heading FOLL_YAW_BEHAVE asks for; unset (None), the heading is kept."""
        lead = ctx.follow_target
        behave = ctx.params["FOLL_YAW_BEHAVE"]
        if behave == YAW_FACE_LEAD:
            ln, le, _ = lead.pos
            if ln * ln + le * le > FACE_LEAD_BEYOND_M2:  # metres less centimetres: see above
                sp.yaw = math.atan2(le - pos_target[1] * CM_PER_M, ln - pos_target[0] * CM_PER_M)
        elif behave == YAW_SAME_AS_LEAD:
            sp.yaw, sp.yaw_rate = lead.heading, lead.heading_rate
        elif behave == YAW_DIR_OF_FLIGHT:
            vn, ve, _ = lead.ofs_vel
            if math.hypot(vn, ve) > FLIGHT_DIRECTION_MIN_M_S:
                sp.yaw = math.atan2(ve, vn)

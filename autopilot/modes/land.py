"""LAND and RTL: descend where you are, or come home first; disarm once landed."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ..control.attitude import wrap_pi
from ..params import ParamStore
from ..results import Severity
from .auto_yaw import holds_in_rtl
from .base import Mode, Setpoint, hold_here, shifted, stopping_point
from .context import ModeContext
from .numbers import ModeNumber
from .rtl_altitude import return_height

if TYPE_CHECKING:
    from ..precland import Steer
from .waypoint_legs import WaypointLegs


GROUND_DISARM_S = 0.9  # LAND entered on the ground disarms this long after
ARMED_YAW_MARGIN_RAD = math.radians(2.0)  # RTL's loiter over home ends this close to the armed heading


def descent_rate_m_s(ctx: ModeContext) -> float:
    """ArduCopter's two-stage descent: fast high up, LAND_SPEED below LAND_ALT_LOW."""
    params = ctx.params
    alt = ctx.height_ref_d - ctx.body.d_m
    if alt > params["LAND_ALT_LOW"] / 100.0:
        return (params["LAND_SPEED_HIGH"] or params["WPNAV_SPEED_DN"]) / 100.0
    return params["LAND_SPEED"] / 100.0


def spool_down_s(params: ParamStore) -> float:
    """How long the motors take from flying to ground idle (MOT_SPOOL_TIM_DN, 0 = MOT_SPOOL_TIME)."""
    return params["MOT_SPOOL_TIM_DN"] or params["MOT_SPOOL_TIME"]


def descend_and_disarm(ctx: ModeContext, sp: Setpoint) -> bool:
    """The final descent shared by LAND, RTL and AUTO's land item; True once landed and disarmed.
    As ArduCopter, it disarms when landed with the motors spooled down to ground idle, which they
    begin once the land detector has fired."""
    rate = descent_rate_m_s(ctx)
    sp.vel_d = rate
    sp.speed_dn = rate
    if ctx.landed and ctx.armed and ctx.time_s - ctx.landed_at_s >= spool_down_s(ctx.params) - 1e-9:
        ctx.disarm("landed")
        return True
    return False


def steer_to_target(ctx: ModeContext, sp: Setpoint) -> Steer | None:
    """Precision landing's part of a landing that holds a point (LAND's, RTL's, AUTO's land item):
    fly to the target in its place, or where it last steered; what it asks of the rest, for
    `finish_precland` once the landing has set its descent (None: nothing)."""
    if sp.pos_ne is None or not ctx.precland_kind:  # (most vehicles have no precision landing)
        return None
    steer = ctx.precland_landing(ctx.params["LAND_SPEED"] / 100.0)
    if steer is not None and steer.ne is not None:
        sp.pos_ne = steer.ne
    return steer


def finish_precland(sp: Setpoint, steer: Steer | None) -> None:
    """Precision landing's descent over the landing's: a hold while far from its target (or in
    its failsafe), slow near it; a retry's climb and return to a height at the position
    controller's own speeds (WPNAV_SPEED_UP / _DN, as ArduCopter's retry flies)."""
    if steer is None:
        return
    if steer.pos_d is not None:
        sp.pos_d, sp.vel_d, sp.speed_dn, sp.speed_up = steer.pos_d, 0.0, None, None
    elif steer.rate_m_s is not None:
        sp.vel_d = sp.speed_dn = steer.rate_m_s


class Land(Mode):
    """Descend and disarm, holding the point where LAND began; without a position (no GPS fix)
    it comes down level instead, for the rest of the landing, as ArduCopter's LAND without GPS."""
    number = ModeNumber.LAND
    requires_position = False  # without home its descent measures height from the boot ground
    _hold_ne: tuple[float, float] | None  # None: comes down level (no position)
    _disarm_from_s: float

    def enter(self, ctx: ModeContext) -> str | None:
        self._hold_ne = hold_here(ctx)[0] if ctx.has_position() else None
        # Entered on the ground, ArduCopter disarms about a second later, not at once (measured on
        # its SITL: still armed 0.5 s after, "Disarming motors" stamped 1.1-1.5 s after the command).
        self._disarm_from_s = ctx.time_s + GROUND_DISARM_S if ctx.landed else ctx.time_s
        return None

    def position_reset(self, dn: float, de: float) -> None:
        self._hold_ne = shifted(self._hold_ne, dn, de)

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        sp.clear()
        if not ctx.has_position():
            self._hold_ne = None
        if self._hold_ne is None:
            sp.lean = (0.0, 0.0)
        else:
            sp.pos_ne = self._hold_ne
        steer = steer_to_target(ctx, sp)
        if ctx.time_s < self._disarm_from_s:
            sp.vel_d = sp.speed_dn = descent_rate_m_s(ctx)
            return
        descend_and_disarm(ctx, sp)
        finish_precland(sp, steer)

    def landed_state_hint(self, ctx: ModeContext) -> str | None:
        return None if ctx.landed else "LANDING"

    def controls_position(self, ctx: ModeContext) -> bool:
        return ctx.has_position()  # it holds its point with a fix, comes down level without


class Rtl(Mode):
    """Climb to RTL_ALT (or stay higher), fly home, loiter RTL_LOIT_TIME, land and disarm.
    The climb and the return are waypoint legs, as ArduCopter flies them with its wp_nav: the
    climb blends into the return leg, which stops over home. The nose on the way home follows
    WP_YAW_BEHAVIOR as an RTL's (auto_yaw.py); where that faces the way (1, 3), the loiter over
    home also turns back to the heading the vehicle was armed at, and lasts until within 2° of it
    (ArduCopter's RESET_TO_ARMED_YAW, measured: the descent faces the armed heading).

    With RTL_ALT_TYPE 1 the climb, the return and the loiter over home are flown above the terrain
    (rtl_altitude.py, the legs' terrain frame); the terrain failsafe in RTL starts it again above
    home (restart_without_terrain), as does an RTL the failsafe itself chose."""
    takes_speed_change = True
    number = ModeNumber.RTL
    plans_paths = True
    requires_position = True
    requires_home = True

    _return_d: float
    _hold_ne: tuple[float, float]
    _stage: str  # GROUND, CLIMB, RETURN, LOITER, LAND
    _loiter_until: float  # set when the stage LOITER begins
    _legs: WaypointLegs | None
    _above_terrain: bool  # _return_d is down from the terrain (less the height above it)
    requires_terrain_failsafe = True

    def __init__(self, disarm_on_land: bool = True):
        self.disarm_on_land = disarm_on_land  # AUTO's RTL item leaves the disarm to the mission's end
        # Until enter() (which may wait for home): nothing to fly to, as if still on the ground.
        self._stage = "GROUND"
        self._legs: WaypointLegs | None = None

    def enter(self, ctx: ModeContext) -> str | None:
        self._start(ctx, not ctx.terrain_failsafe_on)
        return None

    def restart_without_terrain(self, ctx: ModeContext) -> None:
        """ModeRTL::restart_without_terrain: the return starts again, above home."""
        ctx.notify("Restarting RTL - Terrain data missing", Severity.CRITICAL)
        if self._stage in ("CLIMB", "RETURN", "LOITER"):
            self._start(ctx, False)

    def _start(self, ctx: ModeContext, terrain_allowed: bool) -> None:
        height = return_height(ctx, terrain_allowed)
        self._above_terrain = height.above_terrain
        self._return_d = -height.alt_m if height.above_terrain else ctx.require_home()[2] - height.alt_m
        # The climb is over where the vehicle can stop (ArduCopter's origin point): a vehicle
        # entering RTL at speed flies on to it rather than back to where the mode changed.
        self._hold_ne, _ = stopping_point(ctx)
        # Entered on the ground it stays there armed, as ArduCopter's RTL does, until the
        # auto-disarm (DISARM_DELAY from arming) disarms it.
        self._stage = "GROUND" if ctx.landed else "CLIMB"
        self._loiter_until = math.inf
        self._legs = None

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        sp.clear()
        home_ne = ctx.require_home()[:2]
        sp.speed_xy = (ctx.params["RTL_SPEED"] / 100.0) or ctx.nav_speed_m_s
        if self._stage in ("CLIMB", "RETURN"):
            self._fly_home(ctx, sp, dt, home_ne, sp.speed_xy)
        if self._stage == "LOITER":
            sp.pos_ne, sp.pos_d = home_ne, self._return_d
            if self._above_terrain and self._legs is not None:  # over home's terrain, as last known
                self._legs.update(ctx, sp, dt)
                sp.yaw = None
            turned = True
            if not holds_in_rtl(ctx.params):
                sp.yaw = ctx.armed_yaw
                turned = abs(wrap_pi(ctx.attitude[2] - ctx.armed_yaw)) <= ARMED_YAW_MARGIN_RAD
            if ctx.time_s >= self._loiter_until and turned:
                self._stage = "LAND"
        if self._stage == "GROUND":
            sp.vel_d = sp.speed_dn = descent_rate_m_s(ctx)
        if self._stage == "LAND":
            sp.pos_ne = home_ne if not ctx.landed else None
            steer = steer_to_target(ctx, sp)
            if self.disarm_on_land:
                descend_and_disarm(ctx, sp)
            else:
                sp.vel_d = sp.speed_dn = descent_rate_m_s(ctx)
            finish_precland(sp, steer)

    def destination(self) -> tuple[float, float, float | None] | None:
        return self._legs.destination if self._legs is not None else None

    def nav_distance_bearing(self) -> tuple[float, float] | None:
        """While a path round the fence is flown: the way to the leg's end, not the corner."""
        return self._legs.way_to_final() if self._legs is not None and self._legs.avoiding else None

    def controls_position(self, ctx: ModeContext) -> bool:
        return ctx.armed  # disarmed on the ground ArduCopter's RTL runs no position controller

    def touched_down(self, ctx: ModeContext) -> bool:
        """Landed at the end of the return."""
        return self._stage == "LAND" and ctx.landed

    def _fly_home(self, ctx: ModeContext, sp: Setpoint, dt: float, home_ne: tuple[float, float],
                  speed: float) -> None:
        return_target = (home_ne[0], home_ne[1], self._return_d)
        legs = self._legs
        if legs is None:
            legs = self._legs = WaypointLegs(self.plans_paths)
            legs.auto_yaw.rtl = True
            climb_target = (self._hold_ne[0], self._hold_ne[1], self._return_d)
            legs.begin(ctx, climb_target, return_target, speed, terrain=self._above_terrain)
        if not legs.update(ctx, sp, dt):
            return
        if self._stage == "CLIMB":
            self._stage = "RETURN"
            legs.begin(ctx, return_target, None, speed, terrain=self._above_terrain)
        else:
            self._stage = "LOITER"
            self._loiter_until = ctx.time_s + ctx.params["RTL_LOIT_TIME"] / 1000.0

    def landed_state_hint(self, ctx: ModeContext) -> str | None:
        return "LANDING" if self._stage == "LAND" and not ctx.landed else None

"""The height RTL returns at, as ArduCopter's ModeRTL::compute_return_target works it out: above
home, or with RTL_ALT_TYPE 1 above terrain (the waypoint navigator's terrain source: the downward
rangefinder, else the terrain database).

RTL_ALT, at least RTL_CLIMB_MIN above the present height; within RTL_CONE_SLOPE times the distance
home, so a vehicle near home climbs little or not at all; not above an altitude fence's margin;
never below where it is. Above terrain, "the present height" is the vehicle's above the terrain
under it, and home's own height above its terrain is the least the return may be. Without the
terrain (no source, an unhealthy rangefinder, no database height here or at home) ArduCopter says
so and returns above home; so does an RTL the terrain failsafe started.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..results import Severity
from ..safety.fence_switch import ALT_MAX as FENCE_ALT_MAX
from ..terrain import FROM_RANGEFINDER
from .context import ModeContext

RTL_ALT_MIN_M = 2.0  # ArduCopter's RTL_ALT_MIN
RTL_MIN_CONE_SLOPE = 0.5  # a shallower RTL_CONE_SLOPE turns the cone off
ABOVE_TERRAIN = 1  # RTL_ALT_TYPE
NO_DATABASE = "RTL: no terrain data, using alt-above-home"
NO_RANGEFINDER = "RTL: rangefinder unhealthy, using alt-above-home"


@dataclass(frozen=True)
class ReturnHeight:
    alt_m: float  # above home, or above the terrain under the vehicle
    above_terrain: bool


def _terrain_heights(ctx: ModeContext) -> tuple[float, float] | None:
    """(the vehicle above its terrain, home above its terrain) [m], or None (said) without them."""
    source = ctx.terrain_source()
    b, home = ctx.body, ctx.require_home()
    if source == FROM_RANGEFINDER:
        offset = ctx.terrain_offset_m()
        if offset is None:
            ctx.notify(NO_RANGEFINDER, Severity.CRITICAL)
            return None
        return -b.d_m - offset, 0.0  # (home's own height is not asked: the target is RTL_ALT up)
    # the database's heights here and at home, not extrapolated (Location::change_alt_frame)
    offset = ctx.terrain_offset_at(b.n_m, b.e_m) if source is not None else None
    home_offset = ctx.terrain_offset_at(home[0], home[1]) if source is not None else None
    if offset is None or home_offset is None:
        ctx.notify(NO_DATABASE, Severity.CRITICAL)
        return None
    return -b.d_m - offset, -home[2] - home_offset


def return_height(ctx: ModeContext, terrain_allowed: bool = True) -> ReturnHeight:
    params, b = ctx.params, ctx.body
    home = ctx.require_home()
    current, target = home[2] - b.d_m, 0.0
    above_terrain = False
    if terrain_allowed and int(params["RTL_ALT_TYPE"]) == ABOVE_TERRAIN:
        heights = _terrain_heights(ctx)
        if heights is not None:
            current, target = heights
            above_terrain = True
    climb_min = max(0.0, params["RTL_CLIMB_MIN"] / 100.0)
    least = max(RTL_ALT_MIN_M, current + climb_min)
    target = max(max(target, 0.0), params["RTL_ALT"] / 100.0, least)
    slope = params["RTL_CONE_SLOPE"]
    if slope >= RTL_MIN_CONE_SLOPE:
        target = min(target, max(math.hypot(b.n_m - home[0], b.e_m - home[1]) * slope, least))
    if ctx.enabled_fences & FENCE_ALT_MAX:  # not above the ceiling's margin (measured above home)
        home_above_terrain = 0.0
        if above_terrain:
            home_offset = ctx.terrain_offset_at(home[0], home[1])
            home_above_terrain = 0.0 if home_offset is None else -home[2] - home_offset
        ceiling = params["FENCE_ALT_MAX"] - params["FENCE_MARGIN"]
        target = min(target, ceiling + home_above_terrain)
    return ReturnHeight(max(target, current), above_terrain)

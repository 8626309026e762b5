"""NAV_LOITER_TO_ALT (31): fly to the item's point, then climb or descend there to its altitude,
as ArduCopter's AUTO does.

The way there is a waypoint leg to the point at the item's altitude (lat/lon 0: here; altitude 0:
the present one). Once the vehicle is within WPNAV_RADIUS of the point horizontally (the height
need not be reached yet), it holds that position and goes up or down at the square-root
controller's rate on the height error (PSC_POSZ_P, WPNAV_ACCEL_Z), within WPNAV_SPEED_UP/DN,
until within 5 cm of the altitude or past it. ArduCopter returns from this item's verify before
its report: no MISSION_ITEM_REACHED and no "Reached command" text.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

from ...control.position import sqrt_controller
from ..base import Setpoint, stopping_point
from ..context import ModeContext
from ..waypoint_legs import WaypointLegs
from . import AutoItem

if TYPE_CHECKING:
    from ...mission.store import MissionItem
    from ..auto import Auto

ALT_REACHED_M = 0.05  # ArduCopter's "random numbers R US" 5 cm


class LoiterToAlt(AutoItem):
    reports_reached = False
    _legs: WaypointLegs | None  # the leg to the point; None once there
    _point: tuple[float, float]
    _target_d: float
    _hold_ne: tuple[float, float]
    _error_m: float  # height above the target last tick (0: not yet measured)
    _reached_alt: bool

    def start(self, auto: Auto, ctx: ModeContext, index: int, item: MissionItem) -> bool:
        n, e, d = auto.item_position(ctx, item)
        if item.z == 0:  # no altitude given: the present one
            d = ctx.body.d_m
        self._point, self._target_d = (n, e), d
        self._legs = WaypointLegs()
        self._legs.begin(ctx, (n, e, d), None)
        self._error_m, self._reached_alt = 0.0, False
        return True

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        legs = self._legs
        b = ctx.body
        if legs is not None:
            radius = ctx.params["WPNAV_RADIUS"] / 100.0
            pn, pe = self._point
            if (b.n_m - pn) ** 2 + (b.e_m - pe) ** 2 >= radius * radius:
                legs.update(ctx, sp, dt)
                return
            self._legs = None
            self._hold_ne = stopping_point(ctx)[0]
        params = ctx.params
        error = self._target_d - b.d_m  # height above the target [m]
        if abs(error) < ALT_REACHED_M or error * self._error_m < 0:
            self._reached_alt = True
        self._error_m = error
        up, down = params["WPNAV_SPEED_UP"] / 100.0, params["WPNAV_SPEED_DN"] / 100.0
        climb = sqrt_controller(-error, params["PSC_POSZ_P"], params["WPNAV_ACCEL_Z"] / 100.0)
        sp.pos_ne = self._hold_ne
        sp.vel_d = -min(max(climb, -down), up)
        sp.speed_up, sp.speed_dn = up, down

    def done(self, ctx: ModeContext) -> bool:
        return self._legs is None and self._reached_alt

"""Position-holding modes: LOITER (pilot sticks move the hold point) and BRAKE (stop, then hold)."""
from __future__ import annotations

import math
from functools import cached_property

from .base import Mode, Setpoint, hold_here, shifted, stick_deadzone
from .context import ModeContext
from .loiter_nav import LoiterNav
from .manual import PilotTakeoff, pilot_vertical
from .numbers import ModeNumber


STOPPED_M_S = 0.2  # below this horizontal speed braking is over and the point is held


class Loiter(Mode):
    number = ModeNumber.LOITER
    requires_position = True
    allows_arming = True
    _hold_ne: tuple[float, float]
    _hold_d: float

    @cached_property
    def takeoff(self) -> PilotTakeoff:
        return PilotTakeoff()

    def enter(self, ctx: ModeContext) -> str | None:
        self._hold_ne, self._hold_d = hold_here(ctx)
        self._nav: LoiterNav | None = None
        b = ctx.body
        if not ctx.landed and math.hypot(b.vn_m_s, b.ve_m_s) > STOPPED_M_S:
            # As AC_Loiter: entered at speed, the point moves on with the vehicle's velocity and
            # slows as the sticks say, rather than pulling the vehicle back to where it was.
            self._nav = LoiterNav(self._hold_ne, (b.vn_m_s, b.ve_m_s))
        return None

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        sp.clear()
        pilot = ctx.pilot
        fwd, right = pilot.pitch, pilot.roll  # past the channels' dead zones already
        nav = self._nav
        if nav is None:
            if fwd or right:  # the sticks take over from the held point
                nav = self._nav = LoiterNav(self._hold_ne)
            elif self._pushed_back(ctx, dt):  # a fence's margin does, from the drift
                nav = self._nav = LoiterNav(self._hold_ne, (ctx.body.vn_m_s, ctx.body.ve_m_s))
        if nav is not None:
            nav.update(ctx, fwd, right, dt)
            sp.pos_ne, sp.vel_ne, sp.accel_ne = nav.target, nav.vel, nav.accel
            self._hold_ne = nav.target
            if not (fwd or right) and nav.vel == (0.0, 0.0):
                self._nav = None  # stopped: the point is held again
        else:
            sp.pos_ne = self._hold_ne
        self._hold_d = pilot_vertical(ctx, sp, self._hold_d, dt, self.takeoff)
        sp.yaw_rate = stick_deadzone(pilot.yaw) * math.radians(ctx.params["PILOT_Y_RATE"])
        if ctx.landed:
            self._hold_ne = (ctx.body.n_m, ctx.body.e_m)
            self._nav = None

    def position_reset(self, dn: float, de: float) -> None:
        """LOITER's point is the position controller's own target, which the reset moves."""
        self._hold_ne = shifted(self._hold_ne, dn, de)
        if self._nav is not None:
            self._nav.target = shifted(self._nav.target, dn, de)

    @staticmethod
    def _pushed_back(ctx: ModeContext, dt: float) -> bool:
        """Whether a vehicle holding inside a fence's margin is to back away from it. ArduCopter's
        loiter velocity is never quite zero while it holds (it starts from the vehicle's), so the
        fences see the vehicle's own drift and push it back out."""
        if ctx.landed:
            return False
        b = ctx.body
        drift = (b.vn_m_s, b.ve_m_s, 0.0)
        return ctx.avoid_velocity(drift, ctx.params["LOIT_ACC_MAX"] / 100.0, dt) != drift


class Brake(Mode):
    """Stop as hard as the position controller allows, then hold. Arming is refused here."""
    number = ModeNumber.BRAKE
    requires_position = True
    _hold_ne: tuple[float, float] | None  # None while braking
    _hold_d: float

    def enter(self, ctx: ModeContext) -> str | None:
        self._hold_ne = None
        self._hold_d = ctx.body.d_m
        return None

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        sp.clear()
        self.brake_then_hold(ctx, sp)
        sp.pos_d = self._hold_d
        sp.yaw = ctx.attitude[2] if self._hold_ne else None

    def position_reset(self, dn: float, de: float) -> None:
        self._hold_ne = shifted(self._hold_ne, dn, de)

    def brake_then_hold(self, ctx: ModeContext, sp: Setpoint) -> None:
        """Zero velocity wanted until the vehicle is nearly stopped (or on the ground), then the
        point where it stopped is held."""
        b = ctx.body
        if self._hold_ne is None and (ctx.landed or math.hypot(b.vn_m_s, b.ve_m_s) < STOPPED_M_S):
            self._hold_ne = (b.n_m, b.e_m)
        sp.pos_ne = self._hold_ne

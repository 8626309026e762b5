"""Pilot-flown modes: STABILIZE (manual throttle) and ALT_HOLD (throttle stick = climb rate)."""
from __future__ import annotations

import math
from functools import cached_property

from ..pilot import CENTRED, CENTRED_MANUAL, PilotInput
from .base import Mode, Setpoint, stick_deadzone
from .context import ModeContext
from .numbers import ModeNumber

# What the expressions below give for centred sticks, bit for bit (ANGLE_MAX and PILOT_Y_RATE
# are positive): no lean, the pitch's zero negated, no yaw rate.
CENTRED_LEAN = (0.0, -0.0)


def pilot_lean_and_yaw(ctx: ModeContext, sp: Setpoint, pilot: PilotInput | None = None) -> None:
    """Lean from the roll and pitch sticks, yaw rate from the yaw stick (`pilot`: ctx.pilot, if
    the caller has it already: it is read at 100 Hz per vehicle)."""
    if pilot is None:
        pilot = ctx.pilot
    if pilot is CENTRED_MANUAL or pilot is CENTRED:  # no pilot input, the usual case: no parameter to read
        sp.lean, sp.yaw, sp.yaw_rate = CENTRED_LEAN, None, 0.0
        return
    params = ctx.params
    lean_max = math.radians(params["ANGLE_MAX"] / 100.0)
    # pilot.pitch positive = stick forward = nose down = negative pitch angle.
    sp.lean = (pilot.roll * lean_max, -pilot.pitch * lean_max)
    sp.yaw = None
    sp.yaw_rate = stick_deadzone(pilot.yaw) * math.radians(params["PILOT_Y_RATE"])


class Stabilize(Mode):
    number = ModeNumber.STABILIZE
    allows_arming = True
    manual_throttle = True

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        sp.clear()
        pilot = ctx.pilot
        pilot_lean_and_yaw(ctx, sp, pilot)
        sp.throttle = pilot.throttle


def pilot_climb_rate(ctx: ModeContext) -> float:
    """Throttle stick to a climb rate [m/s, up positive], as get_pilot_desired_climb_rate: a dead
    band of THR_DZ thousandths either side of the stick's centre holds; below it the rate scales to
    PILOT_SPEED_DN (0: PILOT_SPEED_UP) at the bottom, above it to PILOT_SPEED_UP at the top."""
    pilot, params = ctx.pilot, ctx.params
    throttle, mid = pilot.throttle, pilot.throttle_mid
    dead = min(max(params["THR_DZ"], 0.0), 400.0) / 1000.0
    top, bottom = mid + dead, mid - dead
    if throttle < bottom and bottom > 0:
        down = (params["PILOT_SPEED_DN"] or params["PILOT_SPEED_UP"]) / 100.0
        return down * (throttle - bottom) / bottom
    if throttle > top and top < 1:
        return params["PILOT_SPEED_UP"] / 100.0 * (throttle - top) / (1.0 - top)
    return 0.0


class PilotTakeoff:
    """ArduCopter's pilot takeoff (Mode::_TakeOff): from the ground, a stick asking to climb
    spools the motors up, then slews the throttle up over TKOFF_SLEW_TIME, and the vehicle leaves
    the ground once it reaches TKOFF_THR_MAX (at most 0.9); until then it stays down."""

    def __init__(self) -> None:
        self.asked_at_s: float | None = None

    def waiting(self, ctx: ModeContext, climb: float) -> bool:
        if not ctx.landed or climb <= 0.0:
            self.asked_at_s = None
            return False
        if self.asked_at_s is None:  # asked during the arming delay: the spool-up starts at its end
            self.asked_at_s = max(ctx.time_s, ctx.interlock_at_s)
        params = ctx.params
        # the motors spool up from ground idle first (MOT_SPOOL_TIME), then the throttle slews
        spool_s = params.get("MOT_SPOOL_TIME", 0.5) + \
            max(params["TKOFF_SLEW_TIME"], 0.25) * min(params["TKOFF_THR_MAX"], 0.9)
        return ctx.time_s - self.asked_at_s < spool_s


def pilot_vertical(ctx: ModeContext, sp: Setpoint, hold_d: float, dt: float,
                   takeoff: PilotTakeoff | None = None) -> float:
    """Throttle stick in ALT_HOLD/LOITER: climb at the stick's rate (slowed before an altitude
    fence), or hold the height it left; returns the height to hold from now on. With `takeoff`,
    a climb from the ground waits for the throttle's slew first."""
    climb = pilot_climb_rate(ctx)
    if climb:
        climb = ctx.avoid_climb(climb, dt)
    if takeoff is not None and takeoff.waiting(ctx, climb):
        sp.vel_d = 0.5  # pressed to the ground while the throttle slews up
        return ctx.body.d_m
    if climb != 0.0 or ctx.landed:
        sp.vel_d = -climb
        # the stick's rate is the limit: PILOT_SPEED_DN/UP, not the navigator's WPNAV_SPEED_DN/UP
        if climb < 0.0:
            sp.speed_dn = -climb
        elif climb > 0.0:
            sp.speed_up = climb
        return ctx.body.d_m
    sp.pos_d = hold_d
    return hold_d


class AltHold(Mode):
    number = ModeNumber.ALT_HOLD
    allows_arming = True

    def enter(self, ctx: ModeContext) -> str | None:
        self._hold_d = ctx.body.d_m
        return None

    @cached_property
    def takeoff(self) -> PilotTakeoff:
        return PilotTakeoff()

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        sp.clear()
        pilot_lean_and_yaw(ctx, sp)
        if not ctx.landed and sp.lean is not None:  # flying: pushed away from what a proximity sensor sees
            sp.lean = ctx.avoid_lean(sp.lean)
        self._hold_d = pilot_vertical(ctx, sp, self._hold_d, dt, self.takeoff)

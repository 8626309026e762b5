"""POSHOLD: the pilot's sticks lean the vehicle directly (as in STABILIZE, with the height held as
in ALT_HOLD); with the sticks centred it brakes to a stop and holds that point, as BRAKE does.

Flown by MAVLink alone (no sticks) it is a position hold: brake, then hold where it stopped."""
from __future__ import annotations

import math
from functools import cached_property

from .base import Setpoint, stick_deadzone
from .context import ModeContext
from .loiter import Brake
from .manual import PilotTakeoff, pilot_lean_and_yaw, pilot_vertical
from .numbers import ModeNumber


class PosHold(Brake):
    number = ModeNumber.POSHOLD
    allows_arming = True

    @cached_property
    def takeoff(self) -> PilotTakeoff:
        return PilotTakeoff()

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        sp.clear()
        pilot = ctx.pilot
        if stick_deadzone(pilot.roll) or stick_deadzone(pilot.pitch):
            pilot_lean_and_yaw(ctx, sp)
            self._hold_ne = None
        else:
            self.brake_then_hold(ctx, sp)
            sp.yaw_rate = stick_deadzone(pilot.yaw) * math.radians(ctx.params["PILOT_Y_RATE"])
        self._hold_d = pilot_vertical(ctx, sp, self._hold_d, dt, self.takeoff)

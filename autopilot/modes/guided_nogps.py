"""GUIDED_NOGPS: GUIDED's attitude target alone, for vehicles without a position (indoor, vision).

As ArduCopter's ModeGuidedNoGPS: entered in any state without a GPS; it flies only
SET_ATTITUDE_TARGET (guided_angle.AttitudeTarget), holding level and height until one comes and
again when the stream stops. Position and velocity targets, a guided waypoint and a takeoff
are taken (ArduCopter answers them as GUIDED's) and change nothing it flies.
"""
from __future__ import annotations

from ..views import Vector3
from .base import Setpoint
from .context import ModeContext
from .guided import Guided
from .numbers import ModeNumber


class GuidedNoGps(Guided):
    number = ModeNumber.GUIDED_NOGPS
    requires_position = False

    def enter(self, ctx: ModeContext) -> str | None:
        super().enter(ctx)
        self.submode = "angle"
        self.angle.start(ctx, ctx.attitude[2])
        return None

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        sp.clear()
        self.angle.fly(ctx, sp, dt)

    def set_attitude(self, ctx: ModeContext, attitude: Vector3 | None, rates: Vector3, climb_or_thrust: float,
                     use_thrust: bool) -> bool:
        self.angle.set(ctx, attitude, rates, climb_or_thrust, use_thrust)
        return True

    def user_takeoff(self, ctx: ModeContext, alt_above_home_m: float) -> None:
        pass  # accepted, as ArduCopter's (GUIDED's takeoff start), and never flown

    def goto(self, ctx, n, e, d, yaw=None, vel_ff=(0.0, 0.0, 0.0), terrain=False) -> bool:
        return True

    def set_target(self, ctx, pos, vel, accel, yaw, yaw_rate, yaw_relative=False, terrain=False) -> bool:
        return True

    def stop(self, ctx: ModeContext) -> bool:
        return True

    def pause(self, ctx: ModeContext, paused: bool) -> bool:
        return True

    def destination(self):
        return None

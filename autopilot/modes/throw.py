"""THROW: armed on the ground (or in a hand), motors quiet, the vehicle waits to be thrown (or
dropped: THROW_TYPE 1); once it is flying free it spools up, turns upright, climbs
THROW_ALT_ACSND (or sinks THROW_ALT_DCSND), stops, and then hands over to THROW_NEXTMODE if that
is a mode ArduCopter lets it go to. Entered only disarmed, as ArduCopter's. Never auto-disarms.

The detection is ArduCopter's (mode_throw.cpp): moving fast or in free fall, going the right way
up or down, nothing pushing it any more, and within THROW_ALT_MIN/MAX; confirmed when the
vertical speed then drops 2.5 m/s within half a second. Waiting, the motors are stopped
(THROW_MOT_START 0, the default) or idle (1). The height target is ArduCopter's: the height when
upright, THROW_ALT_ACSND above (or THROW_ALT_DCSND below), plus where a climb still going stops
at the brake's deceleration; the height is reached once within 0.5 m of it, or past it. The
position stage's target starts on the vehicle (ArduCopter's init_NE_controller), so it is
within 0.5 m at once: THROW_NEXTMODE is taken on the next update.
"""
from __future__ import annotations

import math

from firefly.sim.airframe import GRAVITY_M_S2

from .base import Mode, Setpoint, stopping_point
from .context import ModeContext
from .motor_throttle import stick_from_motor
from .numbers import ModeNumber

HIGH_SPEED_M_S = 5.0
VERTICAL_SPEED_M_S = 0.5
CONFIRM_WITHIN_S = 0.5
CONFIRM_DROP_M_S = 2.5  # of vertical speed lost within CONFIRM_WITHIN_S: falling free
UPRIGHT_COS = 0.866  # tilted less than 30 degrees
UPRIGHTING_THROTTLE = 0.5  # motor throttle, no angle boost: the most righting moment
NEAR_M = 0.5  # height error under which the height stage is done
# ArduCopter's BRAKE_MODE_SPEED_Z and BRAKE_MODE_DECEL_RATE: THROW's vertical speed and braking
CLIMB_M_S = 2.5
BRAKE_M_S2 = 7.5
MOTORS_RUNNING = 1  # THROW_MOT_START
DROP = 1  # THROW_TYPE
NEXT_MODES = (ModeNumber.AUTO, ModeNumber.GUIDED, ModeNumber.RTL, ModeNumber.LAND, ModeNumber.BRAKE,
              ModeNumber.LOITER)


class Throw(Mode):
    number = ModeNumber.THROW
    requires_position = True
    allows_arming = True
    auto_disarms = False
    skips_arming_delay = True

    def __init__(self) -> None:
        self.stage = "DISARMED"  # DETECTING, SPOOLING, UPRIGHTING, HEIGHT, POSITION
        self._next_tried = False
        self._fall_start_s = -math.inf
        self._fall_start_up = 0.0
        self._spooled_at_s = 0.0
        self._target_d = 0.0
        self._hold_ne = (0.0, 0.0)

    def enter(self, ctx: ModeContext) -> str | None:
        if ctx.armed:
            return "init failed"
        self.stage = "DISARMED"
        self._next_tried = False
        self._fall_start_s = -math.inf
        self.motors_stopped = False
        return None

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        sp.clear()
        self._advance(ctx)
        stage = self.stage
        if stage in ("DISARMED", "DETECTING", "SPOOLING"):
            sp.throttle, sp.rates = 0.0, (0.0, 0.0, 0.0)  # quiet: nothing steered until spooled up
            self.motors_stopped = stage != "SPOOLING" and int(ctx.params["THROW_MOT_START"]) != MOTORS_RUNNING
            return
        self.motors_stopped = False
        sp.lean, sp.yaw_rate = (0.0, 0.0), 0.0
        if stage == "UPRIGHTING":
            sp.throttle = stick_from_motor(UPRIGHTING_THROTTLE, ctx.params)
            return
        sp.pos_d = self._target_d
        sp.speed_up = sp.speed_dn = CLIMB_M_S
        if stage == "POSITION":
            sp.lean = None
            sp.pos_ne = self._hold_ne

    def _advance(self, ctx: ModeContext) -> None:
        """ArduCopter's stage machine: one step at most per update."""
        stage, b, now = self.stage, ctx.body, ctx.time_s
        if not ctx.armed:
            self.stage = "DISARMED"
        elif stage == "DISARMED":
            ctx.notify("waiting for throw")
            self.stage = "DETECTING"
        elif stage == "DETECTING" and self._detected(ctx):
            ctx.notify("throw detected - spooling motors")
            self.stage = "SPOOLING"
            self._spooled_at_s = now + ctx.params["MOT_SPOOL_TIME"]
        elif stage == "SPOOLING" and now >= self._spooled_at_s:
            ctx.notify("throttle is unlimited - uprighting")
            self.stage = "UPRIGHTING"
        elif stage == "UPRIGHTING" and math.cos(ctx.attitude[0]) * math.cos(ctx.attitude[1]) > UPRIGHT_COS:
            ctx.notify("uprighted - controlling height")
            self.stage = "HEIGHT"
            ctx.restart_position_control()  # the climb controlled from the climb rate it has now
            params = ctx.params
            drop = int(params["THROW_TYPE"]) == DROP
            rising = max(-b.vd_m_s, 0.0)  # a fall is not followed down: ArduCopter's no-descent start
            self._target_d = b.d_m + (params["THROW_ALT_DCSND"] if drop else -params["THROW_ALT_ACSND"]) \
                - rising * rising / (2.0 * BRAKE_M_S2)
        elif stage == "HEIGHT" and b.d_m - self._target_d < NEAR_M:
            ctx.notify("height achieved - controlling position")
            self.stage = "POSITION"
            self._hold_ne = stopping_point(ctx)[0]
        elif stage == "POSITION" and not self._next_tried:
            self._next_tried = True
            following = int(ctx.params["THROW_NEXTMODE"])
            if following in NEXT_MODES:
                ctx.set_mode(following)

    def _detected(self, ctx: ModeContext) -> bool:
        if not ctx.has_position():
            return False
        params, b, now = ctx.params, ctx.body, ctx.time_s
        up = -b.vd_m_s
        high_speed = b.vn_m_s ** 2 + b.ve_m_s ** 2 + b.vd_m_s ** 2 > HIGH_SPEED_M_S ** 2
        changing = up < -VERTICAL_SPEED_M_S if int(params["THROW_TYPE"]) == DROP else up > VERTICAL_SPEED_M_S
        fx, fy, fz = ctx.accel_body
        qw, qx, qy, qz = b.qw, b.qx, b.qy, b.qz
        down_force = 2.0 * (qx * qz - qw * qy) * fx + 2.0 * (qy * qz + qw * qx) * fy + (1.0 - 2.0 * (qx * qx + qy * qy)) * fz
        free_falling = down_force > -0.25 * GRAVITY_M_S2
        released = math.sqrt(fx * fx + fy * fy + fz * fz) < GRAVITY_M_S2
        alt = ctx.height_ref_d - b.d_m
        alt_min, alt_max = params["THROW_ALT_MIN"], params["THROW_ALT_MAX"]
        in_band = (alt_min == 0 or alt > alt_min) and (alt_max == 0 or alt < alt_max)
        if (free_falling or high_speed) and changing and released and in_band \
                and now - self._fall_start_s > CONFIRM_WITHIN_S:
            self._fall_start_s, self._fall_start_up = now, up
        return now - self._fall_start_s < CONFIRM_WITHIN_S and up - self._fall_start_up < -CONFIRM_DROP_M_S

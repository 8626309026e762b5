"""NAV_PAYLOAD_PLACE: fly to the point (if the item gives one) at the height flown, descend until
the payload touches down, release it (the gripper, when one is configured), wait PLDP_DELAY, climb
back to the height the descent began at. ArduCopter's PayloadPlace states and texts:

  descent   at PLDP_SPEED_DN (0: LAND_SPEED), no faster than WPNAV_SPEED_DN; param 1 > 0 is the
            most it may descend [m] ("PayloadPlace: Reached maximum descent": it climbs back
            without releasing)
  touchdown ArduCopter watches its thrust: once the descent is steady it takes the lowest thrust
            over 2 s, and the payload is down when the thrust stays under PLDP_THRESH of it for
            0.5 s ("PayloadPlace: payload release thrust threshold: F"); the land detector firing
            first says "PayloadPlace: landed". Firefly's vehicle gives its modes no thrust figure:
            the ground taking the weight shows as the descent stopping (under a tenth of its
            speed), and F is PLDP_THRESH of the thrust a steady descent needs, MOT_THST_HOVER.
  release   no gripper (GRIP_ENABLE 0): straight to the delay
  climb     done within the stopping distance of a tenth of WPNAV_SPEED_UP of the start height
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ...c_casts import as_uint16
from ..base import Setpoint
from ..context import ModeContext
from ..waypoint_legs import WaypointLegs
from . import AutoItem

if TYPE_CHECKING:
    from ...mission.store import MissionItem
    from ..auto import Auto

PREFIX = "PayloadPlace:"
CALIBRATION_S = 2.0  # the thrust a steady descent needs is measured this long
PLACED_CHECK_S = 0.5  # the touchdown seen this long
ESTABLISHED_SHARE = 0.95  # of the descent speed: the descent is steady
STOPPED_SHARE = 0.1  # of the descent speed: the ground took the weight
ASCENT_STOP_SHARE = 0.1  # of WPNAV_SPEED_UP: the climb's end counts from its stopping distance

FLY_TO, DESCENT, DELAY, ASCENT, DONE = "fly_to", "descent", "delay", "ascent", "done"


class PayloadPlace(AutoItem):
    _state: str
    _legs: WaypointLegs
    _ne: tuple[float, float]
    _start_d: float  # where the descent began (and the climb returns to) [m down]
    _hold_d: float
    _descent_max_m: float
    _speed: float
    _established_s: float
    _place_start_s: float
    _steady: bool

    def start(self, auto: Auto, ctx: ModeContext, index: int, item: MissionItem) -> bool:
        b = ctx.body
        self._descent_max_m = as_uint16(item.p1 * 100.0) / 100.0 if math.isfinite(item.p1) else 0.0
        self._ne = (b.n_m, b.e_m)
        if item.x != 0 or item.y != 0:  # the point, at the height flown now
            n, e, _ = ctx.ned_of(item.x * 1e-7, item.y * 1e-7, ctx.origin_alt_m)
            self._legs = WaypointLegs()
            self._legs.begin(ctx, (n, e, b.d_m), None)
            self._ne, self._state = (n, e), FLY_TO
        else:
            self._start_descent(ctx)
        return True

    def _start_descent(self, ctx: ModeContext) -> None:
        params = ctx.params
        speed = params["PLDP_SPEED_DN"] if params["PLDP_SPEED_DN"] > 0 else abs(params["LAND_SPEED"]) / 100.0
        self._speed = min(speed, params["WPNAV_SPEED_DN"] / 100.0)
        self._start_d = self._hold_d = ctx.body.d_m
        self._established_s = self._place_start_s = ctx.time_s
        self._steady = False
        self._state = DESCENT

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        state = self._state
        if state == FLY_TO:
            if self._legs.update(ctx, sp, dt):
                self._start_descent(ctx)
            return
        sp.pos_ne = self._ne
        if state == DESCENT:
            self._descend(ctx, sp)
        elif state == DELAY:
            sp.pos_d = self._hold_d
            if ctx.time_s - self._place_start_s >= PLACED_CHECK_S + ctx.params["PLDP_DELAY"]:
                self._state = ASCENT
        if self._state == ASCENT:
            sp.pos_d = self._start_d
            up = ctx.params["WPNAV_SPEED_UP"] / 100.0
            stop_m = 0.5 * (ASCENT_STOP_SHARE * up) ** 2 / (ctx.params["WPNAV_ACCEL_Z"] / 100.0)
            if ctx.body.d_m <= self._start_d + stop_m:
                self._state = DONE
        elif self._state == DONE:
            sp.pos_d = self._start_d

    def _descend(self, ctx: ModeContext, sp: Setpoint) -> None:
        now, b = ctx.time_s, ctx.body
        if self._descent_max_m > 0 and b.d_m - self._start_d > self._descent_max_m:
            ctx.notify(f"{PREFIX} Reached maximum descent")
            self._state = ASCENT
            return
        sp.vel_d = sp.speed_dn = self._speed
        if ctx.landed:
            ctx.notify(f"{PREFIX} landed")
            self._release(ctx)
            return
        if not self._steady:  # ArduCopter waits for its descent to reach speed
            self._steady = b.vd_m_s > ESTABLISHED_SHARE * self._speed
            self._established_s = self._place_start_s = now
        elif now - self._established_s < CALIBRATION_S or b.vd_m_s > STOPPED_SHARE * self._speed:
            self._place_start_s = now  # measuring, or still descending
        elif now - self._place_start_s > PLACED_CHECK_S:
            threshold = ctx.params["PLDP_THRESH"] * ctx.params["MOT_THST_HOVER"]
            ctx.notify(f"{PREFIX} payload release thrust threshold: {threshold:f}")
            self._release(ctx)

    def _release(self, ctx: ModeContext) -> None:
        self._hold_d = ctx.body.d_m  # ArduCopter restarts its height target here, no further down
        self._state = DELAY

    def done(self, ctx: ModeContext) -> bool:
        return self._state == DONE

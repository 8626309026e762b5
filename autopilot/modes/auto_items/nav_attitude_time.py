"""NAV_ATTITUDE_TIME: hold an attitude for a time, climbing at a rate, with no position control
(ArduCopter's nav_attitude_time_run). Param 1 the time [s] (whole seconds), 2 roll, 3 pitch,
4 yaw [deg, absolute], x the climb rate [m/s]. As AP_Mission stores them, a roll beyond 180, a
pitch beyond 90 or a yaw outside -180..360 degrees is 0. The lean is limited to the larger of
10 degrees and ANGLE_MAX; the climb to the navigation's speeds. Ends once the time has passed."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ...control.attitude import wrap_pi
from ..base import Setpoint
from ..context import ModeContext
from . import AutoItem

if TYPE_CHECKING:
    from ...mission.store import MissionItem
    from ..auto import Auto

LEAN_FLOOR_RAD = math.radians(10.0)


def _within(value: float, low: float, high: float) -> float:
    return value if math.isfinite(value) and low <= value <= high else 0.0


class NavAttitudeTime(AutoItem):
    _start_s: float
    _seconds: int
    _lean: tuple[float, float]
    _yaw: float
    _climb: float
    _hold_d: float

    def start(self, auto: Auto, ctx: ModeContext, index: int, item: MissionItem) -> bool:
        params = ctx.params
        self._start_s = ctx.time_s
        self._seconds = int(min(max(item.p1, 0.0), 65535.0)) if math.isfinite(item.p1) else 0
        # AP_Mission's fields: roll int16, pitch int8, yaw int16, climb int16 (x)
        roll = math.radians(int(_within(item.p2, -180.0, 180.0)))
        pitch = math.radians(int(_within(item.p3, -90.0, 90.0)))
        limit = max(LEAN_FLOOR_RAD, math.radians(params["ANGLE_MAX"] / 100.0))
        size = math.hypot(roll, pitch)
        scale = limit / size if size > limit else 1.0
        self._lean = (roll * scale, pitch * scale)
        self._yaw = wrap_pi(math.radians(int(_within(item.p4, -180.0, 360.0))))
        climb = float((int(item.x) + 32768) % 65536 - 32768)
        self._climb = max(-params["WPNAV_SPEED_DN"] / 100.0, min(params["WPNAV_SPEED_UP"] / 100.0, climb))
        self._hold_d = ctx.body.d_m
        return True

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        if ctx.landed and self._climb <= 0.0:  # on the ground: stay level there
            self._hold_d = ctx.body.d_m
            sp.pos_d, sp.lean = self._hold_d, (0.0, 0.0)
            return
        self._hold_d -= self._climb * dt
        sp.lean, sp.yaw = self._lean, self._yaw
        sp.pos_d, sp.vel_d = self._hold_d, -self._climb

    def done(self, ctx: ModeContext) -> bool:
        return ctx.time_s - self._start_s > self._seconds

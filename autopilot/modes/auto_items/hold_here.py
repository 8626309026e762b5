"""A navigation item that keeps the vehicle where it is while something else decides when it ends
(a delay, a script's timeout, a companion computer): the point and height it had at the start,
which it keeps (start_s, start_ne) for the timers and limits."""
from __future__ import annotations

from typing import TYPE_CHECKING

from ..base import Setpoint
from ..context import ModeContext
from . import AutoItem

if TYPE_CHECKING:
    from ...mission.store import MissionItem
    from ..auto import Auto


class HoldHere(AutoItem):
    _ne: tuple[float, float]
    _d: float
    start_s: float
    start_ne: tuple[float, float]

    def start(self, auto: Auto, ctx: ModeContext, index: int, item: MissionItem) -> bool:
        b = ctx.body
        self.start_s = ctx.time_s
        self.start_ne = self._ne = (b.n_m, b.e_m)
        self._d = b.d_m
        return True

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        if ctx.landed:  # on the ground: stay there, as ArduCopter's ground handling does
            b = ctx.body
            self._ne, self._d = (b.n_m, b.e_m), b.d_m
        sp.pos_ne, sp.pos_d = self._ne, self._d

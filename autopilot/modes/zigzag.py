"""ZIGZAG: LOITER, plus two stored points A and B between which the vehicle flies lines on the
pilot's command (ArduCopter's ModeZigZag, for spraying fields).

The pilot stores A and B with the ZigZag SaveWP switch (RC aux function 61, or
MAV_CMD_DO_AUX_FUNCTION): low stores A, high stores B; once both are stored, the same switch
sends the vehicle to the line through A (or B) perpendicular to AB, at the closest point, and
middle takes control back. With ZIGZ_AUTO_ENABLE the ZigZag Auto switch (aux 83) runs lines by
itself: a side step of ZIGZ_SIDE_DIST (ZIGZ_DIRECTION: forward, right, backward, left of the
vehicle), then across to the other line, ZIGZ_LINE_NUM times (0: none, -1: for ever), waiting
ZIGZ_WP_DELAY seconds at each end. Between lines it is LOITER, pilot's climb stick included.

The aux table calls `switch_save_wp(position)` and `switch_auto(position)` (0 low, 1 middle,
2 high); `save_point` / `run_auto` / `manual_control` are the same in words.
"""
from __future__ import annotations

import math

from ..results import Severity
from .base import Setpoint, stick_deadzone
from .context import ModeContext
from .loiter import Loiter
from .numbers import ModeNumber
from .waypoint_legs import WaypointLegs

WP_RADIUS_M = 3.0  # ZIGZAG_WP_RADIUS_CM: an end is reached this close
LINE_FOR_EVER = -1
STORING, MANUAL_REGAIN, AUTO = "STORING", "MANUAL_REGAIN", "AUTO"  # ArduCopter's stages
MANUAL, AB_MOVING, SIDEWAYS = "MANUAL", "AB_MOVING", "SIDEWAYS"  # ... and what the auto run does
DIRECTIONS = ("forward", "right", "backward", "left")  # ZIGZ_DIRECTION 0..3
LOW, MIDDLE, HIGH = 0, 1, 2  # an aux switch's positions
# Shown by ArduCopter only once ZIGZ_AUTO_ENABLE is set; read with its defaults until then.
DEFAULTS = {"ZIGZ_WP_DELAY": 0.0, "ZIGZ_SIDE_DIST": 4.0, "ZIGZ_DIRECTION": 0.0, "ZIGZ_LINE_NUM": 0.0}


class ZigZag(Loiter):
    number = ModeNumber.ZIGZAG
    point_a: tuple[float, float] | None
    point_b: tuple[float, float] | None
    stage: str
    auto_stage: str
    _ctx: ModeContext
    _legs: WaypointLegs
    _dest: tuple[float, float, float]
    _heading_to: str  # "A" or "B": the end flown to last
    _auto: bool
    _suspended: bool
    _line_count: int
    _reached: bool  # the navigator reached the end of the line flown
    _reached_at: float | None

    def enter(self, ctx: ModeContext) -> str | None:
        super().enter(ctx)
        self._ctx = ctx
        self.point_a = self.point_b = None
        self.stage = STORING
        self._legs = WaypointLegs()
        self._heading_to = "A"
        self._reached, self._reached_at = False, None
        self._init_auto()
        return None

    def _init_auto(self) -> None:
        self._auto = False
        self.auto_stage = MANUAL
        self._line_count = 0
        self._suspended = False

    def _param(self, name: str) -> float:
        return self._ctx.params.get(name, DEFAULTS[name])

    # ----- the aux switches ----------------------------------------------------------------------
    def switch_save_wp(self, position: int) -> None:
        """ZigZag SaveWP (aux 61): low A, middle back to the pilot, high B."""
        self._init_auto()
        if position == LOW:
            self.save_point("A")
        elif position == HIGH:
            self.save_point("B")
        else:
            self.manual_control(keep_target=False)

    def switch_auto(self, position: int) -> None:
        """ZigZag Auto (aux 83): high runs the lines, otherwise they pause."""
        if position == HIGH:
            self.run_auto()
        else:
            self.suspend_auto()

    def save_point(self, which: str) -> None:
        """Store A or B where the vehicle holds; with both stored, fly to that line instead."""
        ctx = self._ctx
        here = self._hold_ne
        if self.stage == STORING:
            if which == "A":
                self.point_a = here
            else:
                self.point_b = here
            ctx.notify(f"{self.text_name}: point {which} stored", Severity.INFO)
            a, b = self.point_a, self.point_b
            if a is not None and b is not None and a != b:
                self.stage = MANUAL_REGAIN
            return
        dest = self._line_point(which)
        if dest is None:
            return
        self._fly_to(dest)
        self.auto_stage = AB_MOVING
        self._heading_to = which
        if not self._auto or self._line_num() == LINE_FOR_EVER:
            ctx.notify(f"{self.text_name}: moving to {which}", Severity.INFO)
        else:
            self._line_count += 1
            ctx.notify(f"{self.text_name}: moving to {which} (line {self._line_count}/{self._line_num()})",
                       Severity.INFO)

    def run_auto(self) -> None:
        if not self._param_enabled() or self.stage != MANUAL_REGAIN:
            return
        self._auto = True
        if self._suspended and self._line_count <= self._line_num():
            if self.auto_stage == AB_MOVING:
                self._line_count -= 1
                self.save_point(self._heading_to)
            elif self.auto_stage == SIDEWAYS:
                self._fly_to(self._dest)
                self._say_side()
        else:
            self._move_to_side()

    def suspend_auto(self) -> None:
        if self._param_enabled() and self.auto_stage != MANUAL:
            self._suspended = True
            self.manual_control(keep_target=True)

    def manual_control(self, keep_target: bool) -> None:
        """Back to the pilot (LOITER), holding where the line ended or where the vehicle is."""
        if self.stage != AUTO:
            return
        self.stage = MANUAL_REGAIN
        b = self._ctx.body
        dest = self._legs.destination
        self._hold_ne = (dest[0], dest[1]) if keep_target and dest is not None else (b.n_m, b.e_m)
        self._nav = None  # LOITER's stick-driven point starts again from here
        self._auto = False
        self._ctx.notify(f"{self.text_name}: manual control", Severity.INFO)

    def _param_enabled(self) -> bool:
        return bool(self._ctx.params["ZIGZ_AUTO_ENABLE"])

    def _line_num(self) -> int:
        return int(min(max(self._param("ZIGZ_LINE_NUM"), LINE_FOR_EVER), 32767))

    # ----- where to fly ----------------------------------------------------------------------------
    def _line_point(self, which: str) -> tuple[float, float, float] | None:
        """The closest point of the line through A (or B) square to AB, within as far from it as
        the vehicle is (at least |AB|), at the height flown now."""
        a, b = self.point_a, self.point_b
        if a is None or b is None:
            return None
        start = a if which == "A" else b
        ab = (b[0] - a[0], b[1] - a[1])
        ab_len = math.hypot(*ab)
        if ab_len == 0.0:
            return None
        here = self._hold_ne if self.stage != AUTO else self._legs_position()
        scale = max(1.0, math.hypot(here[0] - start[0], here[1] - start[1]) / ab_len)
        p1 = (start[0] - ab[1] * scale, start[1] + ab[0] * scale)
        p2 = (start[0] + ab[1] * scale, start[1] - ab[0] * scale)
        n, e = _closest_on_segment(here, p1, p2)
        dest = self._legs.destination
        d = dest[2] if self.stage == AUTO and dest is not None else self._hold_d
        return n, e, d

    def _move_to_side(self) -> None:
        a, b = self.point_a, self.point_b
        if a is None or b is None or a == b:
            return
        direction = int(min(max(self._param("ZIGZ_DIRECTION"), 0), 3))
        ab = (b[0] - a[0], b[1] - a[1])
        yaw = self._ctx.attitude[2]
        c, s = math.cos(yaw), math.sin(yaw)
        if DIRECTIONS[direction] in ("right", "left"):
            sign = -s * ab[1] - c * ab[0]
            positive = sign * (1 if DIRECTIONS[direction] == "right" else -1) > 0
        else:
            sign = c * ab[1] - s * ab[0]
            positive = sign * (1 if DIRECTIONS[direction] == "forward" else -1) > 0
        side = (ab[1], -ab[0]) if positive else (-ab[1], ab[0])
        scale = min(max(self._param("ZIGZ_SIDE_DIST"), 0.1), 100.0) / math.hypot(*side)
        here = self._legs_position() if self.stage == AUTO else self._hold_ne
        d = self._hold_d
        self._dest = (here[0] + side[0] * scale, here[1] + side[1] * scale, d)
        self._fly_to(self._dest)
        self.auto_stage = SIDEWAYS
        self._say_side()

    def _say_side(self) -> None:
        direction = int(min(max(self._param("ZIGZ_DIRECTION"), 0), 3))
        self._ctx.notify(f"{self.text_name}: moving to {DIRECTIONS[direction]}", Severity.INFO)

    def _legs_position(self) -> tuple[float, float]:
        nav = self._legs.nav
        if nav is None:
            return self._hold_ne
        return nav.pos[0], nav.pos[1]

    def _fly_to(self, dest: tuple[float, float, float]) -> None:
        self._legs = WaypointLegs()
        self._legs.begin(self._ctx, dest, None)
        self.stage = AUTO
        self._reached, self._reached_at = False, None

    # ----- loop ---------------------------------------------------------------------------------
    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        if self.stage == AUTO:
            if ctx.landed or not ctx.armed:
                self.manual_control(keep_target=False)
            elif self._end_reached(ctx):
                self._line_done()
            else:
                sp.clear()
                sp.speed_xy = ctx.nav_speed_m_s
                self._reached = self._legs.update(ctx, sp, dt)
                yaw_stick = stick_deadzone(ctx.pilot.yaw)
                sp.yaw = None  # ArduCopter's lines keep the heading the pilot gives
                sp.yaw_rate = yaw_stick * math.radians(ctx.params["PILOT_Y_RATE"])
                self._hold_d = sp.pos_d if sp.pos_d is not None else ctx.body.d_m
                return
        if self.stage != AUTO:
            super().update(ctx, sp, dt)

    def _end_reached(self, ctx: ModeContext) -> bool:
        if not self._reached:
            return False
        dest = self._legs.destination
        b = ctx.body
        if dest is None or math.hypot(dest[0] - b.n_m, dest[1] - b.e_m) > WP_RADIUS_M:
            return False
        if self._reached_at is None:
            self._reached_at = ctx.time_s
        delay = int(min(max(self._param("ZIGZ_WP_DELAY"), 0), 127))
        return ctx.time_s - self._reached_at >= delay

    def _line_done(self) -> None:
        self._reached = False
        if not self._auto:
            self.manual_control(keep_target=True)
            return
        line_num = self._line_num()
        if line_num == LINE_FOR_EVER or self._line_count < line_num:
            if self.auto_stage == SIDEWAYS:
                self.save_point("B" if self._heading_to == "A" else "A")
            else:
                self._move_to_side()
        else:
            self._init_auto()
            self.manual_control(keep_target=True)


def _closest_on_segment(p: tuple[float, float], a: tuple[float, float], b: tuple[float, float]) -> tuple[float, float]:
    ab = (b[0] - a[0], b[1] - a[1])
    length2 = ab[0] * ab[0] + ab[1] * ab[1]
    if length2 == 0.0:
        return a
    k = min(max(((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1]) / length2, 0.0), 1.0)
    return a[0] + k * ab[0], a[1] + k * ab[1]

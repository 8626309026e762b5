"""Flight-mode interface and the setpoint a mode hands to the controllers.

A mode declares what it needs and allows (data, not branches in the vehicle), is entered with
`enter()` (which may refuse), fills the setpoint in `update()`, and tidies up in `exit()`.
Modes see the vehicle only through the small context interface documented on `Mode`.
"""
from __future__ import annotations

import math


class Setpoint:
    """What the controllers should achieve this tick. None = that loop is not controlled.

    Horizontal: pos_ne (hold/track a point) with vel_ne as feed-forward, or vel_ne alone, or
    lean (roll, pitch) for manual modes. Vertical: pos_d with vel_d feed-forward, or vel_d alone,
    or throttle (0..1) for manual modes. Yaw: yaw (heading) plus yaw_rate feed-forward.
    """
    __slots__ = ("pos_ne", "vel_ne", "lean", "pos_d", "vel_d", "throttle", "yaw", "yaw_rate",
                 "speed_xy", "speed_up", "speed_dn")

    def __init__(self):
        self.clear()

    def clear(self) -> None:
        self.pos_ne = None
        self.vel_ne = (0.0, 0.0)
        self.lean = None
        self.pos_d = None
        self.vel_d = 0.0
        self.throttle = None
        self.yaw = None
        self.yaw_rate = 0.0
        self.speed_xy = math.inf
        self.speed_up = None
        self.speed_dn = None

    def wants_climb(self, d_m: float) -> bool:
        """Whether this setpoint asks a landed vehicle to leave the ground."""
        if self.throttle is not None:
            return self.throttle > 0.05
        if self.pos_d is not None:
            return self.pos_d < d_m - 0.2
        return self.vel_d < -0.05


class Mode:
    """Base flight mode.

    The context `ctx` offers: ctx.body (estimated state: n_m, e_m, d_m, vn_m_s, ve_m_s, vd_m_s),
    ctx.attitude (roll, pitch, yaw), ctx.params, ctx.pilot (PilotInput), ctx.armed, ctx.landed,
    ctx.home_ned, ctx.time_s, ctx.has_position(), ctx.notify(text, severity), ctx.disarm(reason).
    """
    number: int = -1
    name: str = "?"
    requires_position = False
    allows_arming = False
    has_user_takeoff = False
    manual_throttle = False

    def enter(self, ctx) -> str | None:
        """Prepare to take over; return None to accept, or the reason for refusing."""
        return None

    def update(self, ctx, sp: Setpoint, dt: float) -> None:
        raise NotImplementedError

    def exit(self, ctx) -> None:
        pass

    def landed_state_hint(self, ctx) -> str | None:
        """'TAKEOFF' or 'LANDING' while the mode is doing either, else None."""
        return None


def hold_here(ctx) -> tuple:
    """Current horizontal position and height: the point a mode holds when it takes over."""
    b = ctx.body
    return (b.n_m, b.e_m), b.d_m


def stick_deadzone(value: float, zone: float = 0.05) -> float:
    """Pilot stick (-1..1) with a centre dead-zone, rescaled to stay continuous."""
    if abs(value) <= zone:
        return 0.0
    return math.copysign((abs(value) - zone) / (1.0 - zone), value)

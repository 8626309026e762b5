"""AUTOTUNE: entered, as ArduCopter's, only in flight (armed, auto-armed, off the ground) from
STABILIZE, ALT_HOLD, LOITER or POSHOLD, with the throttle stick off the bottom; anything else is
"init failed" (ArduCopter SITL's receiver holds the throttle at the bottom, so a ground station
alone never gets in). Once in, it flies the tuning dance (tuning/dance.py) on the real rate and
angle loops: twitches about each axis of AUTOTUNE_AXES while the height is held as ALT_HOLD holds
it. Pilot sticks pause the dance (the original gains fly the pilot's sticks) until they have been
centred for half a second. Leaving the mode restores the original gains; entering it again after
"AutoTune: Success" flies the tuned ones, and a disarm in AUTOTUNE saves them.
"""
from __future__ import annotations

from ..tuning.dance import Dance, TuneMode
from .base import Mode, Setpoint, stick_deadzone
from .context import ModeContext
from .loiter import Loiter
from .manual import AltHold, pilot_climb_rate
from .numbers import ModeNumber

TUNES_FROM = (ModeNumber.STABILIZE, ModeNumber.ALT_HOLD, ModeNumber.LOITER, ModeNumber.POSHOLD)
HOLDS_POSITION_FROM = (ModeNumber.LOITER, ModeNumber.POSHOLD)


class AutoTune(Mode):
    number = ModeNumber.AUTOTUNE

    def __init__(self) -> None:
        self._hold: Mode = AltHold()
        self._dance: Dance | None = None  # made on first entry; kept, as ArduCopter keeps its tune

    def enter(self, ctx: ModeContext) -> str | None:
        if ctx.mode_number not in TUNES_FROM or ctx.pilot.throttle <= 0.0:
            return "init failed"
        if not ctx.armed or not ctx.auto_armed or ctx.landed:
            return "init failed"
        self._hold = Loiter() if ctx.mode_number in HOLDS_POSITION_FROM else AltHold()
        self._hold.enter(ctx)
        if self._dance is None:
            self._dance = Dance(ctx.notify, ctx.use_gains, lambda gains: save(ctx, gains))
        self._dance.start(ctx.params, ctx.hover_thrust_share, ctx.time_s, ctx.attitude[2])
        return None

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        self._hold.update(ctx, sp, dt)
        dance = self._dance
        if dance is None:
            return
        if ctx.landed:  # ArduCopter's AutoTune disarms on touching down (a save, once tuned)
            if ctx.armed:
                ctx.disarm("landed")
            return
        b = ctx.body
        ask = dance.update(ctx.time_s, dt, ctx.attitude, (b.p_rad_s, b.q_rad_s, b.r_rad_s), pilot_moves(ctx))
        if ask is None:  # paused by the pilot, or done: the sticks fly on the gains loaded
            return
        sp.lean, sp.yaw, sp.yaw_rate, sp.rates = ask.lean, ask.yaw, 0.0, ask.rates
        sp.pos_ne = None

    def exit(self, ctx: ModeContext) -> None:
        if self._dance is not None:
            self._dance.stop()

    def on_disarm(self, ctx: ModeContext, flying_it: bool) -> None:
        if self._dance is not None and self._dance.mode is not TuneMode.UNINITIALISED:
            self._dance.disarmed(flying_it)

    def controls_position(self, ctx: ModeContext) -> bool:
        return self._hold.controls_position(ctx)


def pilot_moves(ctx: ModeContext) -> bool:
    """Any stick off its centre: roll, pitch, yaw, or the throttle outside its dead band."""
    pilot = ctx.pilot
    return bool(pilot.roll or pilot.pitch or stick_deadzone(pilot.yaw) or pilot_climb_rate(ctx))


def save(ctx: ModeContext, gains) -> None:
    """The tuned gains into the parameters, saved and announced (as AP_Param::save sends each)."""
    for name, value in gains.items():
        ctx.params.set(name, value, in_range=False)

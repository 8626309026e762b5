"""How each tune type moves the gains after a twitch (AC_AutoTune_Multi's updating_* functions),
and when it has seen enough: SUCCESS_COUNT agreeing twitches in a row. A twitch that followed a
gain change on the other side of the verdict is ignored once (ignore_next), as ArduCopter's."""
from __future__ import annotations

from dataclasses import dataclass

from .axes import SUCCESS_COUNT, Axis, TuneType
from .twitch import Twitch

RD_STEP = RP_STEP = SP_STEP = 0.05  # the fraction a gain moves by in one step
RD_MAX = 0.200
FLTE_MIN, FLTE_MAX = 1.0, 5.0       # yaw's error filter, tuned in place of its D [Hz]
RP_MIN, RP_MAX = 0.01, 2.0
SP_MIN, SP_MAX = 0.5, 40.0
D_MARGIN = 0.2                      # AUTOTUNE_D_UP_DOWN_MARGIN: below the target by this much, P rises
SP_BACKOFF = 0.9                    # Angle P ends at 90 % of the largest that passed
RP_ACCEL_MIN, Y_ACCEL_MIN = 4000.0, 1000.0  # cd/s/s

MIN_D_TEXT = "AutoTune: Min Rate D limit reached"
FAILED_D_TEXT = "AutoTune: Rate D Gain Determination Failed"
FAILED_P_TEXT = "AutoTune: Rate P Gain Determination Failed"
FAILED_SP_TEXT = "AutoTune: Angle P Gain Determination Failed"


@dataclass
class AxisGains:
    """The gains being tuned for one axis (yaw's Yaw(E) and Yaw(D) share one)."""
    rp: float
    rd: float
    sp: float
    accel: float  # cd/s/s
    flte: float = 0.0


class Rules:
    """The verdicts, with the success count and ignore_next they share within one tune type.
    Each rule returns the texts it says; `failed` is set when the tune cannot go on."""

    def __init__(self, aggressiveness: float, min_d: float):
        self.aggr, self.min_d = aggressiveness, min_d
        self.success = 0
        self.ignore_next = False
        self.failed = False

    def next_type(self) -> None:
        self.success = 0

    @property
    def done(self) -> bool:
        return self.success >= SUCCESS_COUNT

    def _d_limits(self, axis: Axis) -> tuple[float, float]:
        return (FLTE_MIN, FLTE_MAX) if axis.d_gain == "flte" else (self.min_d, RD_MAX)

    def apply(self, tune: TuneType, axis: Axis, g: AxisGains, t: Twitch) -> list[str]:
        if tune is TuneType.RATE_D_UP:
            return self._rate_d_up(axis, g, t)
        if tune is TuneType.RATE_D_DOWN:
            return self._rate_d_down(axis, g, t)
        if tune is TuneType.RATE_P_UP:
            return self._rate_p_up(axis, g, t)
        if tune is TuneType.ANGLE_P_DOWN:
            return self._angle_p_down(g, t)
        return self._angle_p_up(g, t)

    def _lower_p_then_d(self, axis: Axis, g: AxisGains) -> list[str]:
        """Overshot the target rate: less P; at its floor, less D; at D's floor, done."""
        g.rp -= g.rp * RP_STEP
        if g.rp >= RP_MIN:
            return []
        g.rp = RP_MIN
        return self._lower_d(axis, g)

    def _lower_d(self, axis: Axis, g: AxisGains) -> list[str]:
        d_min, _ = self._d_limits(axis)
        d = getattr(g, axis.d_gain)
        d -= d * RD_STEP
        if d <= d_min:
            setattr(g, axis.d_gain, d_min)
            self.success = SUCCESS_COUNT
            return [MIN_D_TEXT]
        setattr(g, axis.d_gain, d)
        return []

    def _p_to_target(self, axis: Axis, g: AxisGains, t: Twitch) -> list[str]:
        """The D tunes judge bounce only at about the target rate: past it, less P (then D);
        well short of it, more P."""
        if t.rate_max > t.target_rate:
            return self._lower_p_then_d(axis, g)
        if t.rate_max < t.target_rate * (1.0 - D_MARGIN):
            g.rp = min(g.rp + g.rp * RP_STEP, RP_MAX)
        return []

    def _rate_d_up(self, axis: Axis, g: AxisGains, t: Twitch) -> list[str]:
        if not t.target_rate * (1.0 - D_MARGIN) <= t.rate_max <= t.target_rate:
            return self._p_to_target(axis, g, t)
        if t.rate_max - t.rate_min > t.rate_max * self.aggr:  # it bounces back: D is enough
            self.ignore_next = True
            self.success += 1
        else:
            self._step_up(g, axis.d_gain, RD_STEP * 2.0, self._d_limits(axis)[1])
        return []

    def _rate_d_down(self, axis: Axis, g: AxisGains, t: Twitch) -> list[str]:
        if not t.target_rate * (1.0 - D_MARGIN) <= t.rate_max <= t.target_rate:
            return self._p_to_target(axis, g, t)
        if t.rate_max - t.rate_min < t.rate_max * self.aggr:  # no bounce back any more
            self._agree()
            return []
        self.ignore_next = True
        self.success = max(self.success - 1, 0)
        return self._lower_d(axis, g)

    def _rate_p_up(self, axis: Axis, g: AxisGains, t: Twitch) -> list[str]:
        target = t.target_rate
        d_min, _ = self._d_limits(axis)
        d = getattr(g, axis.d_gain)
        if t.rate_max > target * (1.0 + 0.5 * self.aggr):
            self.ignore_next = True
            self.success += 1
            return []
        if (target * (1.0 - D_MARGIN) < t.rate_max < target and
                t.rate_max - t.rate_min > t.rate_max * self.aggr and d > d_min):
            texts = []
            self.success = max(self.success - 1, 0)
            d -= d * RD_STEP
            if d <= d_min:
                d = d_min
                if axis.d_gain == "rd":  # yaw's filter may bottom out; a D may not
                    texts.append(FAILED_D_TEXT)
                    self.failed = True
            setattr(g, axis.d_gain, d)
            g.rp -= g.rp * RP_STEP
            if g.rp <= RP_MIN:
                g.rp = RP_MIN
                texts.append(FAILED_P_TEXT)
                self.failed = True
            return texts
        self._step_up(g, "rp", RP_STEP, RP_MAX)
        return []

    def _agree(self) -> None:
        """A twitch that passes: one more in a row (unless it is the one to ignore)."""
        if self.ignore_next:
            self.ignore_next = False
        else:
            self.success += 1

    def _step_up(self, g: AxisGains, gain: str, step: float, top: float) -> None:
        """Not there yet: the gain up a step (unless this twitch is the one to ignore); at its
        ceiling, the tune type is done."""
        if self.ignore_next:
            self.ignore_next = False
            return
        self.success = max(self.success - 1, 0)
        value = getattr(g, gain) * (1.0 + step)
        if value >= top:
            value = top
            self.success = SUCCESS_COUNT
        setattr(g, gain, value)

    def _angle_p_down(self, g: AxisGains, t: Twitch) -> list[str]:
        if t.angle_max < t.target_angle * (1.0 + 0.5 * self.aggr):
            self._agree()
            return []
        self.ignore_next = True
        self.success = max(self.success - 1, 0)
        g.sp -= g.sp * SP_STEP
        if g.sp <= SP_MIN:
            g.sp = SP_MIN
            self.failed = True
            return [FAILED_SP_TEXT]
        return []

    def _angle_p_up(self, g: AxisGains, t: Twitch) -> list[str]:
        target = t.target_angle
        if (t.angle_max > target * (1.0 + 0.5 * self.aggr) or
                (t.angle_max > target and t.rate_min < -t.rate_max * self.aggr)):
            self.ignore_next = True
            self.success += 1
        else:
            self._step_up(g, "sp", SP_STEP, SP_MAX)
        return []


def back_off(tune: TuneType, axis: Axis, g: AxisGains, t: Twitch) -> None:
    """The gains a finished tune type keeps (set_tuning_gains_with_backoff): ArduCopter's rate
    back-offs are 1.0 (kept as found); Angle P keeps 90 %, and the axis's acceleration limit
    becomes the largest the twitches reached."""
    if tune is TuneType.ANGLE_P_UP:
        g.sp = max(SP_MIN, g.sp * SP_BACKOFF)
        g.accel = max(Y_ACCEL_MIN if axis.index == 2 else RP_ACCEL_MIN, t.accel_max)

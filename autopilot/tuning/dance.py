"""The AUTOTUNE dance (AC_AutoTune and AC_AutoTune_Multi's state machine): level, twitch, move the
gains by the rules, level again with the twitch reversed, tune type after tune type, axis after
axis; then hold on the original gains until the pilot tests the tuned ones (AUTOTUNE entered
again) and a disarm in AUTOTUNE saves them.

It is sans-IO: the flight mode feeds it the vehicle's attitude and body rates each tick and flies
what it asks (an Ask); texts go out through `notify`, gain sets through `use_gains` (None = the
parameters' own), saved gains through `save`."""
from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from enum import Enum

from . import gains as gain_sets
from .gains import Params
from .axes import SEQUENCE, Axis, TuneType, completed_names, enabled_axes
from .rules import AxisGains, Rules, back_off
from .twitch import Outcome, Twitch

LEVEL_ANGLE_CD = 250.0
LEVEL_RATE_RP_CDS = 500.0
LEVEL_RATE_Y_CDS = 750.0
LEVEL_HOLD_S = 0.25          # level this long before a twitch
LEVEL_TIMEOUT_S = 2.0        # the level thresholds widen over this, up to twice; 3x: give up
PILOT_RELEASE_S = 0.5        # sticks centred this long: the dance resumes
PILOT_WARNING_S = 1.0
ANNOUNCE_S = 2.0
# Twitch sizes (cd/s, and shares of ANGLE_MAX)
TARGET_RATE_RP, TARGET_MIN_RATE_RP = 18000.0, 4500.0
TARGET_RATE_Y, TARGET_MIN_RATE_Y = 9000.0, 1500.0
ANGLE_MAX_RP, ANGLE_MIN_RP = 1.0 / 2.0, 1.0 / 3.0
ANGLE_MAX_Y, ANGLE_MIN_Y = 1.0, 1.0 / 6.0
ABORT_TILT, ABORT_BACKWARDS = 2.5 / 3.0, 1.0 / 5.0
YAW_FILTER_HZ = 10.0
# The rate loop the largest step is reckoned for (ArduCopter's max_rate_step_bf_*: the step that
# saturates the output within four ticks of a 400 Hz loop, through the D filter)
RATE_LOOP_DT_S = 1.0 / 400.0
RATE_OUT_MAX = 1.0


class TuneMode(Enum):
    UNINITIALISED = 0
    TUNING = 1
    FINISHED = 2
    FAILED = 3
    VALIDATING = 4


class Ask:
    """What the dance asks the vehicle to fly this tick: lean (roll, pitch) [rad] and heading yaw
    [rad], or body rates (p, q, r) [rad/s] in their place (a rate twitch)."""
    __slots__ = ("lean", "yaw", "rates")

    def __init__(self) -> None:
        self.lean: tuple[float, float] = (0.0, 0.0)
        self.yaw = 0.0
        self.rates: tuple[float, float, float] | None = None


def cd(rad: float) -> float:
    return math.degrees(rad) * 100.0


def wrap_180_cd(angle: float) -> float:
    return (angle + 18000.0) % 36000.0 - 18000.0


def filter_alpha(hz: float, dt: float) -> float:
    return 1.0 if hz <= 0 else dt / (dt + 1.0 / (2.0 * math.pi * hz))


class Dance:
    def __init__(self, notify: Callable[[str, int], None], use_gains: Callable[[Mapping[str, float] | None], None],
                 save: Callable[[Mapping[str, float]], None]):
        self.notify, self.use_gains, self.save = notify, use_gains, save
        self.mode = TuneMode.UNINITIALISED
        self.completed: tuple[Axis, ...] = ()
        self.axes: tuple[Axis, ...] = ()
        self.ask = Ask()
        self._loaded: str | None = None  # the gain set in use: "original", "between", "test", "tuned"

    # ----- entry, exit, disarm (AC_AutoTune::init_internals, stop, disarmed) -------------------
    def start(self, params: Params, hover_share: float, now_s: float, yaw: float) -> None:
        if self.mode in (TuneMode.UNINITIALISED, TuneMode.FAILED):
            self._begin(params, now_s, yaw)
            self.mode = TuneMode.TUNING
            self.notify("AutoTune: Started", 6)
        elif self.mode is TuneMode.TUNING:  # resumed where it was
            self._level_from(now_s)
            self.desired_yaw = yaw
            self.notify("AutoTune: Started", 6)
        else:
            self.mode = TuneMode.VALIDATING
            self.notify(f"AutoTune: Pilot Testing gains for {completed_names(self.completed)}", 5)
        self.hover_share = min(max(hover_share, 0.1), 0.5)
        self.pilot_override = False
        self._loaded = None

    def stop(self) -> None:
        """Leaving the mode: back to the original gains (the dance keeps its place)."""
        self._load("original")
        self.notify("AutoTune: Stopped", 6)

    def disarmed(self, in_autotune: bool) -> None:
        """A disarm in AUTOTUNE saves what was tuned; one in another mode forgets it."""
        if not in_autotune:
            self._reset()
        elif self.completed:
            self.save(gain_sets.tuned(self.tune, self.completed, self.axes))
            self.notify(f"AutoTune: Saved gains for {completed_names(self.completed)}", 5)
            self._reset()

    def _reset(self) -> None:
        self.mode = TuneMode.UNINITIALISED
        self.completed = ()

    def _begin(self, params: Params, now_s: float, yaw: float) -> None:
        """backup_gains_and_initialise: the originals kept, the first axis and tune type."""
        self.params = params
        self.axes = enabled_axes(int(params["AUTOTUNE_AXES"]))
        self.aggr = min(max(params["AUTOTUNE_AGGR"], 0.05), 0.2)
        self.rules = Rules(self.aggr, params["AUTOTUNE_MIN_D"])
        self.orig = {a.rate: gain_sets.original(params, a) for a in self.axes}
        self.tune = {rate: AxisGains(**vars(g)) for rate, g in self.orig.items()}
        yaw_d = next((a for a in self.axes if a.d_gain == "rd" and a.index == 2), None)
        if yaw_d is not None and self.tune["YAW"].rd == 0:
            self.tune["YAW"].rd = params["AUTOTUNE_MIN_D"]
        if any(a.d_gain == "flte" for a in self.axes) and self.tune["YAW"].flte == 0:
            self.tune["YAW"].flte = 2.5  # AUTOTUNE_FLTE_MIN
        self.between = gain_sets.between_twitches(self.orig, self.axes)
        self.completed = ()
        self.axis_at = 0
        self.type_at = 0
        self.positive = False
        self.step_scaler = 1.0
        self.desired_yaw = yaw
        self.last_announce_s = -math.inf
        self.last_warning_s = -math.inf
        self.override_s = 0.0
        self.twitch: Twitch | None = None
        self._level_from(now_s)

    def _level_from(self, now_s: float) -> None:
        self.twitch = None
        self.step_start_s = self.level_start_s = now_s

    @property
    def axis(self) -> Axis:
        return self.axes[self.axis_at]

    @property
    def tune_type(self) -> TuneType:
        return SEQUENCE[self.type_at]

    # ----- every tick ------------------------------------------------------------------------
    def update(self, now_s: float, dt: float, attitude: tuple[float, float, float],
               gyro: tuple[float, float, float], pilot_active: bool) -> Ask | None:
        """The dance's ask this tick, or None: fly the pilot's sticks (on the gains now loaded)."""
        mode = self.mode
        if not self.axes:  # AUTOTUNE_AXES 0: nothing to tune, the sticks fly
            return None
        if mode is TuneMode.VALIDATING:
            self._load("tuned")
            return None
        if mode is not TuneMode.TUNING:
            self._load("original")
            return None
        if pilot_active:
            if not self.pilot_override:
                self.pilot_override = True
            self.override_s = now_s
        elif self.pilot_override and now_s - self.override_s > PILOT_RELEASE_S:
            self.pilot_override = False
            self.twitch = None
            self.step_start_s = self.level_start_s = now_s
            self.desired_yaw = attitude[2]
        if self.pilot_override:
            if now_s - self.last_warning_s > PILOT_WARNING_S:
                self.notify("AutoTune: pilot overrides active", 6)
                self.last_warning_s = now_s
            self._load("original")
            return None
        ask = self._control(now_s, dt, attitude, gyro)
        if self.mode is TuneMode.TUNING and now_s - self.last_announce_s >= ANNOUNCE_S:
            self.notify(f"AutoTune: {self.axis.name} {self.tune_type.value} {self.rules.success * 25}%", 6)
            self.last_announce_s = now_s
        return ask

    def _control(self, now_s: float, dt: float, attitude, gyro) -> Ask:
        ask = self.ask
        ask.rates = None
        if self.twitch is None:
            self._load("between")
            self._ask_level(ask)
            if not self._level(now_s, attitude, gyro):
                self.step_start_s = now_s
            if now_s - self.step_start_s > LEVEL_HOLD_S:
                self._start_twitch(now_s, attitude, gyro)
                self._ask_twitch(ask, attitude)
            return ask
        outcome = self._measure(now_s, dt, attitude, gyro)
        self._ask_twitch(ask, attitude)
        if outcome is Outcome.RUNNING:
            return ask
        if outcome is Outcome.UPDATE_GAINS:
            self._update_gains()
        if self.mode is TuneMode.TUNING:  # done or failed: the original gains, already loaded
            self._load("between")
        self._ask_level(ask)
        self.positive = not self.positive
        self._level_from(now_s)
        return ask

    def _ask_level(self, ask: Ask) -> None:
        ask.lean = (0.0, 0.0)
        ask.yaw = self.desired_yaw
        ask.rates = None

    def _level(self, now_s: float, attitude, gyro) -> bool:
        """currently_level(): within thresholds that widen while levelling takes long (gyro
        compared signed, as ArduCopter compares it)."""
        waited = now_s - self.level_start_s
        if waited > 3 * LEVEL_TIMEOUT_S:
            self.notify("AutoTune: Failed to level, please tune manually", 2)
            self.mode = TuneMode.FAILED
        widen = min(max(waited / LEVEL_TIMEOUT_S, 0.0), 2.0)
        roll, pitch, yaw = attitude
        return (abs(cd(roll)) <= widen * LEVEL_ANGLE_CD and abs(cd(pitch)) <= widen * LEVEL_ANGLE_CD and
                abs(wrap_180_cd(cd(yaw - self.desired_yaw))) <= widen * LEVEL_ANGLE_CD and
                cd(gyro[0]) <= widen * LEVEL_RATE_RP_CDS and cd(gyro[1]) <= widen * LEVEL_RATE_RP_CDS and
                cd(gyro[2]) <= widen * LEVEL_RATE_Y_CDS)

    # ----- one twitch --------------------------------------------------------------------------
    def _max_rate_step(self, axis: Axis, g: AxisGains) -> float:
        """The rate step [rad/s] that saturates the rate loop's output in four ticks."""
        dt = RATE_LOOP_DT_S
        alpha = filter_alpha(self.params[f"ATC_RAT_{axis.rate}_FLTD"], dt)
        if axis.index == 2:
            alpha = min(alpha, filter_alpha(g.flte, dt))
        kd = g.rd if axis.d_gain == "rd" else 0.0
        rate = 2.0 * self.hover_share * RATE_OUT_MAX / ((1.0 - alpha) ** 3 * alpha * kd / dt + g.rp)
        limit = self.params.get(("ATC_RATE_R_MAX", "ATC_RATE_P_MAX", "ATC_RATE_Y_MAX")[axis.index], 0.0) or 0.0
        return min(rate, math.radians(limit)) if limit > 0 else rate

    def _start_twitch(self, now_s: float, attitude, gyro) -> None:
        axis, g, tune = self.axis, self.tune[self.axis.rate], self.tune_type
        self._load("test")
        self.step_start_s = now_s
        lean_max = self.params["ANGLE_MAX"]
        step = self._max_rate_step(axis, g)
        if axis.index == 2:
            top = max(TARGET_MIN_RATE_Y, self.step_scaler * TARGET_RATE_Y)
            target_rate = min(max(cd(step * 0.75), TARGET_MIN_RATE_Y), top)
            target_angle = min(max(cd(step / g.sp * 0.75), lean_max * ANGLE_MIN_Y), lean_max * ANGLE_MAX_Y)
            angle_abort = lean_max * ANGLE_MAX_Y
            filter_hz = YAW_FILTER_HZ if axis.d_gain == "flte" else 2.0 * self.params["ATC_RAT_YAW_FLTD"]
        else:
            top = max(TARGET_MIN_RATE_RP, self.step_scaler * TARGET_RATE_RP)
            target_rate = min(max(cd(step), TARGET_MIN_RATE_RP), top)
            target_angle = min(max(cd(step / g.sp), lean_max * ANGLE_MIN_RP), lean_max * ANGLE_MAX_RP)
            angle_abort = lean_max * ANGLE_MAX_RP
            filter_hz = 2.0 * self.params[f"ATC_RAT_{axis.rate}_FLTD"]
        self.start_rate = cd(gyro[axis.index])
        self.start_angle = cd(attitude[axis.index])
        sign = 1.0 if self.positive else -1.0
        self.sign = sign
        if tune.steps_angle:
            test_target = target_angle * (1.0 + 0.5 * self.aggr)
        elif tune is TuneType.RATE_P_UP:
            test_target = target_rate * (1.0 + 0.5 * self.aggr)
        else:
            test_target = target_rate
        self.twitch = Twitch(tune.steps_angle, target_rate, target_angle, angle_abort, self.aggr,
                             self.start_rate if tune.steps_angle else 0.0, filter_hz, now_s, test_target,
                             sign * self.start_rate if tune.steps_angle else 0.0)
        # An angle step is one move of the attitude target, held: from level, by the step
        lean = [0.0, 0.0]
        self.step_yaw = self.desired_yaw
        if axis.index == 2:
            self.step_yaw = self.desired_yaw + math.radians(sign * target_angle / 100.0)
        else:
            lean[axis.index] = math.radians(sign * target_angle / 100.0)
        self.step_lean = (lean[0], lean[1])

    def _ask_twitch(self, ask: Ask, attitude) -> None:
        twitch, axis = self.twitch, self.axis
        if twitch is None:
            return
        if twitch.steps_angle:
            ask.lean, ask.yaw, ask.rates = self.step_lean, self.step_yaw, None
            return
        rates = [0.0, 0.0, 0.0]
        rates[axis.index] = math.radians((self.sign * twitch.target_rate + self.start_rate) / 100.0)
        ask.rates = (rates[0], rates[1], rates[2])
        ask.yaw = attitude[2]

    def _measure(self, now_s: float, dt: float, attitude, gyro) -> Outcome:
        twitch, axis, sign = self.twitch, self.axis, self.sign
        assert twitch is not None
        self._load("test")
        angle_cd = cd(attitude[axis.index])
        turned = angle_cd - self.start_angle
        lean_angle = sign * (wrap_180_cd(turned) if axis.index == 2 else turned)
        rate_cds = cd(gyro[axis.index])
        rate = sign * rate_cds if twitch.steps_angle else sign * (rate_cds - self.start_rate)
        outcome = twitch.update(lean_angle, rate, now_s, dt)
        if outcome is Outcome.SHRINK:
            if self.step_scaler > 0.2:
                self.step_scaler *= 0.9
            else:
                self.notify("AutoTune: Twitch Size Determination Failed", 2)
                self.mode = TuneMode.FAILED
            outcome = Outcome.ABORT
        lean_max = self.params["ANGLE_MAX"]
        roll, pitch = attitude[0], attitude[1]
        tilt_cd = cd(math.acos(max(-1.0, min(1.0, math.cos(roll) * math.cos(pitch)))))
        if lean_angle <= -lean_max * ABORT_BACKWARDS or tilt_cd > lean_max * ABORT_TILT:
            outcome = Outcome.ABORT
        if axis.index == 2:
            self.desired_yaw = attitude[2]
        return outcome

    # ----- after a twitch -----------------------------------------------------------------------
    def _update_gains(self) -> None:
        axis, tune, twitch = self.axis, self.tune_type, self.twitch
        assert twitch is not None
        g = self.tune[axis.rate]
        for text in self.rules.apply(tune, axis, g, twitch):
            self.notify(text, 2 if "Failed" in text else 6)
        if self.rules.failed:
            self.mode = TuneMode.FAILED
            self.rules.failed = False
        if not self.rules.done:
            return
        self.rules.next_type()
        self.step_scaler = 1.0
        back_off(tune, axis, g, twitch)
        self.type_at += 1
        if self.type_at < len(SEQUENCE):
            return
        self.type_at = 0
        self._report(axis, g)
        self.completed += (axis,)
        if self.axis_at + 1 < len(self.axes):
            self.axis_at += 1
            return
        self.mode = TuneMode.FINISHED
        self.notify("AutoTune: Success", 5)
        self._load("original")

    def _report(self, axis: Axis, g: AxisGains) -> None:
        yaw = axis.index == 2
        ri = g.rp * (gain_sets.YAW_PI_RATIO_FINAL if yaw else gain_sets.PI_RATIO_FINAL)
        rd = 0.0 if axis.d_gain == "flte" else g.rd
        self.notify(f"AutoTune: {axis.name} complete", 5)
        self.notify(f"AutoTune: {axis.name} Rate: P:{g.rp:0.3f}, I:{ri:0.3f}, D:{rd:0.4f}", 5)
        self.notify(f"AutoTune: {axis.name} Angle P:{g.sp:0.3f}, Max Accel:{g.accel:0.0f}", 5)

    # ----- gain sets ---------------------------------------------------------------------------
    def _load(self, which: str) -> None:
        if self._loaded == which:
            return
        self._loaded = which
        if which == "original":
            self.use_gains(None)
        elif which == "between":
            self.use_gains(self.between)
        elif which == "test":
            self.use_gains(gain_sets.testing(self.between, self.axis, self.tune[self.axis.rate]))
        else:
            self.use_gains(gain_sets.tuned(self.tune, self.completed, self.axes))

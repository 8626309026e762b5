"""The receiver and the ground station's overrides read together, as ArduCopter's RC_Channels.

`read(now_s)` runs at the flight-mode rate: a channel takes its override while one is in force,
else the receiver's latest frame; with neither new (no frames, no override), the channels keep
their last values and `read` says so (the radio failsafe counts from `updated_at_s`). The sticks
(`sticks()`) go through RCMAP_* and each channel's calibration, cached until a PWM or a
parameter changes. The flight-mode switch and the aux switches are debounced here; the vehicle
acts on what they report.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

from ..pilot import CENTRED_MANUAL, PilotInput
from .aux import AUX_FUNCTIONS
from .channels import (Calibration, mode_switch_position, stick, stick_pwm, switch_position, throttle, throttle_mid,
                       throttle_pwm)
from .overrides import CHANNELS, Overrides
from .switches import Debounced

if TYPE_CHECKING:
    from firefly.sim.sensors import RcReceiver

    from ..params import ParamStore

# RC_OPTIONS bits (RC_Channels::Option)
IGNORE_RECEIVER, IGNORE_OVERRIDES = 1 << 0, 1 << 1
ARMING_CHECK_THROTTLE, ARMING_SKIP_CHECK_RPY = 1 << 5, 1 << 6  # arming wants the throttle / sticks neutral
ALLOW_SWITCH_REVERSE = 1 << 7  # a reversed channel reverses its switch


class RadioInput:
    def __init__(self, receiver: RcReceiver, params: ParamStore):
        self.receiver = receiver
        self.params = params
        self.overrides = Overrides()
        self.radio_in = [0] * CHANNELS  # each channel's PWM [us] as last read, 0 = never
        self.updated_at_s = 0.0  # sim time of the last read with a frame or an override
        self.version = 0  # bumped whenever a channel's value changes
        self.mode_switch = Debounced()
        # The switches are to be read again: a channel moved, a parameter changed, a switch is
        # still settling, or the flight-mode switch was reset (read at every tick while set).
        self.switches_dirty = True
        self.aux_switches = [Debounced() for _ in range(CHANNELS)]
        self._aux_seen = [False] * CHANNELS  # the channel's switch has been read with its option
        # The sticks as last worked out (sticks()): read at every tick by the flight mode, so
        # kept rather than worked out on each read.
        self.pilot: PilotInput = CENTRED_MANUAL
        self._last_frame: tuple[int, ...] | None = None
        self._configure()
        params.on_change(self._param_changed)

    def _configure(self) -> None:
        """The parameters read at every tick, cached until one changes."""
        p = self.params
        self._options = int(p["RC_OPTIONS"])
        self._stick_channels = tuple(int(p[role]) for role in ("RCMAP_ROLL", "RCMAP_PITCH", "RCMAP_THROTTLE",
                                                                "RCMAP_YAW"))
        self.aux_channels = [(i, int(p[f"RC{i + 1}_OPTION"])) for i in range(CHANNELS)
                             if int(p[f"RC{i + 1}_OPTION"])]
        self._work_out_sticks()
        self._last_frame = None
        self.switches_dirty = True

    def _param_changed(self, name: str, value: float) -> None:
        if name.startswith("RC") and name.endswith("_OPTION") and name[2:-len("_OPTION")].isdigit():
            index = int(name[2:-len("_OPTION")]) - 1
            self._aux_seen[index] = False
            self.aux_switches[index].forget()
        if name.startswith(("RC", "FLTMODE")):  # RCMAP_*, RCn_*, RC_*, the mode switch
            self._configure()

    # ----- the channels ------------------------------------------------------------------------
    def read(self, now_s: float) -> bool:
        """Take the receiver's frame and the overrides in force; True if a channel changed. With
        neither a frame nor a new override, nothing is read (updated_at_s stays)."""
        frame = self.receiver.channels_us()
        overrides = self.overrides
        if self._options & IGNORE_RECEIVER:
            frame = None
        if frame is None and not overrides.new:
            return False
        self.updated_at_s = now_s
        if frame is self._last_frame and not overrides.new and not overrides.held:
            return False  # the usual tick: the same frame, no override
        self._last_frame = frame
        overrides.new = False
        ignore_overrides = bool(self._options & IGNORE_OVERRIDES)
        timeout_s = self.params["RC_OVERRIDE_TIME"]
        radio_in, changed = self.radio_in, False
        for i in range(CHANNELS):
            override = 0 if ignore_overrides else overrides.value(i, now_s, timeout_s)
            value = override or (frame[i] if frame is not None and i < len(frame) else radio_in[i] if frame is None else 0)
            if value != radio_in[i]:
                radio_in[i], changed = value, True
        if timeout_s > 0:
            overrides.forget_lapsed(now_s, timeout_s)
        if changed:
            self.version += 1
            self.switches_dirty = True
            self._work_out_sticks()
        return changed

    def channel_us(self, channel: int) -> int:
        """Channel `channel` (1-based) as last read [us]."""
        return self.radio_in[channel - 1] if 1 <= channel <= CHANNELS else 0

    def throttle_us(self) -> int:
        return self.channel_us(self._stick_channels[2])

    def sticks(self) -> PilotInput:
        """Roll, pitch (positive forward: a low PWM), yaw in -1..1 and throttle 0..1 through the
        channels' calibrations; CENTRED_MANUAL itself for centred sticks and a closed throttle.
        Kept in `pilot`, worked out again whenever a channel or a parameter changes."""
        return self.pilot

    def _work_out_sticks(self) -> None:
        p, chans = self.params, self._stick_channels
        pwm = tuple(self.channel_us(c) for c in chans)
        if 0 in pwm:  # never read: at rest
            self.pilot = CENTRED_MANUAL
            return
        throttle_cal = Calibration.of(p, chans[2])
        r, pt, t, y = (stick(pwm[0], Calibration.of(p, chans[0])), -stick(pwm[1], Calibration.of(p, chans[1])),
                       throttle(pwm[2], throttle_cal), stick(pwm[3], Calibration.of(p, chans[3])))
        if r == 0.0 and pt == 0.0 and y == 0.0 and t == 0.0:
            self.pilot = CENTRED_MANUAL
        else:
            self.pilot = PilotInput(r, pt, y, t, last_update_s=float("inf"), throttle_mid=throttle_mid(throttle_cal))

    def hold_sticks(self, roll: float, pitch: float, yaw: float, throttle: float, now_s: float) -> None:
        """Override the four mapped channels with the PWMs a transmitter sends for these sticks
        (pitch positive forward), as a ground station would, from `now_s` (tests, scripts)."""
        p = self.params
        for role, value, to_pwm in (("RCMAP_ROLL", roll, stick_pwm), ("RCMAP_PITCH", -pitch, stick_pwm),
                                    ("RCMAP_THROTTLE", throttle, throttle_pwm), ("RCMAP_YAW", yaw, stick_pwm)):
            channel = int(p[role])
            self.overrides.set(channel - 1, to_pwm(min(max(value, -1.0), 1.0), Calibration.of(p, channel)), now_s)
        self.read(now_s)

    # ----- the switches ------------------------------------------------------------------------
    def settle_switches(self) -> int | None:
        """At power-on: every switch taken where it is, nothing acted on; the flight-mode
        switch's position (0..5), or None, for the vehicle to enter its mode."""
        for i, _ in self.aux_channels:
            self.aux_switches[i].settle(self._switch_position(i))
            self._aux_seen[i] = True
        position = self._mode_switch_reading()
        self.mode_switch.settle(position)
        return position

    def _mode_switch_reading(self) -> int | None:
        channel = int(self.params["FLTMODE_CH"])
        if not 1 <= channel <= CHANNELS:
            return None
        return mode_switch_position(self.radio_in[channel - 1])

    def mode_switch_moved(self, now_s: float) -> int | None:
        """The flight-mode switch's new position (0..5) once it has held, else None."""
        position = self._mode_switch_reading()
        if position is None or not self.mode_switch.read(position, now_s):
            return None
        return position

    @property
    def switches_settling(self) -> bool:
        """A switch has moved and not yet held long enough to count."""
        return self.mode_switch.settling or any(self.aux_switches[i].settling for i, _ in self.aux_channels)

    def _switch_position(self, index: int) -> int | None:
        allow_reverse = bool(self._options & ALLOW_SWITCH_REVERSE)
        reversed_switch = allow_reverse and bool(self.params[f"RC{index + 1}_REVERSED"])
        return switch_position(self.radio_in[index], reversed_switch)

    def aux_switches_moved(self, now_s: float) -> list[tuple[int, int, int]]:
        """(channel 1-based, RCn_OPTION, position) of each aux switch that has just moved."""
        moved = []
        for i, option in self.aux_channels:
            position = self._switch_position(i)
            if position is None:
                continue
            switch = self.aux_switches[i]
            if not self._aux_seen[i]:
                self._aux_seen[i] = True
                function = AUX_FUNCTIONS.get(option)
                if function is not None and function.settle_on_first_read:
                    switch.settle(position)
            if switch.read(position, now_s):
                moved.append((i + 1, option, position))
        return moved

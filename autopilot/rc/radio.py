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
        self.mode_switch = Debounced()
        self.aux_switches = [Debounced() for _ in range(CHANNELS)]
        self._aux_seen = [False] * CHANNELS  # the channel's switch has been read with its option
        self._sticks: PilotInput = CENTRED_MANUAL
        self._sticks_pwm: tuple[int, ...] | None = None
        params.on_change(self._param_changed)

    def _param_changed(self, name: str, value: float) -> None:
        if name.startswith("RC") and name.endswith("_OPTION"):
            index = int(name[2:-len("_OPTION")]) - 1
            self._aux_seen[index] = False
            self.aux_switches[index].forget()
        if name.startswith("RC"):  # RCMAP_*, RCn_*: the sticks are worked out again
            self._sticks_pwm = None

    # ----- the channels ------------------------------------------------------------------------
    def read(self, now_s: float) -> bool:
        """Take the receiver's frame and the overrides in force; False if neither came."""
        frame = self.receiver.channels_us()
        options = int(self.params["RC_OPTIONS"])
        if options & IGNORE_RECEIVER:
            frame = None
        if frame is None and not self.overrides.new:
            return False
        self.overrides.new = False
        timeout_s = -1.0 if options & IGNORE_OVERRIDES else self.params["RC_OVERRIDE_TIME"]
        ignore_overrides = bool(options & IGNORE_OVERRIDES)
        radio_in = self.radio_in
        for i in range(CHANNELS):
            override = 0 if ignore_overrides else self.overrides.value(i, now_s, timeout_s)
            if override:
                radio_in[i] = override
            elif frame is not None:
                radio_in[i] = frame[i] if i < len(frame) else 0
        self.updated_at_s = now_s
        return True

    def channel_us(self, channel: int) -> int:
        """Channel `channel` (1-based) as last read [us]."""
        return self.radio_in[channel - 1] if 1 <= channel <= CHANNELS else 0

    def throttle_us(self) -> int:
        return self.channel_us(int(self.params["RCMAP_THROTTLE"]))

    def sticks(self) -> PilotInput:
        """Roll, pitch (positive forward: a low PWM), yaw in -1..1 and throttle 0..1 through the
        channels' calibrations; CENTRED_MANUAL itself for centred sticks and a closed throttle."""
        p = self.params
        chans = (int(p["RCMAP_ROLL"]), int(p["RCMAP_PITCH"]), int(p["RCMAP_THROTTLE"]), int(p["RCMAP_YAW"]))
        pwm = tuple(self.channel_us(c) for c in chans)
        if pwm == self._sticks_pwm:
            return self._sticks
        self._sticks_pwm = pwm
        if 0 in pwm:  # never read: at rest
            self._sticks = CENTRED_MANUAL
            return self._sticks
        throttle_cal = Calibration.of(p, chans[2])
        r, pt, t, y = (stick(pwm[0], Calibration.of(p, chans[0])), -stick(pwm[1], Calibration.of(p, chans[1])),
                       throttle(pwm[2], throttle_cal), stick(pwm[3], Calibration.of(p, chans[3])))
        if r == 0.0 and pt == 0.0 and y == 0.0 and t == 0.0:
            self._sticks = CENTRED_MANUAL
        else:
            self._sticks = PilotInput(r, pt, y, t, last_update_s=float("inf"), throttle_mid=throttle_mid(throttle_cal))
        return self._sticks

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
        for i in range(CHANNELS):
            option = int(self.params.get(f"RC{i + 1}_OPTION", 0))
            if option:
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

    def _switch_position(self, index: int) -> int | None:
        allow_reverse = bool(int(self.params["RC_OPTIONS"]) & ALLOW_SWITCH_REVERSE)
        reversed_switch = allow_reverse and bool(self.params[f"RC{index + 1}_REVERSED"])
        return switch_position(self.radio_in[index], reversed_switch)

    def aux_switches_moved(self, now_s: float) -> list[tuple[int, int, int]]:
        """(channel 1-based, RCn_OPTION, position) of each aux switch that has just moved."""
        moved = []
        for i in range(CHANNELS):
            option = int(self.params[f"RC{i + 1}_OPTION"])
            if not option:
                continue
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

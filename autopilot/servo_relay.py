"""Servo outputs and relays set directly, by DO_SET_SERVO, DO_REPEAT_SERVO, DO_SET_RELAY and
DO_REPEAT_RELAY (commands or mission items), as ArduPilot's ServoRelayEvents sets them.

An output takes a PWM only if nothing else drives it: its SERVOn_FUNCTION is none, manual, an
RC pass-through, the sprayer's or the gripper's; otherwise the vehicle says "ServoRelayEvent:
Channel N is already in use" and the command fails (a quad's motors are outputs 1-4). An output
never set reads 0 in SERVO_OUTPUT_RAW, as ArduCopter SITL's do. A relay (0-5) answers only if it
is one (RELAYn_FUNCTION 1) with a pin (RELAYn_PIN not -1): SITL's relay 0 is. State 1 is on, 0
off, anything else toggles.

One repeat runs at a time, a servo's or a relay's: it toggles the output between the PWM asked
for and SERVOn_TRIM (the relay between its states), a half cycle each, `count` full cycles (a
negative count: for ever), starting with the PWM (with a toggle); setting the same output or
relay again ends it, and a new repeat replaces it.
"""
from __future__ import annotations

from typing import Callable

from .params import ParamStore

CHANNELS = 16
RELAYS = 6
RELAY_FUNCTION = 1  # RELAYn_FUNCTION: a plain relay
RELAY_FUNCTIONS = 26  # AP_Relay_Params::FUNCTION::NUM_FUNCTIONS: 1-25 are functions
# SRV_Channel functions an event may drive: none, manual, sprayer pump and spinner, gripper, RC
# pass-through 1-16 and mapped RC pass-through 1-16. (ArduPilot rescales a PWM sent to a mapped
# pass-through through the output's range; Firefly passes it on as it is.)
FREE_FUNCTIONS = frozenset({0, 1, 22, 23, 28, *range(51, 67), *range(140, 156)})
SERVO, RELAY = "servo", "relay"


class ServoRelayEvents:
    def __init__(self, params: ParamStore, notify: Callable[[str], None]):
        self.params = params
        self.notify = notify
        self.pwm = [0] * CHANNELS  # what each output was last set to [us], 0 = never
        self.relays = [False] * RELAYS  # each relay on or off
        self._kind = SERVO  # what the repeat toggles, and which one (1-based output, 0-based relay)
        self._channel = -1
        self._value = 0
        self._left = 0  # half cycles still to come; negative: for ever (its parity says which half)
        self._half_cycle_s = 0.0
        self._next_s = 0.0

    @property
    def repeating(self) -> bool:
        return self._left != 0

    def _free(self, channel: int) -> bool:
        if not 1 <= channel <= CHANNELS:
            return False
        if int(self.params[f"SERVO{channel}_FUNCTION"]) not in FREE_FUNCTIONS:
            self.notify(f"ServoRelayEvent: Channel {channel} is already in use")
            return False
        return True

    def relay_enabled(self, relay: int) -> bool:
        p = self.params
        return (0 <= relay < RELAYS and int(p.get(f"RELAY{relay + 1}_FUNCTION", 0)) == RELAY_FUNCTION
                and int(p.get(f"RELAY{relay + 1}_PIN", -1)) != -1)

    def relay_masks(self) -> tuple[int, int]:
        """RELAY_STATUS's present and on masks: a relay is present with any known RELAYn_FUNCTION
        (1 to 25), pin or not (measured: RELAY2_FUNCTION 1 with no pin is present, 99 is not)."""
        p = self.params
        present = on = 0
        for relay in range(RELAYS):
            if 0 < int(p.get(f"RELAY{relay + 1}_FUNCTION", 0)) < RELAY_FUNCTIONS:
                present |= 1 << relay
                if self.relays[relay]:
                    on |= 1 << relay
        return present, on

    def _cancel(self, kind: str, channel: int) -> None:
        if self._kind == kind and self._channel == channel:
            self._left = 0

    def set_servo(self, channel: int, pwm: int) -> bool:
        """DO_SET_SERVO; False if the output does not exist or is in use."""
        if not self._free(channel):
            return False
        self._cancel(SERVO, channel)
        self.pwm[channel - 1] = pwm
        return True

    def set_relay(self, relay: int, state: int) -> bool:
        """DO_SET_RELAY; False if it is not a relay."""
        if not self.relay_enabled(relay):
            return False
        self._cancel(RELAY, relay)
        self.relays[relay] = (state == 1) if state in (0, 1) else not self.relays[relay]
        return True

    def repeat_servo(self, channel: int, pwm: int, count: int, cycle_s: float, now_s: float) -> bool:
        """DO_REPEAT_SERVO: `count` cycles of `cycle_s` seconds; False as set_servo."""
        if not self._free(channel):
            return False
        self._start(SERVO, channel, pwm, count, cycle_s, now_s)
        return True

    def repeat_relay(self, relay: int, count: int, cycle_s: float, now_s: float) -> bool:
        """DO_REPEAT_RELAY: `count` cycles of toggling; False as set_relay."""
        if not self.relay_enabled(relay):
            return False
        self._start(RELAY, relay, 0, count, cycle_s, now_s)
        return True

    def _start(self, kind: str, channel: int, value: int, count: int, cycle_s: float, now_s: float) -> None:
        self._kind, self._channel, self._value = kind, channel, value
        self._left, self._half_cycle_s = 2 * count, cycle_s / 2.0
        self._next_s = now_s
        self.update(now_s)

    def update(self, now_s: float) -> None:
        """The repeat's next half cycle, when it is due (the vehicle calls it at 10 Hz)."""
        if self._left == 0 or now_s < self._next_s:
            return
        self._next_s = now_s + self._half_cycle_s
        channel = self._channel
        if self._kind == RELAY:
            self.relays[channel] = not self.relays[channel]
        else:
            self.pwm[channel - 1] = int(self.params[f"SERVO{channel}_TRIM"]) if self._left & 1 else self._value
        self._left = self._left - 1 if self._left > 0 else self._left ^ 1

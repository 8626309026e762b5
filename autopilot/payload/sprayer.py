"""A crop sprayer, as ArduCopter runs AC_Sprayer (SPRAY_*), measured on its SITL: a pump on the
outputs with SERVOn_FUNCTION 22 and a spinner on those with 23.

DO_SPRAYER 1 (or a mission's) switches it on, if SPRAY_ENABLE; 0 (a mission's: anything but 1)
switches it off. A change sets both outputs to their minimum (SERVOn_MIN): a sprayer switched on
while disabled too; before any, SERVO_OUTPUT_RAW reads 0 there.

While on it is updated at 3 Hz (AC_Sprayer's rate). It starts spraying once the ground speed has
been at least SPRAY_SPEED_MIN [cm/s] for more than 0.1 s and stops once it has been below for
more than 1 s. Spraying, the pump runs at SPRAY_PUMP_RATE % of its range per m/s of ground speed
(at least SPRAY_PUMP_MIN %, at most all of it) and the spinner at SPRAY_SPINNER [us]; otherwise
both sit at their minimum. Turning SPRAY_ENABLE off switches it off at the next update.
"""
from __future__ import annotations

from ..params import ParamStore
from .outputs import minimum_pwm, outputs_of, range_pwm

PUMP_FUNCTION, SPINNER_FUNCTION = 22, 23  # SERVOn_FUNCTION: sprayer pump, sprayer spinner
UPDATE_S = 1.0 / 3.0
TURN_ON_S = 0.1  # at speed this long before spraying (AC_SPRAYER_DEFAULT_TURN_ON_DELAY)
SHUT_OFF_S = 1.0  # below speed this long before stopping (AC_SPRAYER_DEFAULT_SHUT_OFF_DELAY)


class Sprayer:
    def __init__(self, params: ParamStore, servo_pwm: list[int]):
        self.params = params
        self._servo_pwm = servo_pwm  # the outputs it drives (servo_relay.py's)
        self.running = False  # switched on (and enabled): update() is due every UPDATE_S
        self.spraying = False
        self.next_update_s = 0.0
        self._fast_since_s: float | None = None  # at speed since (not spraying yet)
        self._slow_since_s: float | None = None  # below speed since (spraying still)

    @property
    def enabled(self) -> bool:
        return self.params["SPRAY_ENABLE"] > 0

    def run(self, on: bool, now_s: float) -> None:
        """Switch on or off; a change puts the outputs at their minimum until it sprays."""
        if self.running == on:
            return
        self.running = self.enabled and on
        self.next_update_s = now_s
        if not self.running:
            self._stop()

    def _stop(self) -> None:
        for function in (PUMP_FUNCTION, SPINNER_FUNCTION):
            for output in outputs_of(self.params, function):
                self._servo_pwm[output - 1] = minimum_pwm(self.params, output)
        self.spraying = False

    def update(self, now_s: float, ground_speed_m_s: float) -> None:
        """AC_Sprayer's 3 Hz update (the vehicle calls it while running, when next_update_s is due)."""
        self.next_update_s = now_s + UPDATE_S
        if not self.enabled:
            self.run(False, now_s)
            return
        p = self.params
        pumps = outputs_of(p, PUMP_FUNCTION)
        if not pumps:
            return
        speed_cm_s = ground_speed_m_s * 100.0
        spray = self.spraying
        if speed_cm_s >= p["SPRAY_SPEED_MIN"]:
            self._slow_since_s = None
            if not self.spraying:
                if self._fast_since_s is None:
                    self._fast_since_s = now_s
                elif now_s - self._fast_since_s > TURN_ON_S:
                    spray, self._fast_since_s = True, None
        else:
            self._fast_since_s = None
            if self.spraying:
                if self._slow_since_s is None:
                    self._slow_since_s = now_s
                elif now_s - self._slow_since_s > SHUT_OFF_S:
                    spray, self._slow_since_s = False, None
        if not spray:
            self._stop()
            return
        # the pump's share of its range, in ten-thousandths as ArduPilot counts it (whole ones)
        share = int(min(max(speed_cm_s * p["SPRAY_PUMP_RATE"], 100.0 * p["SPRAY_PUMP_MIN"]), 10000.0)) / 10000.0
        for output in pumps:
            self._servo_pwm[output - 1] = range_pwm(p, output, share)
        for output in outputs_of(p, SPINNER_FUNCTION):
            self._servo_pwm[output - 1] = int(p["SPRAY_SPINNER"])
        self.spraying = True

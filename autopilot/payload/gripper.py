"""The gripper, as ArduCopter runs AP_Gripper with a servo (GRIP_TYPE 1), measured on its SITL.

The gripper is made at boot when GRIP_ENABLE and GRIP_TYPE say so (other types are not modelled:
nothing is made); it then puts the outputs with SERVOn_FUNCTION 28 at GRIP_NEUTRAL. DO_GRIPPER
(and a mission's) grabs or releases while GRIP_ENABLE is 1, whatever was made at boot:

  grab     "Gripper load grabbing", the output to GRIP_GRAB; once it has been there for the
           servo's 0.5 s (seen by the 10 Hz update) "Gripper load grabbed". Asked again while
           grabbing: nothing; once grabbed: "Gripper load grabbed" again.
  release  the same with GRIP_RELEASE, "Gripper load releasing" / "Gripper load released".

Without an output for it the servo never gets there: no "grabbed" or "released". With
GRIP_AUTOCLOSE above 0 a released gripper grabs again that many seconds after its release began.
"""
from __future__ import annotations

from collections.abc import Callable

from ..params import ParamStore
from ..results import Severity
from .outputs import outputs_of

SERVO_TYPE = 1  # GRIP_TYPE
GRIPPER_FUNCTION = 28  # SERVOn_FUNCTION: gripper
ACTUATION_S = 0.5  # the servo's travel, after which the gripper counts as there
UPDATE_S = 0.1  # AP_Gripper::update's rate, 10 Hz
NEUTRAL, GRABBING, RELEASING, GRABBED, RELEASED = "neutral", "grabbing", "releasing", "grabbed", "released"
MOVING = {GRABBING: (GRABBED, "GRIP_GRAB", "Gripper load grabbed"),
          RELEASING: (RELEASED, "GRIP_RELEASE", "Gripper load released")}


class Gripper:
    def __init__(self, params: ParamStore, servo_pwm: list[int], notify: Callable[[str, int], None]):
        self.params = params
        self._servo_pwm = servo_pwm  # the outputs it drives (servo_relay.py's)
        self._notify = notify
        self.fitted = params["GRIP_ENABLE"] > 0 and int(params["GRIP_TYPE"]) == SERVO_TYPE  # made at boot
        self.state = NEUTRAL
        self._moved_at_s = 0.0  # when the last grab or release began
        self.next_update_s = 0.0
        if self.fitted:
            self._output(int(params["GRIP_NEUTRAL"]))

    @property
    def enabled(self) -> bool:
        return self.params["GRIP_ENABLE"] > 0

    def valid(self) -> bool:
        """Enabled, made at boot and with an output: what payload placing asks of it."""
        return self.enabled and self.fitted and bool(outputs_of(self.params, GRIPPER_FUNCTION))

    @property
    def released(self) -> bool:
        return self.enabled and self.fitted and self.state == RELEASED

    def grab(self, now_s: float) -> None:
        self._move(now_s, GRABBING)

    def release(self, now_s: float) -> None:
        self._move(now_s, RELEASING)

    def _move(self, now_s: float, moving: str) -> None:
        if not (self.enabled and self.fitted) or self.state == moving:
            return
        done, pwm_param, done_text = MOVING[moving]
        if self.state == done:
            self._notify(done_text, Severity.INFO)
            return
        self.state, self._moved_at_s = moving, now_s
        self._output(int(self.params[pwm_param]))
        self._notify("Gripper load grabbing" if moving == GRABBING else "Gripper load releasing", Severity.INFO)

    def _output(self, pwm: int) -> None:
        for output in outputs_of(self.params, GRIPPER_FUNCTION):
            self._servo_pwm[output - 1] = pwm

    def update(self, now_s: float) -> None:
        """The 10 Hz update: a grab or release that has had its time is done; the autoclose."""
        self.next_update_s = now_s + UPDATE_S
        if not (self.enabled and self.fitted):
            return
        moving = MOVING.get(self.state)
        if moving is not None and self._there(now_s, int(self.params[moving[1]])):
            self.state = moving[0]
            self._notify(moving[2], Severity.INFO)
        autoclose = self.params["GRIP_AUTOCLOSE"]
        if self.state == RELEASED and autoclose > 0 and now_s - self._moved_at_s > autoclose:
            self.grab(now_s)

    def _there(self, now_s: float, pwm: int) -> bool:
        outputs = outputs_of(self.params, GRIPPER_FUNCTION)
        return bool(outputs) and self._servo_pwm[outputs[0] - 1] == pwm and now_s - self._moved_at_s >= ACTUATION_S

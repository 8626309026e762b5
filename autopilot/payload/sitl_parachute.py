"""ArduPilot SITL's simulated parachute (SIM_PARA_ENABLE, SIM_PARA_PIN): a pyrotechnic on an output
(SIM_PARA_PIN, 1-based) that fires the first time the output reaches 1250 us, saying "BANG!
Parachute deployed" as SITL does (measured). Here it also opens the sim's canopy, which slows the
fall (sim/parachute.py); ArduPilot SITL's says so and nothing else, its vehicle falls as before.
Once fired it stays fired until the simulation restarts.
"""
from __future__ import annotations

from collections.abc import Callable

from ..params import ParamStore
from ..results import Severity

FIRES_AT_PWM = 1250
CHANNELS = 16


class SitlParachute:
    def __init__(self, params: ParamStore, servo_pwm: list[int], notify: Callable[[str, int], None],
                 deploy: Callable[[], None]):
        self.params = params
        self._servo_pwm = servo_pwm
        self._notify, self._deploy = notify, deploy
        self._fired = False
        self.ready = params["SIM_PARA_ENABLE"] > 0  # fitted and not fired: its output is worth watching
        params.on_change(self._param_changed)

    def _param_changed(self, name: str, value: float) -> None:
        if name == "SIM_PARA_ENABLE":
            self.ready = value > 0 and not self.fired

    @property
    def fired(self) -> bool:
        return self._fired

    def update(self) -> None:
        pin = int(self.params["SIM_PARA_PIN"])
        if 1 <= pin <= CHANNELS and self._servo_pwm[pin - 1] >= FIRES_AT_PWM:
            self._fired, self.ready = True, False
            self._notify("BANG!  Parachute deployed", Severity.WARNING)
            self._deploy()

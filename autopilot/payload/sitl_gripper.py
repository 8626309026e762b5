"""ArduPilot SITL's simulated servo gripper (SIM_GRPS_*): jaws on an output (SIM_GRPS_PIN, 1-based)
that close on a 1 kg load when they shut on the ground, and let it go when they open.

As SITL's: the output's PWM places the jaws between SIM_GRPS_RELEASE (open, 30 mm apart) and
SIM_GRPS_GRAB (shut), SIM_GRPS_REVERSE swapping the ends; they move 35 % of that travel a
second; a PWM outside the two (0: never set) leaves them where they are. Under 5 mm apart on the
ground they hold the load; over 10 mm apart it is gone. The load hangs on a 2 m string
(sim/slung_load.py): the vehicle carries it only that high.
"""
from __future__ import annotations

from collections.abc import Callable

from ..params import ParamStore

GAP_MM = 30.0
SLEW_PER_S = 0.35  # of the travel
HOLDS_UNDER_MM, LETS_GO_OVER_MM = 5.0, 10.0
LOAD_KG = 1.0
CHANNELS = 16


class SitlGripper:
    def __init__(self, params: ParamStore, servo_pwm: list[int], hang_load: Callable[[float], None],
                 drop_load: Callable[[], None]):
        self.params = params
        self._servo_pwm = servo_pwm
        self._hang, self._drop = hang_load, drop_load
        self.position = 0.0  # 0 .. 1 of the way from SIM_GRPS_RELEASE's end to SIM_GRPS_GRAB's
        self.holding = False
        self._last_s: float | None = None
        self.ready = params["SIM_GRPS_ENABLE"] > 0  # fitted: its output is worth watching
        params.on_change(self._param_changed)

    def _param_changed(self, name: str, value: float) -> None:
        if name == "SIM_GRPS_ENABLE":
            self.ready = value > 0

    def update(self, now_s: float, height_above_ground_m: float) -> None:
        dt = 0.0 if self._last_s is None else now_s - self._last_s
        self._last_s = now_s
        p = self.params
        pin = int(p["SIM_GRPS_PIN"])
        if not 1 <= pin <= CHANNELS:
            return
        pwm = self._servo_pwm[pin - 1]
        grab, release = int(p["SIM_GRPS_GRAB"]), int(p["SIM_GRPS_RELEASE"])
        demand = (pwm - abs(grab - release)) * 0.001
        if pwm < min(grab, release) or demand > 1.0:
            demand = self.position
        step = SLEW_PER_S * dt
        self.position = min(max(demand, self.position - step), self.position + step)
        reverse = bool(p["SIM_GRPS_REVERSE"])
        if (release < grab and reverse) or (release > grab and not reverse):
            gap = GAP_MM * self.position
        else:
            gap = GAP_MM * (1.0 - self.position)
        if gap < HOLDS_UNDER_MM and height_above_ground_m <= 0.0 and not self.holding:
            self.holding = True
            self._hang(LOAD_KG)
        elif gap > LETS_GO_OVER_MM and self.holding:
            self.holding = False
            self._drop()

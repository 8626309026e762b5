"""The pre-arm reports ArduCopter sends on its own while disarmed (AP_Arming::update, once a
second): the failing pre-arm checks, each as "PreArm: <reason>", every DISPLAY_PERIOD_S, and
sooner when checks that passed start to fail (a mode that needs home chosen before there is
one, a GPS fix lost): at the next update, unless a report went out less than IMMEDIATE_GAP_S
before. The clock starts at power-on, so a vehicle that fails its checks from boot first
reports 30 s in. ARMING_OPTIONS bit 0 turns the reports off; an armed vehicle runs no pre-arm
checks and reports nothing. An ARM refused says its own "Arm: " texts (arming.py) whatever this
does.

Sans-IO: the vehicle calls update() once a second with the failing checks and says what it
returns."""
from __future__ import annotations

from collections.abc import Callable

DISPLAY_PERIOD_S = 30.0  # PREARM_DISPLAY_PERIOD
IMMEDIATE_GAP_S = 4.0  # a failure that just began waits for this since the last report
DISABLE_PREARM_DISPLAY = 1 << 0  # ARMING_OPTIONS
NO_ARMING_CHANGE_TEXT = 1 << 1  # ARMING_OPTIONS: no "Arming motors" / "Disarming motors" (vehicle.py)


class PrearmDisplay:
    __slots__ = ("last_display_s", "last_passed", "report_immediately")

    def __init__(self) -> None:
        self.last_display_s = 0.0
        self.last_passed = False  # as at boot: failing from the start is no change
        self.report_immediately = False

    def update(self, now_s: float, armed: bool, failures: Callable[[], list[str]], options: int) -> list[str]:
        """The texts to say now (the reasons, without their "PreArm: ")."""
        display = now_s - self.last_display_s > DISPLAY_PERIOD_S or \
            (self.report_immediately and now_s - self.last_display_s > IMMEDIATE_GAP_S)
        if display:
            self.report_immediately = False
            self.last_display_s = now_s
        reasons = [] if armed else failures()
        passed = not reasons
        if not passed and self.last_passed:  # decided after this update's display, as ArduCopter does
            self.report_immediately = True
        self.last_passed = passed
        if not display or options & DISABLE_PREARM_DISPLAY:
            return []
        return reasons

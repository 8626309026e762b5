"""Failsafes and the geofence's breaches (fence_breach.py), configured by ArduCopter's parameters.

Each check looks at the vehicle (sim time only) and, on a new breach, announces it and switches
to the configured action. Ground-station link loss is detected by the MAVLink session on the
link clock and reported here through `gcs_lost()`, so wall time never reaches the vehicle.
"""
from __future__ import annotations

import math

from ..modes.numbers import ModeNumber
from ..results import Result, Severity
from ..views import FailsafeView
from .ekf_check import EkfCheck
from .fence_breach import FenceBreach

RTL, LAND, AUTO = ModeNumber.RTL, ModeNumber.LAND, ModeNumber.AUTO
# A mode tried first, what ArduCopter says when it is refused, and the mode then tried
# (events.cpp's set_mode_SmartRTL_or_RTL, ..._or_land_with_pause, set_mode_auto_do_land_start_or_RTL).
Fallback = tuple[ModeNumber, str, ModeNumber]
SMART_RTL_OR_RTL: Fallback = (ModeNumber.SMART_RTL, "SmartRTL Unavailable, Trying RTL Mode", RTL)
SMART_RTL_OR_LAND: Fallback = (ModeNumber.SMART_RTL, "SmartRTL Unavailable, Using Land Mode", LAND)
AUTO_RTL_OR_RTL: Fallback = (ModeNumber.AUTO_RTL, "Trying RTL Mode", RTL)
# BATT_FS_LOW_ACT and BATT_FS_CRT_ACT / FS_GCS_ENABLE values -> mode to
# switch to (Brake-then-Land is flown as LAND here).
Action = ModeNumber | Fallback
BATT_ACTIONS: dict[int, Action] = {1: LAND, 2: RTL, 3: SMART_RTL_OR_RTL, 4: SMART_RTL_OR_LAND, 6: AUTO_RTL_OR_RTL, 7: LAND}
GCS_ACTIONS: dict[int, Action] = {1: RTL, 2: RTL, 3: SMART_RTL_OR_RTL, 4: SMART_RTL_OR_LAND, 5: LAND, 6: AUTO_RTL_OR_RTL}
# FS_THR_ENABLE -> mode (2, "continue the mission", is RTL in ArduCopter 4.7 too)
RADIO_ACTIONS: dict[int, Action] = {1: RTL, 2: RTL, 3: LAND, 4: SMART_RTL_OR_RTL, 5: SMART_RTL_OR_LAND, 6: AUTO_RTL_OR_RTL, 7: LAND}
# FS_OPTIONS bits the radio failsafe reads
RC_CONTINUE_IF_AUTO, RC_CONTINUE_IF_GUIDED, CONTINUE_IF_LANDING = 1, 4, 8
RADIO_LOW_THROTTLE_CHECKS = 3  # ArduCopter's FS_COUNTER: low throttle readings in a row
GCS_CONTINUE_IN_AUTO = 2  # FS_GCS_ENABLE: a mission in AUTO flies on
CHECK_S = 0.1  # check() runs at 10 Hz of sim time
TERRAIN_TIMEOUT_S = 5.0  # FS_TERRAIN_TIMEOUT_MS: terrain data missing this long is a failsafe
TERRAIN_CLEAR_S = 0.1  # failures forgotten after this long of the data found again


class Failsafes:
    def __init__(self) -> None:
        self.battery_level = 0  # 0 ok, 1 low, 2 critical
        # Checks since the pack first read below BATT_LOW_VOLT / BATT_CRT_VOLT, without a break
        # (None: not below); counted, not summed, so 10 s is 100 checks exactly.
        self._low_volts_checks: int | None = None
        self._critical_volts_checks: int | None = None
        self.radio = False  # ArduCopter's failsafe.radio
        self._rc_silent_checks = 0  # checks since the last RC frame
        self._rc_low_throttle = 0  # ArduCopter's failsafe.radio_counter
        self.gcs = False
        self.fence = FenceBreach()
        self.adsb = False  # ArduCopter's failsafe.adsb: avoidance is acting on a threat (adsb/escape.py)
        self.ekf = EkfCheck()
        self.terrain = False  # ArduCopter's failsafe.terrain
        self._terrain_failures: tuple[float, float] | None = None  # first and last time terrain was missing

    @property
    def radio_input_valid(self) -> bool:
        """ArduCopter's has_valid_input: no radio failsafe, and no low-throttle reading being
        counted towards one; the flight-mode and aux switches are read only then."""
        return not self.radio and self._rc_low_throttle == 0

    @property
    def active(self) -> bool:
        return bool(self.battery_level or self.gcs or self.radio or self.adsb or self.ekf.failsafe)

    def _act(self, v: FailsafeView, mode: Action | None, reason: str) -> None:
        if mode is None or not v.armed or v.landed or v.mode_number == LAND:
            return
        if isinstance(mode, tuple):
            first, refused, mode = mode
            if v.mode_number == first or v.set_mode(first) == Result.ACCEPTED:
                return
            v.notify(refused, Severity.WARNING)
        if mode == RTL and v.mode_number == RTL:
            return
        if v.set_mode(mode) != Result.ACCEPTED and mode == RTL:
            v.set_mode(LAND)

    # ----- battery ------------------------------------------------------------------------------
    @staticmethod
    def _for_long(below: bool, checks: int | None) -> int | None:
        """Checks below a voltage threshold after one more: None once it is not below; 0 at the
        first reading below, as AP_BattMonitor starts its timer there."""
        if not below:
            return None
        return 0 if checks is None else checks + 1

    def check_battery(self, v: FailsafeView) -> None:
        """As AP_BattMonitor: a voltage below BATT_LOW_VOLT / BATT_CRT_VOLT counts once it has
        lasted more than BATT_LOW_TIMER seconds (a timer of 0 turns the voltage checks off: a
        momentary sag under a climb's current does not fire); capacity left below BATT_LOW_MAH /
        BATT_CRT_MAH counts at once."""
        p = v.params
        battery = v.battery
        volts, used = battery.voltage_v, battery.consumed_mah
        self._low_volts_checks = self._for_long(p["BATT_LOW_VOLT"] > 0 and volts < p["BATT_LOW_VOLT"],
                                                self._low_volts_checks)
        self._critical_volts_checks = self._for_long(p["BATT_CRT_VOLT"] > 0 and volts < p["BATT_CRT_VOLT"],
                                                     self._critical_volts_checks)
        timer_checks = round(p["BATT_LOW_TIMER"] / CHECK_S)
        critical = (timer_checks > 0 and (self._critical_volts_checks or 0) > timer_checks) or \
                   (p["BATT_CRT_MAH"] > 0 and p["BATT_CAPACITY"] - used < p["BATT_CRT_MAH"])
        low = critical or (timer_checks > 0 and (self._low_volts_checks or 0) > timer_checks) or \
            (p["BATT_LOW_MAH"] > 0 and p["BATT_CAPACITY"] - used < p["BATT_LOW_MAH"])
        level = 2 if critical else 1 if low else 0
        if level <= self.battery_level or not v.armed:
            return
        self.battery_level = level
        word = "critical" if level == 2 else "low"
        v.notify(f"Battery 1 is {word} {volts:.2f}V used {used:.0f} mAh", Severity.CRITICAL)
        # As ArduCopter: each level has its own action (AP_BattMonitor's low and critical), and
        # its handler announces the failsafe whatever the action (handle_battery_failsafe)
        action = int(p["BATT_FS_CRT_ACT"] if level == 2 else p["BATT_FS_LOW_ACT"])
        if v.landed:
            v.notify("Battery Failsafe - Disarming", Severity.WARNING)
            v.disarm("battery failsafe", force=True)
        elif v.mode_number == LAND and int(p["FS_OPTIONS"]) & CONTINUE_IF_LANDING and action:
            v.notify("Battery Failsafe - Continuing Landing", Severity.WARNING)
        else:
            v.notify("Battery Failsafe", Severity.WARNING)
            self._act(v, BATT_ACTIONS.get(action), "battery")

    # ----- radio --------------------------------------------------------------------------------
    def check_radio(self, v: FailsafeView) -> None:
        """As ArduCopter's radio.cpp: no RC frame for RC_FS_TIMEOUT, or RADIO_LOW_THROTTLE_CHECKS
        throttle readings in a row below FS_THR_VALUE, is the radio failsafe (with FS_THR_ENABLE
        set); frames with a good throttle clear it. SITL's receiver has always been seen, so the
        failsafe comes armed or not. Overrides count as frames (RC_Channels::read_input)."""
        p = v.params
        enabled = int(p["FS_THR_ENABLE"])
        throttle = v.rc_throttle_us()
        if throttle is None:
            self._rc_silent_checks += 1
            timeout_checks = math.ceil(p["RC_FS_TIMEOUT"] / CHECK_S - 1e-9)
            if enabled and not self.radio and self._rc_silent_checks >= timeout_checks:
                self._radio_lost(v, enabled)
            return
        self._rc_silent_checks = 0
        if not enabled:
            self._rc_low_throttle = 0
            self._radio_back(v)
        elif throttle < p["FS_THR_VALUE"]:
            if not self.radio:
                self._rc_low_throttle = min(self._rc_low_throttle + 1, RADIO_LOW_THROTTLE_CHECKS)
                if self._rc_low_throttle >= RADIO_LOW_THROTTLE_CHECKS:
                    self._radio_lost(v, enabled)
        else:
            self._rc_low_throttle = max(self._rc_low_throttle - 1, 0)
            if self._rc_low_throttle == 0:
                self._radio_back(v)

    def _radio_lost(self, v: FailsafeView, enabled: int) -> None:
        """ArduCopter's failsafe_radio_on_event: the exceptions FS_OPTIONS and the state make, each
        announced as it announces them, else FS_THR_ENABLE's action."""
        self.radio = True
        options, mode = int(v.params["FS_OPTIONS"]), v.mode_number
        if not v.armed or v.landed:
            v.notify("Radio Failsafe - Disarming", Severity.WARNING)
            if v.armed:
                v.disarm("radio failsafe", force=True)
        elif mode == LAND and self.battery_level:
            v.notify("Radio + Battery Failsafe - Continuing Landing", Severity.WARNING)
        elif mode == LAND and options & CONTINUE_IF_LANDING:
            v.notify("Radio Failsafe - Continuing Landing", Severity.WARNING)
        elif mode == AUTO and options & RC_CONTINUE_IF_AUTO:
            v.notify("Radio Failsafe - Continuing Auto", Severity.WARNING)
        elif mode == ModeNumber.GUIDED and options & RC_CONTINUE_IF_GUIDED:
            v.notify("Radio Failsafe - Continuing Guided Mode", Severity.WARNING)
        else:
            v.notify("Radio Failsafe", Severity.WARNING)
            self._act(v, RADIO_ACTIONS.get(enabled, LAND), "radio")

    def _radio_back(self, v: FailsafeView) -> None:
        if self.radio:
            self.radio = False
            v.notify("Radio Failsafe Cleared", Severity.WARNING)

    # ----- ground station -----------------------------------------------------------------------
    def gcs_lost(self, v: FailsafeView) -> None:
        if self.gcs or not v.armed or v.params["FS_GCS_ENABLE"] == 0:
            return
        self.gcs = True
        v.notify("GCS Failsafe", Severity.CRITICAL)
        action = int(v.params["FS_GCS_ENABLE"])
        if action == GCS_CONTINUE_IN_AUTO and v.mode_number == AUTO:
            return
        self._act(v, GCS_ACTIONS.get(action), "gcs")

    def gcs_regained(self, v: FailsafeView) -> None:
        if self.gcs:
            self.gcs = False
            v.notify("GCS Failsafe Cleared", Severity.CRITICAL)

    # ----- terrain ------------------------------------------------------------------------------
    def terrain_status(self, found: bool, now_s: float) -> None:
        """A waypoint leg's terrain offset found or not (failsafe_terrain_set_status, each step)."""
        failures = self._terrain_failures
        if not found:
            self._terrain_failures = (now_s if failures is None else failures[0], now_s)
        elif failures is not None and now_s - failures[1] > TERRAIN_CLEAR_S:
            self._terrain_failures = None

    def check_terrain(self, v: FailsafeView) -> None:
        """failsafe_terrain_check: missing for over 5 s in a mode that needs it starts the
        failsafe (v.terrain_failsafe); it ends when that no longer holds."""
        failures = self._terrain_failures
        trigger = (failures is not None and failures[1] - failures[0] > TERRAIN_TIMEOUT_S
                   and v.mode_requires_terrain_failsafe)
        if trigger != self.terrain:
            if trigger:
                v.terrain_failsafe()
            else:
                self.terrain = False

    def check(self, v: FailsafeView) -> None:
        self.check_terrain(v)
        self.check_radio(v)
        self.check_battery(v)
        self.fence.update(v, v.time_s, self.radio)
        self.ekf.check(v)

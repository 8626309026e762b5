"""The recovery parachute, as ArduCopter runs AP_Parachute (CHUTE_*), measured on its SITL.

Nothing happens while CHUTE_ENABLED is 0: a release is accepted and ignored, the output is never
set (SERVO_OUTPUT_RAW reads 0 until it is enabled). Enabled, the release output sits at its off
position: CHUTE_TYPE 10 drives the outputs with SERVOn_FUNCTION 27 to CHUTE_SERVO_OFF; types 0-3
the relays with RELAYn_FUNCTION 3 (off).

A release says "Parachute: Released", disarms the motors at once (unless CHUTE_OPTIONS bit 1) so
the canopy does not tangle in the propellers, and CHUTE_DELAY_MS later fires the output
(CHUTE_SERVO_ON, or the relay on) for 2 s (for ever with CHUTE_OPTIONS bit 0). It is released:
  - by DO_PARACHUTE 2 (manual_release), unless landed ("Parachute: Landed") or below CHUTE_ALT_MIN
    above home ("Parachute: Too low"; 0: no minimum);
  - by a mission's DO_PARACHUTE 2 (release), with neither check;
  - by itself while flying armed above CHUTE_ALT_MIN (in a mode that checks for crashes, not ACRO
    or FLIP) once sinking faster than CHUTE_CRT_SINK [m/s] for more than a second (0: never).
Once released, arming is refused ("Chute is released") until the next boot, also after disabling
and enabling it again; disabled, nothing is checked.

DO_PARACHUTE 0 and 1 (and the mission's) set CHUTE_ENABLED. Not modelled: ArduCopter's release on
a loss of control (attitude 30 degrees off its target for a second while falling), which needs a
failing airframe to measure on both vehicles.
"""
from __future__ import annotations

from collections.abc import Callable

from ..params import ParamStore
from ..results import Severity
from .outputs import outputs_of, relays_of

SERVO_TYPE = 10  # CHUTE_TYPE: a servo output; 0-3 (older firmware's relay numbers): a relay
LAST_RELAY_TYPE = 3
RELEASE_FUNCTION = 27  # SERVOn_FUNCTION: parachute release
RELAY_FUNCTION = 3  # RELAYn_FUNCTION: parachute
FIRED_S = 2.0  # the output stays fired this long (AP_PARACHUTE_RELEASE_DURATION_MS)
HOLD_OPEN, SKIP_DISARM = 1, 2  # CHUTE_OPTIONS bits
SINKING_S = 1.0  # sinking faster than CHUTE_CRT_SINK for more than this releases it


class Parachute:
    def __init__(self, params: ParamStore, servo_pwm: list[int], relays: list[bool],
                 notify: Callable[[str, int], None], disarm: Callable[[], object]):
        self.params = params
        self._servo_pwm, self._relays = servo_pwm, relays  # the outputs it drives (servo_relay.py's)
        self._notify, self._disarm = notify, disarm
        self.release_initiated = False  # a release was asked for since boot: arming is refused
        self._released_at_s: float | None = None  # when the present release was asked for
        self._firing = False  # the output is at its fired position
        self._sinking_since_s: float | None = None
        self.enabled = params["CHUTE_ENABLED"] > 0  # kept with the parameter: read at every tick
        params.on_change(self._param_changed)

    def _param_changed(self, name: str, value: float) -> None:
        if name == "CHUTE_ENABLED":
            self.enabled = value > 0

    def enable(self, on: bool) -> None:
        """DO_PARACHUTE 0 / 1: switch it off or on (a release under way is forgotten)."""
        self.params.set("CHUTE_ENABLED", 1 if on else 0)
        self._released_at_s = None

    # ----- releases ------------------------------------------------------------------------------
    def release(self, now_s: float) -> None:
        """Release now, unasked questions aside (a mission's item, the sink-rate check)."""
        if not self.enabled:
            return
        self._notify("Parachute: Released", Severity.INFO)
        if not int(self.params["CHUTE_OPTIONS"]) & SKIP_DISARM:
            self._disarm()
        if self._released_at_s is None:
            self._released_at_s = now_s
        self.release_initiated = True

    def manual_release(self, now_s: float, landed: bool, height_above_home_m: float) -> None:
        """DO_PARACHUTE 2: refused on the ground and below CHUTE_ALT_MIN, as the pilot's release is."""
        if not self.enabled:
            return
        if landed:
            self._notify("Parachute: Landed", Severity.INFO)
            return
        alt_min = self.params["CHUTE_ALT_MIN"]
        if alt_min != 0 and height_above_home_m < alt_min:
            self._notify("Parachute: Too low", Severity.ALERT)
            return
        self.release(now_s)

    # ----- every flight-mode tick ----------------------------------------------------------------
    def update(self, now_s: float, armed: bool, landed: bool, crash_checked: bool, sink_m_s: float,
               height_above_home_m: float) -> None:
        """Move the output, and release on a sink rate past CHUTE_CRT_SINK: armed, flying above
        CHUTE_ALT_MIN in a mode that checks for crashes, not released yet. Enabled only."""
        if not self.enabled:
            return
        self._watch_sink(now_s, not landed, sink_m_s)
        self._move_output(now_s)
        if not armed or landed or not crash_checked or self.release_initiated:
            return
        alt_min = self.params["CHUTE_ALT_MIN"]
        if alt_min != 0 and height_above_home_m < alt_min:
            return
        if self._sinking_since_s is not None and now_s - self._sinking_since_s > SINKING_S:
            self.release(now_s)

    def _watch_sink(self, now_s: float, flying: bool, sink_m_s: float) -> None:
        critical = self.params["CHUTE_CRT_SINK"]
        if critical <= 0 or not flying or sink_m_s <= critical:
            self._sinking_since_s = None
        elif self._sinking_since_s is None:
            self._sinking_since_s = now_s

    def _move_output(self, now_s: float) -> None:
        released = self._released_at_s
        delay_s = max(self.params["CHUTE_DELAY_MS"], 0.0) / 1000.0
        since = 0.0 if released is None else now_s - released
        if released is not None and not self._firing:
            if since >= delay_s - 1e-9:
                self._fire(True)
        elif released is None or (not int(self.params["CHUTE_OPTIONS"]) & HOLD_OPEN
                                  and since >= delay_s + FIRED_S - 1e-9):
            self._fire(False)
            self._released_at_s = None

    def _fire(self, on: bool) -> None:
        self._firing = on
        kind = int(self.params["CHUTE_TYPE"])
        if kind == SERVO_TYPE:
            pwm = int(self.params["CHUTE_SERVO_ON" if on else "CHUTE_SERVO_OFF"])
            for output in outputs_of(self.params, RELEASE_FUNCTION):
                self._servo_pwm[output - 1] = pwm
        elif 0 <= kind <= LAST_RELAY_TYPE:
            for relay in relays_of(self.params, RELAY_FUNCTION):
                self._relays[relay] = on

    # ----- arming --------------------------------------------------------------------------------
    def prearm_failure(self) -> str | None:
        """AP_Parachute's arming check: enabled, it needs its output, and must not be released."""
        if not self.enabled:
            return None
        if int(self.params["CHUTE_TYPE"]) == SERVO_TYPE:
            if not outputs_of(self.params, RELEASE_FUNCTION):
                return "Chute has no channel"
        elif not relays_of(self.params, RELAY_FUNCTION):
            return "Chute has no relay"
        return "Chute is released" if self.release_initiated else None

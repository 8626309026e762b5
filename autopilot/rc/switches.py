"""ArduPilot's switch debounce (RC_Channel::debounce_completed): a new position counts once the
switch has read it for SWITCH_DEBOUNCE_S; a flick shorter than that does nothing."""
from __future__ import annotations

SWITCH_DEBOUNCE_S = 0.2


class Debounced:
    def __init__(self) -> None:
        self.current: int | None = None  # the position acted on (None: none yet)
        self._candidate: int | None = None
        self._since_s = 0.0

    def settle(self, position: int | None) -> None:
        """Take `position` as where the switch already is, acting on nothing."""
        self.current = self._candidate = position

    def forget(self) -> None:
        """As reset_mode_switch: the next position read counts as new once it has held."""
        self.current = self._candidate = None

    @property
    def settling(self) -> bool:
        """A new position is being timed."""
        return self._candidate != self.current

    def read(self, position: int, now_s: float) -> bool:
        """True when `position` has just become the current one."""
        if position == self.current:
            self._candidate = position
            return False
        if self._candidate != position:
            self._candidate, self._since_s = position, now_s
            return False
        if now_s - self._since_s >= SWITCH_DEBOUNCE_S - 1e-9:
            self.current = position
            return True
        return False

"""RC overrides: channel values a ground station sends in place of the receiver's, each lasting
RC_OVERRIDE_TIME seconds from when it was sent (0: overrides off; negative: they never lapse).
A value of 0 gives the channel back to the receiver."""
from __future__ import annotations

CHANNELS = 16


class Overrides:
    def __init__(self) -> None:
        self.values = [0] * CHANNELS
        self._at_s = [0.0] * CHANNELS
        self.new = False  # an override arrived since the channels were last read
        self.held = False  # some channel has an override value (in force, or lapsed but kept)

    def set(self, index: int, value: int, now_s: float) -> None:
        """Channel `index` (0-based) overridden with `value` [us], 0 = released."""
        self.values[index] = value
        self._at_s[index] = now_s
        self.new = True
        self.held = any(self.values)

    def value(self, index: int, now_s: float, timeout_s: float) -> int:
        """The override of channel `index` in force now, 0 for none (RC_Channel::has_override)."""
        v = self.values[index]
        if v == 0 or timeout_s == 0:
            return 0
        if timeout_s > 0 and now_s - self._at_s[index] >= timeout_s:
            return 0
        return v

    def forget_lapsed(self, now_s: float, timeout_s: float) -> None:
        """Drop the values that have lapsed (a positive timeout: they cannot come back)."""
        values, at_s = self.values, self._at_s
        for i in range(CHANNELS):
            if values[i] and now_s - at_s[i] >= timeout_s:
                values[i] = 0
        self.held = any(values)

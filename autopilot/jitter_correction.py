"""When a report from another system was made, in this vehicle's time, as ArduPilot's
JitterCorrection estimates it: the sender's own timestamp plus the link's offset, the offset
being the smallest (sender - local) lag seen over the last window of reports, and never older
than max_lag. A burst of late reports is so dated to when they were sent, not to when they
arrived, and a sender's clock need not be this vehicle's.
"""
from __future__ import annotations


class JitterCorrection:
    __slots__ = ("max_lag_s", "window", "offset_s", "_window_min_s", "_count")

    def __init__(self, max_lag_s: float = 0.5, window: int = 100):
        self.max_lag_s = max_lag_s
        self.window = window
        self.offset_s: float | None = None  # local time less sender time, its smallest seen
        self._window_min_s = 0.0
        self._count = 0

    def local_time(self, sender_s: float, local_s: float) -> float:
        """The local time at which a report stamped sender_s (sender's clock), heard at local_s,
        was made."""
        lag = local_s - sender_s
        if self.offset_s is None or lag < self.offset_s:
            self.offset_s = lag
        estimate = sender_s + self.offset_s
        if estimate + self.max_lag_s < local_s:  # older than it can be: the link got slower
            estimate = local_s - self.max_lag_s
            self.offset_s = estimate - sender_s
        if self._count == 0 or lag < self._window_min_s:
            self._window_min_s = lag
        self._count += 1
        if self._count == self.window:  # the offset moves to the least lag of the window
            self.offset_s = self._window_min_s
            self._count = 0
        return estimate

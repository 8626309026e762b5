"""Telemetry stream scheduling in sim time: per-message intervals, set by the stream-group
parameters (SRn_*), REQUEST_DATA_STREAM and SET_MESSAGE_INTERVAL."""
from __future__ import annotations

import math

from ..params import DEFAULTS
from .telemetry import BUILDERS, FIXED_RATES_HZ, MIN_INTERVAL_S, STREAM_GROUPS, UNASKED


def _limited(msg_id: int, interval_s: float) -> float:
    return max(interval_s, MIN_INTERVAL_S.get(msg_id, 0.0))


class StreamScheduler:
    def __init__(self, params):
        self._interval_s: dict[int, float] = {}
        self._next_s: dict[int, float] = {}
        self.next_due_s = -math.inf  # no stream is due before this sim time; -inf: look at every one
        self._default_s: dict[int, float] = {}
        # Heartbeat first: a client that has just started listening sees it before anything else.
        for msg_id, rate in FIXED_RATES_HZ.items():
            self._default_s[msg_id] = 1.0 / rate
        for name, ids in STREAM_GROUPS.values():
            rate = params[name]
            for msg_id in ids:
                self._default_s[msg_id] = _limited(msg_id, 1.0 / rate if rate > 0 else math.inf)
        self._interval_s.update({msg_id: interval for msg_id, interval in self._default_s.items()
                                 if msg_id in UNASKED or msg_id in FIXED_RATES_HZ})
        # A group whose rate was set before boot (a saved value, a scenario's) streams whole, as
        # ArduPilot streams what its MAVn_ parameters say from boot.
        for name, ids in STREAM_GROUPS.values():
            if params[name] > 0 and params[name] != DEFAULTS.get(name):
                self._interval_s.update({msg_id: self._default_s[msg_id] for msg_id in ids})

    def param_changed(self, name: str, value: float) -> None:
        """A MAV1_ stream-rate parameter set over PARAM_SET applies at once, as on ArduPilot."""
        for stream_id, (param, _) in STREAM_GROUPS.items():
            if param == name:
                self.set_group_rate(stream_id, value, value > 0)

    def interval_s(self, msg_id: int) -> float:
        """Current interval; inf = not streamed."""
        return self._interval_s.get(msg_id, math.inf)

    def set_interval_us(self, msg_id: int, interval_us: float) -> bool:
        """SET_MESSAGE_INTERVAL semantics: -1 stops, 0 restores the default, >0 sets it."""
        if msg_id not in BUILDERS:
            return False
        if interval_us < 0:
            self._interval_s[msg_id] = math.inf
        elif interval_us == 0:
            self._interval_s[msg_id] = self._default_s.get(msg_id, math.inf)
        else:
            self._interval_s[msg_id] = _limited(msg_id, max(interval_us * 1e-6, 0.001))
        self._next_s.pop(msg_id, None)
        self.next_due_s = -math.inf
        return True

    def set_group_rate(self, stream_id: int, rate_hz: float, start: bool) -> None:
        """REQUEST_DATA_STREAM: stream_id 0 = all groups."""
        groups = STREAM_GROUPS.values() if stream_id == 0 else \
            ([STREAM_GROUPS[stream_id]] if stream_id in STREAM_GROUPS else [])
        for _, ids in groups:
            for msg_id in ids:
                interval = 1.0 / rate_hz if start and rate_hz > 0 else math.inf
                self._interval_s[msg_id] = _limited(msg_id, interval)
                self._next_s.pop(msg_id, None)
        self.next_due_s = -math.inf

    def due(self, now_s: float) -> list[int]:
        if now_s + 1e-9 < self.next_due_s:  # most ticks: nothing is due (checked once, not per message)
            return []
        out = []
        earliest = math.inf
        for msg_id, interval in self._interval_s.items():
            if interval == math.inf:
                continue
            nxt = self._next_s.get(msg_id)
            if nxt is None or now_s + 1e-9 >= nxt:
                out.append(msg_id)
                # Keep a fixed cadence, but never queue up a backlog after a pause.
                base = now_s if nxt is None or now_s - nxt > interval else nxt
                nxt = self._next_s[msg_id] = base + interval
            earliest = min(earliest, nxt)
        self.next_due_s = earliest
        return out

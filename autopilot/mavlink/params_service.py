"""Parameter microservice: list, read by name or index, set with an echoed PARAM_VALUE.

The list (some 1,400 PARAM_VALUEs) is streamed over link time at LIST_RATE_PER_S, as ArduPilot
streams it bandwidth-limited: sent in one burst it can overflow a client's socket buffer, and the
client then has to ask again for each parameter it lost. There is one stream for the link, as
ArduPilot has one per link: a new PARAM_REQUEST_LIST starts it again from index 0 but at the pace
it already had, so asking again does not buy another burst (a flood of requests gets no more
PARAM_VALUEs than one request does). Reads and sets are answered at once, one PARAM_VALUE each.
"""
from __future__ import annotations

from ..params import ParamError
from ..results import Severity

LIST_RATE_PER_S = 1500.0  # PARAM_VALUEs a second while a list is streamed: the reference SITL's pace (~0.9 s)
LIST_BURST = 40  # at most this many in one poll, however long since the last (about one datagram's worth)


def _name(raw) -> str:
    if isinstance(raw, bytes):
        raw = raw.decode("ascii", "replace")
    return raw.split("\0", 1)[0]


class ParamService:
    def __init__(self, params, codec):
        self.params = params
        self.codec = codec
        self._names = params.names()
        self.refused = 0  # PARAM_SETs refused: unknown name, not finite, out of the table's range
        self._next_index: int | None = None  # the list stream's next index, None when not streaming
        self._allowance = float(LIST_BURST)  # PARAM_VALUEs the stream may send now
        self._last_s = 0.0

    @property
    def streaming(self) -> bool:
        return self._next_index is not None

    def value_message(self, name: str, index: int | None = None):
        index = self.params.index_of(name) if index is None else index
        return self.codec.param_value_encode(name.encode(), float(self.params[name]), self.params.mav_type(name),
                                             len(self._names), index)

    def request_list(self, msg, link_s: float) -> list:
        """Start (or restart) streaming the whole list from index 0, at the stream's pace: what
        is due goes at once (after a quiet spell, a burst of LIST_BURST)."""
        if self._next_index is None:  # not streaming: the allowance has grown since the last poll
            self._allowance = min(float(LIST_BURST),
                                  self._allowance + max(0.0, link_s - self._last_s) * LIST_RATE_PER_S)
            self._last_s = link_s
        self._next_index = 0
        return self.poll(link_s)

    def poll(self, link_s: float) -> list:
        """The PARAM_VALUEs of the list stream due by link time `link_s`."""
        if self._next_index is None:
            return []
        elapsed = max(0.0, link_s - self._last_s)
        self._last_s = link_s
        self._allowance = min(float(LIST_BURST), self._allowance + elapsed * LIST_RATE_PER_S)
        start = self._next_index
        end = min(len(self._names), start + int(self._allowance))
        self._allowance -= end - start
        self._next_index = end if end < len(self._names) else None
        return [self.value_message(self._names[i], i) for i in range(start, end)]

    def request_read(self, msg) -> list:
        if msg.param_index >= 0:
            if msg.param_index >= len(self._names):
                return []
            return [self.value_message(self._names[msg.param_index], msg.param_index)]
        name = _name(msg.param_id)
        return [self.value_message(name)] if name in self.params else []

    def set(self, msg, notify) -> list:
        """Apply PARAM_SET. A refused value is answered with the unchanged value and a reason."""
        name = _name(msg.param_id)
        if name not in self.params:
            self.refused += 1
            notify(f"Param set failed: unknown parameter {name}", Severity.WARNING)
            return []
        try:
            self.params.set(name, msg.param_value)
        except ParamError as exc:
            self.refused += 1
            notify(f"Param set failed: {exc}", Severity.WARNING)
        return [self.value_message(name)]

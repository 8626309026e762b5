"""Parameter microservice: list, read by name or index, set with an echoed PARAM_VALUE."""
from __future__ import annotations

from ..params import SPEC_BY_NAME, ParamError
from ..results import Severity
from .dialect import mavlink as mav


def mav_type(params, name: str) -> int:
    """The MAV_PARAM_TYPE `name` is sent as: the one place the parameter, FTP and any other service
    take a parameter's type from (the table knows integers, sent as INT32, and floats)."""
    return mav.MAV_PARAM_TYPE_INT32 if SPEC_BY_NAME[name].is_int else mav.MAV_PARAM_TYPE_REAL32


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

    def value_message(self, name: str):
        return self.codec.param_value_encode(name.encode(), float(self.params[name]),
                                             mav_type(self.params, name),
                                             len(self._names), self._names.index(name))

    def request_list(self, msg) -> list:
        return [self.value_message(name) for name in self._names]

    def request_read(self, msg) -> list:
        if msg.param_index >= 0:
            if msg.param_index >= len(self._names):
                return []
            return [self.value_message(self._names[msg.param_index])]
        name = _name(msg.param_id)
        return [self.value_message(name)] if name in SPEC_BY_NAME else []

    def set(self, msg, notify) -> list:
        """Apply PARAM_SET. A refused value is answered with the unchanged value and a reason."""
        name = _name(msg.param_id)
        if name not in SPEC_BY_NAME:
            self.refused += 1
            notify(f"Param set failed: unknown parameter {name}", Severity.WARNING)
            return []
        try:
            self.params.set(name, msg.param_value)
        except ParamError as exc:
            self.refused += 1
            notify(f"Param set failed: {exc}", Severity.WARNING)
        return [self.value_message(name)]

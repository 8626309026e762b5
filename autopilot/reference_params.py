"""The reference ArduCopter's parameter table, as recorded from its SITL (autopilot/data/).

tests/parity/record_param_table.py writes the file from a freshly booted reference vehicle:
names in the order it serves them, the MAVLink type and default it reported, and the range its
documentation gives where it gives one. Firefly serves every one of these names.
"""
from __future__ import annotations

import json
from dataclasses import dataclass
from functools import cache
from importlib import resources

DATA_FILE = "arducopter_params.json"


@dataclass(frozen=True)
class ReferenceParam:
    name: str
    mav_type: int  # MAV_PARAM_TYPE as the reference reported it
    default: float
    low: float | None  # the documented @Range, or None where the documentation gives none
    high: float | None


@cache
def recording() -> dict:
    """The whole recorded file: its header (reference commit, how it was recorded) and params."""
    text = resources.files("firefly.autopilot").joinpath("data", DATA_FILE).read_text()
    return json.loads(text)


@cache
def reference_params() -> tuple[ReferenceParam, ...]:
    return tuple(ReferenceParam(p["name"], int(p["type"]), float(p["default"]), p.get("low"), p.get("high"))
                 for p in recording()["params"])

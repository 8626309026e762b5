"""The run() of an area whose probes each take a freshly booted vehicle, with parameters of their own."""
from __future__ import annotations

from ..facts import Trace


def each_on_a_fresh_vehicle(target, probes: dict, params: dict) -> dict[str, Trace]:
    """{probe name: Trace}, each probe flown on a vehicle booted with params[name] (None: defaults)."""
    traces = {}
    try:
        for name, probe in probes.items():
            client = target.boot(params=params[name])
            trace = traces[name] = Trace()
            probe(client, trace)
    finally:
        target.close()
    return traces

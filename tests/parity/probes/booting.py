"""The run() of an area whose probes each take a freshly booted vehicle, with parameters of their own."""
from __future__ import annotations

from ..facts import Trace


def each_on_a_fresh_vehicle(target, probes: dict, params: dict, **boot) -> dict[str, Trace]:
    """{probe name: Trace}, each probe flown on a vehicle booted with params[name] (None: defaults)
    and the target's other boot options (streams_hz=None: no streams asked for, and no wait to
    be armable)."""
    traces = {}
    try:
        for name, probe in probes.items():
            client = target.boot(params=params[name], **boot)
            trace = traces[name] = Trace()
            probe(client, trace)
    finally:
        target.close()
    return traces

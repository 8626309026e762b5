"""Mode entry rules: which modes can be entered disarmed, armed on the ground, flying, and
without a GPS fix; the ACK result and the mode the vehicle is in after."""
from __future__ import annotations

from ..client import Client
from ..facts import Trace
from .states import (MODE_NAMES, STABILIZE, mode_name, on_ground_disarmed, reach_armed_on_ground,
                     reach_flying)
from .texts import said

AREA = "modes"
SAID_WITHIN_S = 0.5  # the replies to a mode change, not what follows it (LAND on the ground disarms ~1 s later)
MODES = [m for m in MODE_NAMES if m != 1]  # ACRO needs a pilot's sticks: neither offers it by MAVLink alone


def try_mode(client: Client, trace: Trace, name: str, mode: int) -> None:
    t0 = client.now_ms
    result = client.set_mode(mode)
    client.idle(SAID_WITHIN_S)
    texts = said(client.texts_since(t0, SAID_WITHIN_S))  # what it said within SAID_WITHIN_S of the command
    client.fresh_heartbeat()
    trace.fact(f"{name}.result", result)
    trace.fact(f"{name}.mode_after", mode_name(client.mode))
    trace.fact(f"{name}.said", texts)


def run(target) -> dict[str, Trace]:
    traces = {s: Trace() for s in ("disarmed", "armed_ground", "flying", "disarmed_no_gps")}
    client = target.boot()
    try:
        for mode in MODES:
            on_ground_disarmed(client)
            client.set_mode(STABILIZE)
            try_mode(client, traces["disarmed"], mode_name(mode), mode)
        for mode in MODES:
            reach_armed_on_ground(client, STABILIZE)
            try_mode(client, traces["armed_ground"], mode_name(mode), mode)
        for mode in MODES:
            reach_flying(client)
            try_mode(client, traces["flying"], mode_name(mode), mode)
        on_ground_disarmed(client)
        client.set_mode(STABILIZE)
        client.set_param("SIM_GPS1_ENABLE", 0)
        client.wait(lambda: client.last["GPS_RAW_INT"].fix_type < 3, 20, what="GPS fix lost")
        client.idle(5.0)  # let the estimate notice too
        for mode in MODES:
            client.set_mode(STABILIZE)
            try_mode(client, traces["disarmed_no_gps"], mode_name(mode), mode)
    finally:
        target.close()
    return traces

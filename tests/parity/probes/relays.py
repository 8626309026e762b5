"""RELAY_STATUS (issue 32): the relays ArduCopter reports as present and on, asked for by
MAV_CMD_REQUEST_MESSAGE and streamed by SET_MESSAGE_INTERVAL (no stream carries it).

relay_status   defaults (SITL's relay 1), then DO_SET_RELAY 0 on and off, RELAY2_FUNCTION 1 with no
               pin, RELAY3_FUNCTION 4 (a camera's relay), RELAY4_FUNCTION 99 (no such function), a
               DO_REPEAT_RELAY's toggling, and the message at 2 Hz: each time the answer to the
               request, whether the message came, its masks.
"""
from __future__ import annotations

from pymavlink.dialects.v20 import ardupilotmega as v20

from ..client import Client, mav
from ..facts import Tol, Trace
from .booting import each_on_a_fresh_vehicle

AREA = "relays"
RELAY_STATUS = v20.MAVLINK_MSG_ID_RELAY_STATUS  # (a MAVLink 2 message: not in the probes' constants)


def _status(c: Client, trace: Trace, name: str) -> None:
    """REQUEST_MESSAGE RELAY_STATUS: the answer, and the message's masks if one came."""
    seen = c.received.get("RELAY_STATUS", 0)
    trace.fact(f"{name}.result", c.command(mav.MAV_CMD_REQUEST_MESSAGE, RELAY_STATUS))
    came = c.try_wait(lambda: c.received.get("RELAY_STATUS", 0) > seen, 2.0)
    m = c.last.get("RELAY_STATUS") if came else None
    trace.fact(f"{name}.masks", None if m is None else [m.present, m.on])


def relay_status(c: Client, trace: Trace) -> None:
    _status(c, trace, "boot")
    for name, relay, state in (("relay0_on", 0, 1), ("relay0_off", 0, 0), ("relay0_toggle", 0, 2)):
        trace.fact(f"{name}.set", c.command(mav.MAV_CMD_DO_SET_RELAY, relay, state))
        c.idle(0.2)
        _status(c, trace, name)
    for name, param, value in (("relay2_no_pin", "RELAY2_FUNCTION", 1), ("relay3_camera", "RELAY3_FUNCTION", 4),
                               ("relay4_unknown", "RELAY4_FUNCTION", 99)):
        trace.fact(f"{name}.param_set", c.set_param(param, value))
        c.idle(0.5)
        _status(c, trace, name)
    trace.fact("relay1_on.set", c.command(mav.MAV_CMD_DO_SET_RELAY, 1, 1))
    c.idle(0.2)
    _status(c, trace, "relay1_on")
    trace.fact("interval.result", c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, RELAY_STATUS, 500_000))
    seen = c.received.get("RELAY_STATUS", 0)
    c.idle(4.0)
    trace.fact("interval.per_s", (c.received.get("RELAY_STATUS", 0) - seen) / 4.0,
               Tol(abs=0.5, why="messages counted over 4 s of vehicle time, a tick either side"))


PROBES = {"relay_status": relay_status}


def run(target) -> dict[str, Trace]:
    return each_on_a_fresh_vehicle(target, PROBES, {name: None for name in PROBES})

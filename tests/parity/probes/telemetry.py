"""Telemetry: what streams without asking, what REQUEST_DATA_STREAM(ALL) brings and at what rates
(in vehicle time), HEARTBEAT and EXTENDED_SYS_STATE through arming, takeoff, flight and landing,
and the SYS_STATUS sensor bits."""
from __future__ import annotations

import time
from collections import Counter

from ..client import Client, mav
from ..facts import Tol, Trace
from ..targets import wait_armable
from .states import (ALT_HOLD, AUTO, BRAKE, GUIDED, LAND, LOITER, RTL, STABILIZE, mode_name, on_ground_disarmed,
                     reach_armed_on_ground, reach_battery_failsafe, reach_flying)

AREA = "telemetry"
WINDOW_S = 10.0
# Rates are counts over a 10 s window of vehicle time: one message more or less is timing, not
# behaviour, and ArduPilot's scheduler slips a little under load; so 15 % and 0.2 Hz.
RATE_TOL = Tol(abs=0.2, rel=0.15, why="scheduler jitter over a 10 s window")
# Messages a vehicle sends that carry nothing a client acts on and are not what this checks.
MODES_BY_MAVLINK = (STABILIZE, ALT_HOLD, LOITER, GUIDED, AUTO, LAND, RTL, BRAKE, 16)  # 16: POSHOLD
IGNORED = {"TIMESYNC", "BAD_DATA", "PARAM_VALUE", "STATUSTEXT", "COMMAND_ACK"}


def rates(client: Client, window_s: float) -> dict[str, float]:
    client.log.clear()
    client.logging = True
    client.idle(window_s)
    client.logging = False
    counts = Counter(msg.get_type() for _, msg in client.log)
    return {kind: n / window_s for kind, n in sorted(counts.items()) if kind not in IGNORED}


def status(client: Client, trace: Trace, name: str) -> None:
    client.idle(1.0)
    client.fresh_heartbeat()
    hb = client.last["HEARTBEAT"]
    trace.fact(f"{name}.base_mode", hb.base_mode)
    trace.fact(f"{name}.system_status", hb.system_status)
    ext = client.last.get("EXTENDED_SYS_STATE")
    trace.fact(f"{name}.landed_state", ext.landed_state if ext else None)


def run(target) -> dict[str, Trace]:
    traces = {}
    client = target.boot(streams_hz=None)
    try:
        t = traces["unrequested"] = Trace()
        client.wait(lambda: len(client.last) > 3, 30, what="a few messages")
        client.log.clear()
        client.logging = True
        start = time.monotonic()
        while time.monotonic() - start < 3.0:  # no vehicle time without requested streams: wall
            client.pump()
        client.logging = False
        t.fact("messages", sorted({m.get_type() for _, m in client.log} - IGNORED))
        client.request_streams(4)
        wait_armable(client)
        client.request_streams(4)
        client.idle(2.0)
        t = traces["requested_all_4hz"] = Trace()
        for kind, hz in rates(client, WINDOW_S).items():
            t.fact(kind, hz, RATE_TOL)
        client.request_streams(10)
        client.conn.mav.command_long_send(1, 1, mav.MAV_CMD_SET_MESSAGE_INTERVAL, 0,
                                          mav.MAVLINK_MSG_ID_EXTENDED_SYS_STATE, 200000, 0, 0, 0, 0, 0)
        client.idle(1.0)
        t = traces["sys_status"] = Trace()
        s = client.last["SYS_STATUS"]
        for field in ("onboard_control_sensors_present", "onboard_control_sensors_enabled",
                      "onboard_control_sensors_health"):
            value = getattr(s, field)
            t.fact(field, [BIT_NAMES.get(1 << bit, str(bit)) for bit in range(32) if (value >> bit) & 1])
        t = traces["states"] = Trace()
        on_ground_disarmed(client)
        client.set_mode(GUIDED)
        status(client, t, "disarmed")
        reach_armed_on_ground(client)
        status(client, t, "armed_ground")
        client.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 10)
        client.wait(lambda: client.rel_alt_m() > 3, 30, what="climbing")
        status(client, t, "taking_off")
        # Up there before "flying" is read: how far the climb got in the wall time a busy client
        # takes to react is timing, not behaviour.
        client.wait(lambda: client.rel_alt_m() > 9.5, 60, what="takeoff altitude")
        reach_flying(client)
        status(client, t, "flying")
        client.set_mode(LAND)
        client.idle(1.0)
        status(client, t, "landing")
        client.wait(lambda: not client.armed, 60, what="landed")
        status(client, t, "landed")
        for mode in MODES_BY_MAVLINK:  # the GUIDED_ENABLED flag and system_status in each mode, disarmed
            client.set_mode(mode)
            client.wait(lambda: client.mode == mode, 5, what=mode_name(mode))
            status(client, t, f"disarmed_{mode_name(mode).lower()}")
        reach_battery_failsafe(client)
        status(client, t, "battery_failsafe")
    finally:
        target.close()
    return traces


BIT_NAMES = {value: entry.name.removeprefix("MAV_SYS_STATUS_").lower()
             for value, entry in mav.enums["MAV_SYS_STATUS_SENSOR"].items() if value & (value - 1) == 0 and value}

"""Session.idle is what lets the loop skip a vehicle's exchange on a quiet tick. Two identical
vehicles get the same ground-station traffic, tick by tick: one is polled on every tick, the other
only when it is not idle. They must send the very same messages at the same ticks, through
streams, a parameter list, a mission upload, arming and takeoff (status texts) and a GCS that
falls silent (the failsafe's timing)."""
from __future__ import annotations

from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.mavlink.session import Session

from ._util import client_codec, command_long, ready_vehicle, wire

TICK_S = 0.01


def test_skipping_the_idle_ticks_changes_nothing_that_is_sent():
    gcs = client_codec()
    heartbeat = wire(gcs.heartbeat_encode(6, 8, 0, 0, 0))
    inputs = {tick: heartbeat for tick in range(53, 1500, 100)}  # a GCS, until it falls silent
    inputs |= {  # tick -> what else the ground station sends, between the streams' 10 Hz ticks
        103: wire(gcs.param_request_list_encode(1, 1)),
        403: wire(gcs.mission_count_encode(1, 1, 2, 0)),
        703: command_long(176, 1, 4),  # GUIDED
        715: command_long(400, 1),  # arm: a status text follows
        727: command_long(22, 0, 0, 0, 0, 0, 0, 10.0),  # take off
    }
    vehicles = [ready_vehicle(), ready_vehicle()]
    for vehicle in vehicles:
        vehicle.params.set("FS_GCS_ENABLE", 1)  # its silence then triggers the failsafe
    sessions = [Session(v, new_codec(1)) for v in vehicles]
    sent = [[], []]
    skipped = 0
    link_s = 0.0
    for tick in range(1, 3000):
        link_s += TICK_S
        for k, (vehicle, session) in enumerate(zip(vehicles, sessions)):
            vehicle.run_until(tick * TICK_S)
            if tick == 1237:  # something the vehicle says between the streams' ticks
                vehicle.notify("between ticks")
            now = vehicle.time_s
            out = session.receive(inputs[tick], now, link_s) if tick in inputs else []
            if k == 1 and not out and session.idle(now, link_s):
                skipped += 1
                continue
            out += session.poll(now, link_s)
            sent[k] += [(tick, m.get_type(), m.pack(new_codec(1))) for m in out]
    assert skipped > 250, skipped  # streams, transfers and texts leave fewer quiet ticks than a real flight
    assert [s[:2] for s in sent[1]] == [s[:2] for s in sent[0]]
    assert sent[1] == sent[0]
    kinds = {kind for _, kind, _ in sent[0]}
    assert {"STATUSTEXT", "PARAM_VALUE", "MISSION_REQUEST"} <= kinds or {"STATUSTEXT", "PARAM_VALUE", "MISSION_REQUEST_INT"} <= kinds
    assert vehicles[0].mode.number == vehicles[1].mode.number != 4, "the GCS failsafe took both out of GUIDED"

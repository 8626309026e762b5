"""Persistence without loss: kill -9 the autopilot while it is writing parameters and missions, at
seeded moments, again and again; every restart finds well-formed files holding either the previous
or the new version of each value and list, never something torn or half-uploaded."""
from __future__ import annotations

import json
import random

import pytest

from .pymav import Gcs

pytestmark = pytest.mark.sitl
NAME = b"WPNAV_SPEED"
VALUES = [500.0 + 10.0 * k for k in range(60)]  # every value sent is distinct, so each is traceable
MISSION_LEN = 6


def _read_param(gcs: Gcs) -> float:
    gcs.mav.param_request_read_send(1, 1, NAME, -1)
    msg = gcs.recv("PARAM_VALUE", 5, lambda m: m.param_id == NAME.decode())
    assert msg is not None, "no PARAM_VALUE after restart"
    return msg.param_value


def _mission_items(gcs: Gcs) -> list:
    gcs.mav.mission_request_list_send(1, 1, 0)
    count = gcs.recv("MISSION_COUNT", 5)
    assert count is not None
    items = []
    for seq in range(1, count.count):  # seq 0 is home
        gcs.mav.mission_request_int_send(1, 1, seq, 0)
        item = gcs.recv("MISSION_ITEM_INT", 5, lambda m, s=seq: m.seq == s)
        assert item is not None
        items.append((item.x, item.y, item.z))
    return items


def _send_mission(gcs: Gcs, tag: int, stop_after: int | None = None) -> list:
    """Upload MISSION_LEN waypoints whose altitude carries `tag`; stop answering after
    `stop_after` items (an interrupted upload). Returns the items as (x, y, z)."""
    items = [(-353632610 + 1000 * k, 1491652300 + 1000 * k, float(tag)) for k in range(MISSION_LEN)]
    gcs.mav.mission_count_send(1, 1, MISSION_LEN + 1, 0)
    sent = 0
    while True:
        msg = gcs.recv(["MISSION_REQUEST_INT", "MISSION_REQUEST", "MISSION_ACK"], 5)
        assert msg is not None, "upload stalled"
        if msg.get_type() == "MISSION_ACK":
            assert msg.type == 0, msg
            return items
        if stop_after is not None and sent >= stop_after:
            return items
        x, y, z = (0, 0, 0.0) if msg.seq == 0 else items[msg.seq - 1]
        gcs.mav.mission_item_int_send(1, 1, msg.seq, 6, 16, 0, 1, 0, 0, 0, 0, x, y, z, 0)
        sent += 1


def test_kill_minus_nine_mid_write_leaves_old_or_new_never_torn(autopilot_factory):
    rng = random.Random(7)
    acked_param, in_flight = 1000.0, set()  # the default, then whatever was echoed / still unanswered
    acked_mission, maybe_mission = [], None
    for round_no in range(5):
        ap = autopilot_factory(speedup="10", wipe=round_no == 0)
        gcs = Gcs(ap.pymavlink_url)
        # What survived the last kill: well-formed files, and values that were sent at some point.
        value = _read_param(gcs)
        assert value == acked_param or value in in_flight, (value, acked_param, sorted(in_flight))
        mission = _mission_items(gcs)
        assert mission == acked_mission or mission == maybe_mission, "a torn or partial mission survived"
        state = ap.state_dir / "instance-0"
        for name in ("params.json", "missions.json"):
            if (state / name).exists():
                json.loads((state / name).read_text())
        assert not list(state.glob(".*.json-*")), "temporaries of a killed write were left behind"
        acked_param, in_flight = value, set()
        acked_mission, maybe_mission = mission, None
        # A complete upload, then an interrupted one: only the complete one may ever be stored.
        acked_mission = _send_mission(gcs, tag=10 + round_no)
        _send_mission(gcs, tag=50 + round_no, stop_after=rng.randint(1, MISSION_LEN - 1))
        # A burst of parameter writes, killed after a seeded number of echoes while more are in flight.
        burst = rng.sample(VALUES, 40)
        kill_after = rng.randint(3, 30)
        echoed = 0
        for v in burst:
            gcs.mav.param_set_send(1, 1, NAME, v, 9)
            in_flight.add(v)
        while echoed < kill_after:
            msg = gcs.recv("PARAM_VALUE", 5, lambda m: m.param_id == NAME.decode())
            assert msg is not None, "PARAM_SET burst not echoed"
            echoed += 1
        # A store writes at most twice a second (persist.JsonFile), so of a burst the last echoed
        # values may not be on disk yet, as ArduPilot's storage writes behind its echoes: what
        # survives is the value before the burst or one of the burst, never anything else.
        in_flight |= set(burst)
        ap.process.kill()
        ap.process.wait()
        gcs.close()

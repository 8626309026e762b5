"""Link faults at the I/O edge (SIM_LINK_DOWN, SIM_LINK_LOSS), and the GCS failsafe they trip,
with a real vehicle and session and a wall clock that the test advances itself."""
from __future__ import annotations

import pytest

from autopilot.faults.link import LinkFaults
from autopilot.mavlink.dialect import new_codec
from autopilot.mavlink.session import Session
from autopilot.modes import Rtl
from autopilot.params import ParamStore

from ._util import client_codec, hovering_vehicle, mav, statustexts, wire

FRAMES = [bytes([k % 256]) * 20 for k in range(4000)]


def kept_pattern(seed: int, loss_pct: float) -> list:
    params = ParamStore()
    link = LinkFaults(params, seed)
    params.set("SIM_LINK_LOSS", loss_pct)
    return [bool(link.pass_out([f])) for f in FRAMES]


def test_no_fault_no_filtering():
    link = LinkFaults(ParamStore(), 0)
    assert not link.active
    assert link.pass_out(FRAMES) is FRAMES


def test_loss_drops_that_share_each_way_and_counts_it():
    params = ParamStore()
    link = LinkFaults(params, 5)
    params.set("SIM_LINK_LOSS", 25)
    assert link.active
    sent = link.pass_out(FRAMES)
    got = link.admit(FRAMES, wall_s=0.0)
    for kept, way in ((sent, "out"), (got, "in")):
        assert len(kept) == pytest.approx(0.75 * len(FRAMES), rel=0.05)
        assert link.dropped[way] == len(FRAMES) - len(kept)


def test_loss_is_the_same_for_the_same_seed_only():
    assert kept_pattern(1, 50) == kept_pattern(1, 50)
    assert kept_pattern(1, 50) != kept_pattern(2, 50)
    assert not any(kept_pattern(1, 100)) and all(kept_pattern(1, 0))


def test_link_down_starts_after_the_answer_and_ends_by_itself():
    params = ParamStore()
    link = LinkFaults(params, 0)
    params.set("SIM_LINK_DOWN", 5)
    assert link.pass_out([b"echo"]) == [b"echo"]  # the PARAM_VALUE that answered the set still goes
    assert link.admit([b"hb"], wall_s=100.0) == [] and link.down
    assert link.pass_out([b"a", b"b"]) == []
    assert link.admit([b"hb"], wall_s=104.9) == []
    assert link.admit([b"hb"], wall_s=105.0) == [b"hb"]  # outage over
    assert params["SIM_LINK_DOWN"] == 0 and not link.active
    assert link.dropped == {"in": 2, "out": 2}


def test_setting_link_down_to_zero_restores_the_link_at_once():
    params = ParamStore()
    link = LinkFaults(params, 0)
    params.set("SIM_LINK_DOWN", 60)
    link.admit([], wall_s=0.0)
    params.set("SIM_LINK_DOWN", 0)
    assert link.admit([b"hb"], wall_s=1.0) == [b"hb"]


def test_a_cut_link_trips_the_gcs_failsafe_and_its_return_clears_it():
    v = hovering_vehicle(10.0)
    session = Session(v, new_codec(v.system_id))
    link = LinkFaults(v.params, 0)
    for name, value in (("FS_GCS_ENABLE", 1), ("FS_GCS_TIMEOUT", 2)):
        v.params.set(name, value)
    heartbeat = wire(client_codec().heartbeat_encode(mav.MAV_TYPE_GCS, mav.MAV_AUTOPILOT_INVALID, 0, 0, 0))
    heard = []

    def exchange(wall_s: float) -> None:
        """One tick of the runner: a GCS heartbeat every half second, through the faulty link."""
        incoming = [heartbeat] if round(wall_s * 10) % 5 == 0 else []
        for msg in link.admit(incoming, wall_s):
            session.receive(msg, v.time_s, wall_s)
        heard.extend(link.pass_out(session.poll(v.time_s, wall_s)))
        v.run_until(v.time_s + 0.1)

    ticks = iter(range(1000))  # wall time in tenths of a second
    for _ in range(20):  # 2 s of a healthy link
        exchange(next(ticks) / 10)
    v.params.set("SIM_LINK_DOWN", 4)
    heard.clear()
    tripped_after = None
    while v.params["SIM_LINK_DOWN"]:
        wall = next(ticks) / 10
        exchange(wall)
        if link.down:
            assert heard == []  # nothing gets out while the link is down
            if v.failsafes.gcs and tripped_after is None:
                tripped_after = wall - 1.5  # the last heartbeat through was at 1.5 s
    assert tripped_after == pytest.approx(2.0, abs=0.15)  # FS_GCS_TIMEOUT after it
    assert v.mode.number == Rtl.number
    assert link.dropped["out"] > 0 and link.dropped["in"] == 8  # the heartbeats of 4 s
    for _ in range(10):
        exchange(next(ticks) / 10)
    assert "GCS Failsafe Cleared" in statustexts(heard)
    assert not v.failsafes.gcs

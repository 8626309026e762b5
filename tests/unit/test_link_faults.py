"""Link faults (SIM_LINK_DOWN, SIM_LINK_LOSS), a stage of the sans-IO link, and the GCS failsafe
they trip, with a real vehicle, session and link and a link clock that the test advances itself."""
from __future__ import annotations

import pytest

from firefly.autopilot.faults.link import LinkFaults
from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.mavlink.link import Link
from firefly.autopilot.mavlink.session import Session
from firefly.autopilot.mavlink.signing import LinkSigning
from firefly.autopilot.modes import Rtl
from firefly.autopilot.params import ParamStore

from ._util import client_codec, hovering_vehicle, mav, statustexts

FRAMES = [bytes([k % 256]) * 20 for k in range(4000)]
GCS = ("127.0.0.1", 14550)


def kept_pattern(seed: int, loss_pct: float) -> list:
    params = ParamStore()
    link = LinkFaults(params, seed)
    params.set("SIM_LINK_LOSS", loss_pct)
    return [bool(link.pass_out([f])) for f in FRAMES]


def test_no_fault_no_filtering():
    link = LinkFaults(ParamStore(), 0)
    assert not link.active
    assert link.pass_out(FRAMES) is FRAMES
    assert not any(link.lose_in() for _ in FRAMES)


def test_loss_drops_that_share_each_way_and_counts_it():
    params = ParamStore()
    link = LinkFaults(params, 5)
    params.set("SIM_LINK_LOSS", 25)
    assert link.active
    sent = link.pass_out(FRAMES)
    got = [f for f in FRAMES if not link.lose_in()]
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
    assert not link.lose_in() and not link.down  # nor is anything lost before the outage starts
    link.advance(100.0)
    assert link.down and link.lose_in()
    assert link.pass_out([b"a", b"b"]) == []
    link.advance(104.9)
    assert link.lose_in()
    link.advance(105.0)  # outage over
    assert not link.lose_in()
    assert params["SIM_LINK_DOWN"] == 0 and not link.active
    assert link.dropped == {"in": 2, "out": 2}


def test_setting_link_down_to_zero_restores_the_link_at_once():
    params = ParamStore()
    link = LinkFaults(params, 0)
    params.set("SIM_LINK_DOWN", 60)
    link.advance(0.0)
    params.set("SIM_LINK_DOWN", 0)
    assert not link.down and not link.lose_in()


def _lossy_link(seed: int) -> Link:
    params = ParamStore()
    codec = new_codec(1)
    link = Link(codec, LinkSigning(codec), LinkFaults(params, seed))
    params.set("SIM_LINK_LOSS", 50)
    return link


def test_the_link_loses_received_frames_by_its_seed():
    gcs = client_codec()
    datagram = b"".join(gcs.heartbeat_encode(6, 8, 0, 0, 4).pack(gcs) for _ in range(200))

    def seqs(seed: int) -> list:
        return [m.get_seq() for m, _ in _lossy_link(seed).receive(datagram, GCS)]

    assert seqs(1) == seqs(1) != seqs(2)
    assert 60 < len(seqs(1)) < 140


def test_a_sender_whose_frames_are_all_lost_is_still_answered():
    from firefly.autopilot.io.runner import incoming
    link = _lossy_link(1)
    link.faults.params.set("SIM_LINK_LOSS", 100)
    gcs = client_codec()
    answered = []
    datagram = gcs.heartbeat_encode(6, 8, 0, 0, 4).pack(gcs)
    assert list(incoming([(datagram, GCS)], link, answered.append)) == []
    assert answered == [GCS]
    assert list(incoming([(b"\xfd\x00garbage", GCS)], link, answered.append)) == [] and answered == [GCS]


def test_a_cut_link_trips_the_gcs_failsafe_and_its_return_clears_it():
    v = hovering_vehicle(10.0)
    session = Session(v, new_codec(v.system_id))
    link = Link(session.codec, session.signing, LinkFaults(v.params, 0))
    for name, value in (("FS_GCS_ENABLE", 1), ("FS_GCS_TIMEOUT", 2)):
        v.params.set(name, value)
    gcs = client_codec()
    heartbeat = gcs.heartbeat_encode(mav.MAV_TYPE_GCS, mav.MAV_AUTOPILOT_INVALID, 0, 0, 0).pack(gcs)
    heard = []

    def exchange(link_s: float) -> None:
        """One tick of the runner: a GCS heartbeat every half second, through the faulty link."""
        link.advance(0.0, link_s)
        if round(link_s * 10) % 5 == 0:
            for msg, _ in link.receive(heartbeat, GCS):
                session.receive(msg, v.time_s, link_s)
        for frame in link.pack(session.poll(v.time_s, link_s)):
            heard.extend(gcs.parse_buffer(frame))
        v.run_until(v.time_s + 0.1)

    ticks = iter(range(1000))  # link time in tenths of a second
    for _ in range(20):  # 2 s of a healthy link
        exchange(next(ticks) / 10)
    v.params.set("SIM_LINK_DOWN", 4)
    heard.clear()
    tripped_after = None
    while v.params["SIM_LINK_DOWN"]:
        wall = next(ticks) / 10
        exchange(wall)
        if link.faults.down:
            assert heard == []  # nothing gets out while the link is down
            if v.failsafes.gcs and tripped_after is None:
                tripped_after = wall - 1.5  # the last heartbeat through was at 1.5 s
    assert tripped_after == pytest.approx(2.0, abs=0.15)  # FS_GCS_TIMEOUT after it
    assert v.mode.number == Rtl.number
    assert link.faults.dropped["out"] > 0 and link.faults.dropped["in"] == 8  # the heartbeats of 4 s
    for _ in range(10):
        exchange(next(ticks) / 10)
    assert "GCS Failsafe Cleared" in statustexts(heard)
    assert not v.failsafes.gcs

"""The sans-IO link: datagrams (bytes, sender) in, judged messages out; messages in, frames out.

No sockets: senders are address tuples, as recvfrom gives them, and the session on the other side
is the real one, so SETUP_SIGNING takes effect exactly as it does in the running vehicle."""
from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from firefly.autopilot.faults.link import LinkFaults
from firefly.autopilot.io.runner import incoming
from firefly.autopilot.mavlink import link as link_module
from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.mavlink.link import Link
from firefly.autopilot.mavlink.session import Session
from firefly.autopilot.mavlink.signing import LinkSigning, frame_signature, signing_time
from firefly.autopilot.params import ParamStore

from ._util import GCS_COMPONENT, GCS_SYSTEM, mav, ready_vehicle
from .test_signing import KEY, NOW, OTHER_KEY, arm_frame, radio_status_frame, signing_client

A, B = ("10.0.0.1", 14550), ("10.0.0.2", 14550)
NOW_UNIX_S = 1_750_000_000.0  # the wall clock the edge hands in; NOW is it in signing units


def plain_link(faults=None) -> Link:
    codec = new_codec(1)
    return Link(codec, LinkSigning(codec), faults)


def signed_link() -> Link:
    link = plain_link()
    link.signing.set_key(KEY)
    link.advance(NOW_UNIX_S, 0.0)
    return link


def plain_client():
    return new_codec(GCS_SYSTEM, GCS_COMPONENT)


def heartbeat_frame(codec) -> bytes:
    return bytes(codec.heartbeat_encode(mav.MAV_TYPE_GCS, mav.MAV_AUTOPILOT_INVALID, 0, 0, 0).pack(codec))


def types(judged) -> list:
    return [(m.get_type(), answerable) for m, answerable in judged]


# ----- per-sender parsers -------------------------------------------------------------------------
def test_a_frame_split_over_two_datagrams_of_one_sender_decodes_whole():
    link, frame = plain_link(), arm_frame(plain_client())
    assert list(link.receive(frame[:7], A)) == []
    assert types(link.receive(frame[7:], A)) == [("COMMAND_LONG", True)]


def test_interleaved_partial_frames_from_two_senders_do_not_mix():
    link = plain_link()
    arm, heartbeat = arm_frame(plain_client()), heartbeat_frame(plain_client())
    assert list(link.receive(arm[:20], A)) == []
    assert list(link.receive(heartbeat[:5], B)) == []
    assert types(link.receive(arm[20:], A)) == [("COMMAND_LONG", True)]
    assert types(link.receive(heartbeat[5:], B)) == [("HEARTBEAT", True)]


def test_parsers_are_bounded_and_the_longest_silent_loses_its_partial_frame():
    link, frame = plain_link(), arm_frame(plain_client())
    assert list(link.receive(frame[:20], A)) == []
    assert list(link.receive(frame[:20], B)) == []
    for port in range(link_module.MAX_PARSERS - 2):  # fills the table
        assert list(link.receive(b"", ("10.0.1.1", port))) == []
    assert list(link.receive(b"", A)) == []  # A is heard again: B is now the longest silent
    assert link.counters["parsers_evicted"] == 0
    assert list(link.receive(b"", ("10.0.9.9", 1))) == []  # one sender too many: B's parser goes
    assert link.counters["parsers_evicted"] == 1
    assert types(link.receive(frame[20:], A)) == [("COMMAND_LONG", True)]
    assert "COMMAND_LONG" not in [m.get_type() for m, _ in link.receive(frame[20:], B)]  # a fresh parser


def test_bad_data_goes_on_to_be_counted_but_does_not_make_a_peer():
    for link in (plain_link(), signed_link()):
        judged = list(link.receive(b"\x01\x02garbage", A))
        assert judged and all(m.get_type() == "BAD_DATA" and not answerable for m, answerable in judged)


@settings(max_examples=300, deadline=None)
@given(st.lists(st.tuples(st.binary(max_size=400), st.sampled_from([A, B])), max_size=8), st.booleans())
def test_any_bytes_from_any_sender_are_judged_never_raise(datagrams, signing_on):
    link = signed_link() if signing_on else plain_link()
    for data, sender in datagrams:
        for msg, answerable in link.receive(data, sender):
            assert isinstance(answerable, bool)
            assert msg.get_type() == "BAD_DATA" or msg.get_msgbuf()


# ----- signing admission --------------------------------------------------------------------------
def test_without_a_key_every_valid_frame_passes_and_makes_a_peer():
    assert types(plain_link().receive(arm_frame(plain_client()), A)) == [("COMMAND_LONG", True)]


def test_with_a_key_only_frames_signed_with_it_pass_and_the_rest_are_counted():
    link = signed_link()
    datagram = arm_frame(plain_client()) + arm_frame(signing_client(key=OTHER_KEY)) + \
        arm_frame(signing_client(timestamp=NOW + 1))
    assert types(link.receive(datagram, A)) == [("COMMAND_LONG", True)]
    assert link.signing.counters["dropped_unsigned"] == 1
    assert link.signing.counters["dropped_bad_signature"] == 1


def test_unsigned_radio_status_passes_but_does_not_make_a_peer():
    link = signed_link()
    datagram = radio_status_frame(plain_client()) + heartbeat_frame(plain_client())
    assert types(link.receive(datagram, A)) == [("RADIO_STATUS", False)]
    answered = []
    got = list(msg for msg, _ in incoming([(radio_status_frame(plain_client()), B)], link, answered.append))
    assert [m.get_type() for m in got] == ["RADIO_STATUS"] and answered == []


def test_a_sender_is_answered_once_per_datagram_with_a_message_that_may_be():
    link, answered = plain_link(), []
    client = plain_client()
    datagrams = [(heartbeat_frame(client) * 3, A), (b"garbage", B), (heartbeat_frame(client), B)]
    assert len(list(incoming(datagrams, link, answered.append))) == 5
    assert answered == [A, B]  # not B for its garbage


def _setup_signing_frame(codec, key: bytes) -> bytes:
    return bytes(codec.setup_signing_encode(1, 1, list(key), NOW).pack(codec))


def test_frames_after_setup_signing_are_judged_under_the_key_it_set():
    session = Session(ready_vehicle(), new_codec(1))
    link = Link(session.codec, session.signing)
    plain = plain_client()
    datagram = (_setup_signing_frame(plain, KEY) + arm_frame(plain)
                + arm_frame(signing_client(timestamp=NOW + 1)))
    passed = []
    for msg, _ in incoming([(datagram, A)], link, lambda sender: None):
        passed.append(msg.get_type())
        session.receive(msg, 0.0)  # handled before the next frame is judged, as the runner does
    assert passed == ["SETUP_SIGNING", "COMMAND_LONG"]  # the unsigned ARM after it was dropped ...
    assert session.signing.key == KEY and session.signing.counters["dropped_unsigned"] == 1
    assert session.signing.counters["accepted_signed"] == 1  # ... and the signed one admitted


def test_a_signed_setup_signing_that_clears_the_key_lets_unsigned_frames_after_it_in():
    session = Session(ready_vehicle(), new_codec(1))
    session.signing.set_key(KEY)
    link = Link(session.codec, session.signing)
    link.advance(NOW_UNIX_S, 0.0)
    datagram = _setup_signing_frame(signing_client(timestamp=NOW + 1), bytes(32)) + arm_frame(plain_client())
    passed = []
    for msg, answerable in link.receive(datagram, A):
        passed.append((msg.get_type(), answerable))
        session.receive(msg, 0.0)
    assert passed == [("SETUP_SIGNING", True), ("COMMAND_LONG", True)]
    assert not session.signing.enabled


# ----- time ---------------------------------------------------------------------------------------
def test_the_signing_timestamp_follows_the_wall_clock_handed_in_and_never_goes_back():
    link = plain_link()
    link.advance(NOW_UNIX_S, 0.0)
    assert link.signing.timestamp == 0  # signing off: nothing to follow
    link.signing.set_key(KEY)
    link.advance(NOW_UNIX_S, 0.0)
    assert link.signing.timestamp == NOW
    link.advance(NOW_UNIX_S + 2.0, 0.0)
    assert link.signing.timestamp == signing_time(NOW_UNIX_S + 2.0)
    link.advance(NOW_UNIX_S - 60.0, 0.0)  # a wall clock stepped back
    assert link.signing.timestamp == signing_time(NOW_UNIX_S + 2.0)


# ----- outgoing and link faults -------------------------------------------------------------------
def test_packed_frames_are_signed_exactly_when_a_key_is_set():
    link = plain_link()
    heartbeat = link.codec.heartbeat_encode(2, 3, 0, 0, 0)
    assert not link.pack([heartbeat])[0][2] & 0x01
    link.signing.set_key(KEY)
    link.advance(NOW_UNIX_S, 0.0)
    frame = link.pack([heartbeat])[0]
    assert frame[2] & 0x01 and frame[-6:] == frame_signature(KEY, frame[:-6])


def test_link_faults_are_a_stage_each_way():
    params = ParamStore()
    link = plain_link(LinkFaults(params, 0))
    heartbeat = link.codec.heartbeat_encode(2, 3, 0, 0, 0)
    datagram = heartbeat_frame(plain_client())
    params.set("SIM_LINK_DOWN", 5)
    assert len(link.pack([heartbeat])) == 1  # the answer to the set still goes out
    link.advance(NOW_UNIX_S, 100.0)  # the outage starts on the link clock
    assert list(link.receive(datagram, A)) == [] and link.pack([heartbeat]) == []
    link.advance(NOW_UNIX_S, 105.0)
    assert types(link.receive(datagram, A)) == [("HEARTBEAT", True)] and len(link.pack([heartbeat])) == 1
    assert link.faults.dropped == {"in": 1, "out": 1}

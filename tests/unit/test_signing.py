"""MAVLink 2 signing, sans-IO: raw frames in, admit or drop; the vehicle's own frames signed.

Frames are made by pymavlink's own signing client (a ground station's codec with the key), so a
frame accepted here is one a real signing ground station would send."""
from __future__ import annotations

import hashlib

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.mavlink.session import Session
from firefly.autopilot.mavlink.signing import (FUTURE_WINDOW, MAX_STREAMS, NEW_STREAM_WINDOW, RESERVE, SAVE_EVERY,
                                       TICKS_PER_S, LinkSigning, frame_signature, signing_time)

from ._util import GCS_COMPONENT, GCS_SYSTEM, mav, ready_vehicle, wire

KEY = hashlib.sha256(b"correct horse").digest()
OTHER_KEY = hashlib.sha256(b"battery staple").digest()
NOW = signing_time(1_750_000_000.0)  # a fixed wall-clock instant, in signing units


def signing_client(key=KEY, timestamp=NOW, link_id=0, system=GCS_SYSTEM, component=GCS_COMPONENT):
    """A ground station's pymavlink codec that signs what it packs."""
    codec = new_codec(system, component)
    codec.signing.secret_key = key
    codec.signing.sign_outgoing = True
    codec.signing.link_id = link_id
    codec.signing.timestamp = timestamp
    return codec


def arm_frame(codec) -> bytes:
    return codec.command_long_encode(1, 1, mav.MAV_CMD_COMPONENT_ARM_DISARM, 0, 1, 0, 0, 0, 0, 0, 0).pack(codec)


def radio_status_frame(codec) -> bytes:
    return codec.radio_status_encode(200, 180, 90, 50, 40, 0, 0).pack(codec)


@pytest.fixture
def link() -> LinkSigning:
    signing = LinkSigning(new_codec(1))
    signing.set_key(KEY)
    signing.advance(NOW)
    return signing


def dropped(link, reason: str) -> int:
    return link.counters[f"dropped_{reason}"]


# ----- accept and reject --------------------------------------------------------------------------
def test_frame_signed_with_the_key_is_admitted(link):
    assert link.admit(arm_frame(signing_client()))
    assert link.counters["accepted_signed"] == 1


def test_frame_signed_with_another_key_is_dropped(link):
    assert not link.admit(arm_frame(signing_client(key=OTHER_KEY)))
    assert dropped(link, "bad_signature") == 1


def test_tampered_payload_fails_the_signature(link):
    frame = bytearray(arm_frame(signing_client()))
    frame[12] ^= 0x01
    assert not link.admit(bytes(frame))
    assert dropped(link, "bad_signature") == 1


def test_unsigned_frames_are_dropped_except_the_radios(link):
    plain = new_codec(GCS_SYSTEM, GCS_COMPONENT)
    assert not link.admit(arm_frame(plain))
    assert link.admit(radio_status_frame(plain))
    assert link.admit(plain.radio_encode(200, 180, 90, 50, 40, 0, 0).pack(plain))
    assert dropped(link, "unsigned") == 1 and link.counters["accepted_unsigned"] == 2


def test_mavlink1_frames_cannot_be_signed_and_are_dropped(link):
    plain = new_codec(GCS_SYSTEM, GCS_COMPONENT)
    frame = plain.command_long_encode(1, 1, 400, 0, 1, 0, 0, 0, 0, 0, 0).pack(plain, force_mavlink1=True)
    assert frame[0] == 0xFE
    assert not link.admit(frame)
    assert dropped(link, "unsigned") == 1


@pytest.mark.parametrize("key", [bytes(32), KEY[:16]])
def test_a_key_is_32_bytes_not_all_zero(key):
    with pytest.raises(ValueError):
        LinkSigning(new_codec(1)).set_key(key)


def test_without_a_key_everything_is_admitted():
    signing = LinkSigning(new_codec(1))
    assert signing.admit(arm_frame(new_codec(GCS_SYSTEM, GCS_COMPONENT)))
    assert signing.admit(b"\x00garbage")
    assert not any(signing.counters.values())


# ----- timestamps: replay and stale streams -------------------------------------------------------
def test_replayed_frame_is_dropped(link):
    frame = arm_frame(signing_client())
    assert link.admit(frame)
    assert not link.admit(frame)
    assert dropped(link, "replay") == 1


def test_older_timestamp_on_a_stream_is_dropped_newer_is_admitted(link):
    assert link.admit(arm_frame(signing_client(timestamp=NOW + 100)))
    assert not link.admit(arm_frame(signing_client(timestamp=NOW + 50)))
    assert not link.admit(arm_frame(signing_client(timestamp=NOW + 100)))
    assert link.admit(arm_frame(signing_client(timestamp=NOW + 101)))
    assert dropped(link, "replay") == 2


def test_streams_are_per_system_component_and_link(link):
    assert link.admit(arm_frame(signing_client(timestamp=NOW + 100)))
    # the same older timestamp is new on another link id, and from another component
    assert link.admit(arm_frame(signing_client(timestamp=NOW + 50, link_id=1)))
    assert link.admit(arm_frame(signing_client(timestamp=NOW + 50, component=191)))
    assert set(link.streams) == {(GCS_SYSTEM, GCS_COMPONENT, 0), (GCS_SYSTEM, GCS_COMPONENT, 1),
                                 (GCS_SYSTEM, 191, 0)}


def test_new_stream_more_than_a_minute_behind_is_dropped(link):
    assert not link.admit(arm_frame(signing_client(timestamp=NOW - NEW_STREAM_WINDOW - 1)))
    assert dropped(link, "replay") == 1
    assert link.admit(arm_frame(signing_client(timestamp=NOW - NEW_STREAM_WINDOW + TICKS_PER_S)))


def test_forged_frame_with_a_huge_timestamp_does_not_lock_out_the_real_client(link):
    # pymavlink's own verifier records the timestamp before checking the signature; we must not
    assert not link.admit(arm_frame(signing_client(key=OTHER_KEY, timestamp=NOW + 10 ** 9)))
    assert link.admit(arm_frame(signing_client(timestamp=NOW + 1)))
    assert link.timestamp < NOW + 10 ** 9


def test_accepted_timestamp_ahead_of_the_local_clock_moves_it_forward(link):
    assert link.admit(arm_frame(signing_client(timestamp=NOW + 5 * TICKS_PER_S)))
    assert link.timestamp == NOW + 5 * TICKS_PER_S
    link.advance(NOW)  # the wall clock behind it does not pull it back
    assert link.timestamp == NOW + 5 * TICKS_PER_S


def test_full_stream_table_forgets_stale_streams_and_refuses_when_all_are_fresh(link):
    for n in range(MAX_STREAMS):
        assert link.admit(arm_frame(signing_client(link_id=n % 256, system=1 + n // 256)))
    assert not link.admit(arm_frame(signing_client(system=200)))
    assert dropped(link, "stream_table_full") == 1
    link.advance(NOW + NEW_STREAM_WINDOW + TICKS_PER_S)  # every stream is now more than a minute old
    assert link.admit(arm_frame(signing_client(system=200, timestamp=link.timestamp)))
    assert len(link.streams) == 1


@settings(max_examples=300, deadline=None)
@given(st.binary(max_size=300))
def test_any_bytes_are_admitted_or_dropped_never_raise(data):
    signing = LinkSigning(new_codec(1))
    signing.set_key(KEY)
    assert signing.admit(data) in (True, False)
    assert signing.admit(b"\xfd" + data) in (True, False)
    assert signing.admit(b"\xfd" + bytes([len(data), 1]) + data) in (True, False)


# ----- outgoing --------------------------------------------------------------------------------------
def test_outgoing_frames_carry_a_valid_signature_and_rising_timestamps(link):
    vehicle = ready_vehicle()
    session = Session(vehicle, new_codec(1))
    session.signing.set_key(KEY)
    session.signing.advance(NOW)
    frames = [m.pack(session.codec) for m in session.poll(vehicle.time_s)]
    assert len(frames) > 3
    stamps = []
    for frame in frames:
        assert frame[2] & 0x01, "signed flag not set"
        assert frame[-6:] == frame_signature(KEY, frame[:-6])
        stamps.append(int.from_bytes(frame[-12:-6], "little"))
    assert stamps[0] >= NOW and stamps == sorted(set(stamps))
    client = signing_client()  # a pymavlink ground station with the key accepts every one
    assert all(m.get_signed() for f in frames for m in client.parse_buffer(f))


def test_no_key_means_unsigned_outgoing_frames():
    session = Session(ready_vehicle(), new_codec(1))
    frame = session.codec.heartbeat_encode(2, 3, 0, 0, 0).pack(session.codec)
    assert not frame[2] & 0x01


# ----- SETUP_SIGNING ----------------------------------------------------------------------------------
def setup_signing(key: bytes, timestamp: int = NOW):
    client = new_codec(GCS_SYSTEM, GCS_COMPONENT)
    return wire(client.setup_signing_encode(1, 1, list(key), timestamp))


def test_setup_signing_sets_then_an_all_zero_key_clears_the_key():
    session = Session(ready_vehicle(), new_codec(1))
    saved = []
    session.signing.persist = lambda record: saved.append(record) or True
    session.receive(setup_signing(KEY, NOW + 7), 0.0)
    assert session.signing.key == KEY and session.signing.timestamp >= NOW + 7
    assert session.codec.signing.sign_outgoing
    assert saved[-1] == {"setup_key": KEY.hex(), "timestamp": session.signing.timestamp}
    session.receive(setup_signing(bytes(32), 0), 0.0)
    assert not session.signing.enabled and not session.codec.signing.sign_outgoing
    assert saved[-1]["setup_key"] is None
    assert session.signing.counters["setup_applied"] == 2


def test_setup_signing_is_refused_while_armed():
    session = Session(ready_vehicle(), new_codec(1))
    session.vehicle.arm()
    assert session.vehicle.armed
    session.receive(setup_signing(KEY), 0.0)
    assert not session.signing.enabled
    assert session.signing.counters["setup_refused_armed"] == 1


def test_setup_signing_for_another_system_is_ignored():
    session = Session(ready_vehicle(), new_codec(1))
    client = new_codec(GCS_SYSTEM, GCS_COMPONENT)
    session.receive(wire(client.setup_signing_encode(7, 1, list(KEY), NOW)), 0.0)
    assert not session.signing.enabled


# ----- across restarts: the saved high-water mark ------------------------------------------------
class Disk:
    """What a persist callback wrote last: what a process killed at any instant leaves behind."""

    def __init__(self):
        self.records = []

    def __call__(self, record) -> bool:
        self.records.append(dict(record))
        return True

    @property
    def last(self) -> dict:
        return self.records[-1]


def attached(clock: int, record=None, key=KEY) -> tuple[LinkSigning, Disk]:
    """A link booted at wall clock `clock` from `record`, saving to a Disk (as attach_state does)."""
    signing, disk = LinkSigning(new_codec(1)), Disk()
    signing.restore(record)
    signing.set_key(key)
    signing.persist = disk
    signing.advance(clock)
    return signing, disk


def test_an_accepted_timestamp_is_saved_before_its_frame_is_let_in():
    signing, disk = attached(NOW)
    client = signing_client()
    for n in range(50):  # a client at 10 frames a second, for 5 s
        client.signing.timestamp = NOW + n * TICKS_PER_S // 10
        signing.advance(client.signing.timestamp)
        frame = arm_frame(client)
        saved = len(disk.records)
        assert signing.admit(frame)
        stamp = int.from_bytes(frame[-12:-6], "little")
        assert disk.last["timestamp"] >= stamp  # on disk before admit() returned
        assert len(disk.records) - saved <= 1
    # a save every RESERVE of timestamps, not one a frame
    assert len(disk.records) <= 2 + 5 * TICKS_PER_S // RESERVE


def test_restarts_do_not_move_the_timestamp_ahead_of_the_clock():
    clock, record = NOW, None
    for _ in range(3):  # three restarts a few seconds apart, each after a client's frame
        signing, disk = attached(clock, record)
        assert clock <= signing.timestamp <= clock + RESERVE
        client = signing_client(timestamp=clock + TICKS_PER_S // 2)
        assert signing.admit(arm_frame(client))
        record = disk.last  # killed: what is on disk stays
        clock += 3 * TICKS_PER_S
    # ArduPilot's rule (a minute past the saved timestamp at each boot) would be three minutes ahead


def test_a_frame_accepted_before_a_kill_is_refused_after_the_restart():
    signing, disk = attached(NOW)
    client = signing_client(timestamp=NOW + TICKS_PER_S // 10)
    captured = [arm_frame(client) for _ in range(3)]
    assert all(signing.admit(f) for f in captured)
    after, _ = attached(NOW + 2 * TICKS_PER_S, disk.last)  # killed, restarted two seconds later
    assert not any(after.admit(f) for f in captured)
    assert after.counters["dropped_replay"] == 3
    # the same client, its clock right, is welcome; so is one that adopts the vehicle's timestamp
    assert after.admit(arm_frame(signing_client(timestamp=NOW + 2 * TICKS_PER_S)))
    assert after.admit(arm_frame(signing_client(timestamp=after.timestamp + 1, link_id=3)))


def test_a_restart_keeps_the_setup_key_and_the_mark_as_its_timestamp(link):
    link.setup_key = KEY
    link.save()
    after = LinkSigning(new_codec(1))
    after.restore(link.record())
    assert after.key == KEY
    assert after.timestamp == link.saved_timestamp == link.timestamp  # not a minute past it


def test_the_timestamp_is_saved_every_30_s_of_clock_as_ardupilot_saves_it():
    signing, disk = attached(NOW)
    saves = len(disk.records)
    signing.advance(NOW + SAVE_EVERY - 1)
    assert len(disk.records) == saves
    signing.advance(NOW + SAVE_EVERY + 1)
    assert len(disk.records) == saves + 1 and disk.last["timestamp"] == NOW + SAVE_EVERY + 1


# ----- frames from the future ---------------------------------------------------------------------
def test_a_frame_more_than_a_minute_ahead_of_the_clock_is_dropped_and_moves_nothing(link):
    assert not link.admit(arm_frame(signing_client(timestamp=NOW + FUTURE_WINDOW + TICKS_PER_S)))
    assert link.counters["dropped_future"] == 1 and link.timestamp == NOW and not link.streams
    assert link.admit(arm_frame(signing_client(timestamp=NOW + FUTURE_WINDOW - TICKS_PER_S)))


def test_a_key_holder_a_year_ahead_locks_no_one_out_not_even_across_a_restart():
    year = 365 * 24 * 3600 * TICKS_PER_S
    signing, disk = attached(NOW)
    assert not signing.admit(arm_frame(signing_client(timestamp=NOW + year, system=77)))
    assert signing.admit(arm_frame(signing_client(timestamp=NOW + 1)))  # a correct clock
    after, _ = attached(NOW + 5 * TICKS_PER_S, disk.last)
    assert after.timestamp < NOW + 5 * TICKS_PER_S + RESERVE
    assert after.admit(arm_frame(signing_client(timestamp=NOW + 5 * TICKS_PER_S, link_id=1)))


def test_setup_signing_takes_its_initial_timestamp_up_to_a_minute_ahead():
    session = Session(ready_vehicle(), new_codec(1))
    session.signing.advance(NOW)
    session.receive(setup_signing(KEY, NOW + 10 ** 12), 0.0)
    assert session.signing.key == KEY and session.signing.timestamp == NOW + FUTURE_WINDOW


@pytest.mark.parametrize("record", [None, [], {"setup_key": "zz", "timestamp": "x"},
                                    {"setup_key": "00" * 32, "timestamp": -5}, {"setup_key": 3}])
def test_malformed_saved_state_is_ignored(record):
    signing = LinkSigning(new_codec(1))
    signing.restore(record)
    assert not signing.enabled and signing.timestamp == 0


def test_summary_names_each_drop_reason(link):
    link.admit(arm_frame(new_codec(GCS_SYSTEM, GCS_COMPONENT)))
    assert link.summary() == ("signing on: dropped 1 unsigned, 0 bad signature, 0 replay, 0 future, "
                              "0 stream table full")

"""The fast telemetry packer (autopilot/mavlink/fast_pack.py) against pymavlink, byte for byte: every
message a telemetry builder makes, in several vehicle states, unsigned and signed, packed by the
fast path and by pymavlink's own message objects from the same values, at the same sequence
number, must be the same frame. And the link numbers its frames as ArduPilot does, one more each."""
from __future__ import annotations

import pytest

from firefly.autopilot.mavlink.dialect import mavlink as mav
from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.mavlink.fast_pack import FastCodec, PackedMessage
from firefly.autopilot.mavlink.link import Link
from firefly.autopilot.mavlink.signing import LinkSigning
from firefly.autopilot.mavlink.telemetry import BUILDERS

from ._util import ready_vehicle

KEY = bytes(range(32))


def flying_vehicle():
    v = ready_vehicle()
    v.set_mode(4)
    v.arm()
    v.takeoff(10.0)
    v.run_until(v.time_s + 6.0)
    return v


def sign(codec) -> None:
    codec.signing.secret_key = KEY
    codec.signing.link_id = 3
    codec.signing.timestamp = 123456789
    codec.signing.sign_outgoing = True


@pytest.mark.parametrize("signed", [False, True], ids=["unsigned", "signed"])
@pytest.mark.parametrize("state", ["on the ground", "flying"])
@pytest.mark.parametrize("msg_id", sorted(BUILDERS))
def test_every_streamed_message_packs_as_pymavlink_packs_it(msg_id, state, signed):
    vehicle = ready_vehicle() if state == "on the ground" else flying_vehicle()
    fast_codec, reference = new_codec(7), new_codec(7)
    for seq in (0, 41, 255):
        fast_codec.seq = reference.seq = seq
        if signed:
            sign(fast_codec)
            sign(reference)
        packed = BUILDERS[msg_id](vehicle, FastCodec(fast_codec))
        if packed is None:  # some messages exist only in some states (e.g. no terrain request due)
            continue
        assert isinstance(packed, PackedMessage)
        expected = packed.cls(*packed.args).pack(reference)
        assert packed.pack(fast_codec) == expected, (packed.get_type(), state, signed, seq)
        decoded = new_codec(255).parse_buffer(expected)
        assert decoded and decoded[0].get_msgId() == msg_id


def test_a_packed_message_reads_like_the_pymavlink_one():
    packed = FastCodec(new_codec(1)).named_value_float_encode(1234, b"GND_TEMP", 21.5)
    assert packed.get_type() == "NAMED_VALUE_FLOAT" and packed.get_msgId() == 251
    assert packed.time_boot_ms == 1234 and packed.name == "GND_TEMP" and packed.value == 21.5
    defaults = FastCodec(new_codec(1)).heartbeat_encode(2, 3, 4, 5, 6)
    assert defaults.mavlink_version == 3, "pymavlink's default arguments hold"


def test_each_link_numbers_its_frames_one_more_each_as_ardupilot_does():
    codec = new_codec(1)
    link = Link(codec, LinkSigning(codec))
    fast = FastCodec(codec)
    frames = link.pack([fast.heartbeat_encode(2, 3, 4, 5, 6), codec.statustext_encode(6, b"hello"),
                        fast.system_time_encode(0, 10)])
    frames += link.pack([fast.heartbeat_encode(2, 3, 4, 5, 6)])
    decoder = new_codec(255)
    seqs = [decoder.parse_buffer(f)[0].get_seq() for f in frames]
    assert seqs == [0, 1, 2, 3]
    for _ in range(251):
        link.pack([fast.heartbeat_encode(2, 3, 4, 5, 6)])
    (frame,) = link.pack([fast.heartbeat_encode(2, 3, 4, 5, 6)])
    assert new_codec(255).parse_buffer(frame)[0].get_seq() == 255 and codec.seq == 0, "it wraps at 256"
    (other,) = link.pack([fast.heartbeat_encode(2, 3, 4, 5, 6)], ("tcp", 5760, 1))
    assert new_codec(255).parse_buffer(other)[0].get_seq() == 0, "each link numbers its own frames"
    assert mav.MAVLINK_MSG_ID_HEARTBEAT == 0

"""The compiled MAVLink 2 frame (autopilot/mavlink/_frames.c) and its Python twin
(fast_pack.frame_py) make the same bytes: for every message of the dialect, over random payloads
(trailing zeros, all zeros, full length), every sequence number's edges and any system and
component; and both are pymavlink's frame of the same message. Bad arguments raise rather than
make a frame nobody can read, as the Python twin's struct packing does."""
from __future__ import annotations

import random

import pytest

from firefly.autopilot.control import compiled
from firefly.autopilot.mavlink.dialect import mavlink as mav
from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.mavlink.fast_pack import compiled_frame, frame_py

if compiled.required() and compiled_frame is None:  # CI builds it or fails the install
    pytest.fail("CI=true but the compiled frame (autopilot.mavlink._frames) is not built; "
                "see the compile errors of `pip install` (setup.py)", pytrace=False)
pytestmark = pytest.mark.skipif(compiled_frame is None, reason="compiled frame not built")

MESSAGES = sorted(mav.mavlink_map.values(), key=lambda cls: cls.id)


def payloads(cls, rng):
    size = cls.unpacker.size
    yield bytes(size)
    yield bytes([7]) + bytes(size - 1)
    yield bytes(rng.randrange(256) for _ in range(size))
    tail = rng.randrange(size + 1)
    yield bytes(rng.randrange(1, 256) for _ in range(size - tail)) + bytes(tail)


@pytest.mark.parametrize("cls", MESSAGES, ids=lambda cls: cls.msgname)
def test_the_compiled_frame_is_the_python_twins(cls):
    rng = random.Random(cls.id)
    for payload in payloads(cls, rng):
        for seq, system, component in ((0, 1, 1), (255, 255, 0), (rng.randrange(256), rng.randrange(256), 190)):
            args = (payload, cls.id, cls.crc_extra, seq, system, component)
            assert compiled_frame(*args) == frame_py(*args), (cls.msgname, payload.hex(), seq)


@pytest.mark.parametrize("cls", MESSAGES[::7], ids=lambda cls: cls.msgname)
def test_both_are_pymavlinks_frame(cls):
    """pymavlink packs a message of the values the payload holds; its frame is ours."""
    rng = random.Random(cls.id + 1)
    payload = bytes(rng.randrange(256) for _ in range(cls.unpacker.size))
    message = cls(*_values(cls, payload))
    codec = new_codec(9)
    codec.seq = 77
    expected = message.pack(codec)
    ours = compiled_frame(_payload_of(expected), cls.id, cls.crc_extra, 77, 9, codec.srcComponent)
    assert ours == expected


def _values(cls, payload: bytes) -> list:
    """The message's field values as the payload holds them, in the order its constructor takes."""
    wire = list(cls.unpacker.unpack(payload))
    values = {}
    for name, length in zip(cls.ordered_fieldnames, cls.array_lengths):
        field_type = dict(zip(cls.fieldnames, cls.fieldtypes))[name]
        if length and field_type != "char":
            values[name], wire = wire[:length], wire[length:]
        else:
            values[name], wire = wire[0], wire[1:]
    return [values[name] for name in cls.fieldnames]


def _payload_of(frame: bytes) -> bytes:
    return frame[10:10 + frame[1]]


@pytest.mark.parametrize("bad", [
    (b"\0", -1, 0, 0, 1, 1), (b"\0", 1 << 24, 0, 0, 1, 1), (b"\0", 0, 256, 0, 1, 1),
    (b"\0", 0, 0, 256, 1, 1), (b"\0", 0, 0, 0, -1, 1), (b"\0", 0, 0, 0, 1, 300),
    ("text", 0, 0, 0, 1, 1), (b"\1" * 300, 0, 0, 0, 1, 1), (b"\0", 0.5, 0, 0, 1, 1),
])
def test_bad_arguments_raise(bad):
    with pytest.raises((ValueError, TypeError)):
        compiled_frame(*bad)


def test_a_payload_of_zeros_keeps_one_byte():
    assert compiled_frame(bytes(300), 0, 50, 0, 1, 1) == frame_py(bytes(300), 0, 50, 0, 1, 1)
    assert compiled_frame(bytes(300), 0, 50, 0, 1, 1)[1] == 1

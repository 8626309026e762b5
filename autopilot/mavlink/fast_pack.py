"""Telemetry packed straight from its values: pymavlink's wire format without its message objects.

The telemetry builders call `codec.<name>_encode(...)` as they would on pymavlink's codec; given a
FastCodec instead, each call packs the payload at once with the message's own struct (a function
generated per message from pymavlink's field tables, arguments and defaults exactly as its encode
method takes them) and returns a PackedMessage. Its `pack(codec)` adds the MAVLink 2 header, trims
the payload's trailing zeros and appends the CRC with the message's CRC extra, as pymavlink does;
a signed link falls back to pymavlink's own packing, which signs. Reading a field of a
PackedMessage (tests, the rare service that looks) builds the pymavlink message then.

Why: building a pymavlink message object (an __init__ setting every field and its bookkeeping)
and packing it cost more than the rest of a vehicle's tick at speedup inf. The wire format must
not drift: tests/unit/test_fast_pack.py checks every streamed message byte for byte against
pymavlink, signed and unsigned.
"""
from __future__ import annotations

import inspect
import struct

from .dialect import mavlink as mav

_HEADER = struct.Struct("<BBBBBBBHB")
_CRC = struct.Struct("<H")
_crc16 = getattr(mav, "mcrf4xx", None)  # fastcrc's C CRC when pymavlink found it


def _crc(data: bytes) -> int:
    if _crc16 is not None:
        return _crc16(data, 0xFFFF)
    return mav.x25crc(data).crc


def frame_py(payload: bytes, msg_id: int, crc_extra: int, seq: int, system: int, component: int) -> bytes:
    """An unsigned MAVLink 2 frame of a packed payload, as pymavlink makes it: the payload less its
    trailing zeros (one byte kept), the header before it, the CRC with the CRC extra after it.
    The readable twin of the compiled `frame` (_frames.c)."""
    payload = payload.rstrip(b"\0") or payload[:1]
    body = _HEADER.pack(0xFD, len(payload), 0, 0, seq, system, component, msg_id & 0xFFFF, msg_id >> 16) + payload
    return body + _CRC.pack(_crc(body[1:] + bytes((crc_extra,))))


def _compiled_frame():
    try:
        from ._frames import frame
    except ImportError:  # no C compiler at install: the Python twin, the same bytes
        return None
    return frame


compiled_frame = _compiled_frame()
frame = compiled_frame or frame_py


class PackedMessage:
    """A message whose payload is packed; the frame is made when the link packs it."""
    __slots__ = ("cls", "payload", "args", "_message")

    def __init__(self, cls, payload: bytes, args: tuple):
        self.cls, self.payload, self.args, self._message = cls, payload, args, None

    def pack(self, codec, force_mavlink1: bool = False) -> bytes:
        if force_mavlink1 or codec.signing.sign_outgoing:
            return self.message().pack(codec, force_mavlink1)
        cls = self.cls
        return frame(self.payload, cls.id, cls.crc_extra, codec.seq, codec.srcSystem, codec.srcComponent)

    def message(self):
        """The pymavlink message of the same values."""
        if self._message is None:
            self._message = self.cls(*self.args)
        return self._message

    def get_type(self) -> str:
        return self.cls.msgname

    def get_msgId(self) -> int:
        return self.cls.id

    def __getattr__(self, name):  # a field, or anything else a pymavlink message answers
        return getattr(self.message(), name)

    def __repr__(self) -> str:
        return repr(self.message())


def _encoder(cls, pymavlink_encode):
    """encode(*values) -> PackedMessage, taking the values as pymavlink's encode method does (its
    defaults are the encode method's: HEARTBEAT's mavlink_version has one, the class has none)."""
    params = list(inspect.signature(pymavlink_encode).parameters.values())[1:]
    types = dict(zip(cls.fieldnames, cls.fieldtypes))
    wire = []
    for name, length in zip(cls.ordered_fieldnames, cls.array_lengths):
        if length and types[name] != "char":  # numeric arrays go on the wire element by element
            wire += [f"{name}[{i}]" for i in range(length)]
        else:
            wire.append(name)
    names = [p.name for p in params]
    if names != list(cls.fieldnames):
        raise TypeError(f"{cls.msgname}: encode takes {names}, the message has {cls.fieldnames}")
    signature = ", ".join(p.name if p.default is inspect.Parameter.empty else f"{p.name}=_d{i}"
                          for i, p in enumerate(params))
    source = (f"def encode({signature}):\n"
              f"    return _Packed(_cls, _pack({', '.join(wire)}), ({', '.join(names)},))\n")
    scope = {"_Packed": PackedMessage, "_cls": cls, "_pack": cls.unpacker.pack}
    scope.update({f"_d{i}": p.default for i, p in enumerate(params) if p.default is not inspect.Parameter.empty})
    exec(compile(source, f"<fast encode {cls.msgname}>", "exec"), scope)  # noqa: S102 - our own generated source
    return scope["encode"]


_ENCODERS: dict[str, object] = {}


def encoder(name: str):
    """The fast twin of pymavlink's `<name>_encode` (name without the suffix, e.g. "attitude")."""
    found = _ENCODERS.get(name)
    if found is None:
        cls = getattr(mav, f"MAVLink_{name}_message")
        found = _ENCODERS[name] = _encoder(cls, getattr(mav.MAVLink, f"{name}_encode"))
    return found


class FastCodec:
    """A codec for the telemetry builders: `<name>_encode` packs at once (PackedMessage); anything
    else is the wrapped pymavlink codec's."""

    def __init__(self, codec):
        self.codec = codec

    def __getattr__(self, attr):
        if attr.endswith("_encode"):
            fast = encoder(attr[:-len("_encode")])
            setattr(self, attr, fast)  # found once per codec
            return fast
        return getattr(self.codec, attr)

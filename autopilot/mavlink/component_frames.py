"""Messages sent as another component of the vehicle's system: the session's codec packs every
frame as the autopilot (component 1), so a message of SITL's ADS-B transceiver (156) or of the
thermal camera (100) carries its component id and its own numbering, which this wrapper swaps in
for the one frame."""
from __future__ import annotations


class FromComponent:
    COMPONENT = 0  # each kind of sender names its own

    def __init__(self, message, seq: int, component: int | None = None):
        self._message, self._seq = message, seq
        self._component = self.COMPONENT if component is None else component

    def pack(self, codec, force_mavlink1: bool = False) -> bytes:
        component, seq = codec.srcComponent, codec.seq
        codec.srcComponent, codec.seq = self._component, self._seq
        try:
            return self._message.pack(codec, force_mavlink1)
        finally:  # the link counts every frame it packs: one back, so the vehicle's own numbering has no gap
            codec.srcComponent, codec.seq = component, (seq - 1) & 0xFF

    def __getattr__(self, name):  # get_type() and the fields, as the message's
        return getattr(self._message, name)

"""A vehicle and its MAVLink session wired as on the wire, for the session tests (no sockets)."""
from __future__ import annotations

import pytest

from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.mavlink.session import Session

from ._util import GCS_COMPONENT, GCS_SYSTEM, client_codec, command_long, of_type, ready_vehicle

SYSTEM_ID = 1


class Link:
    """A vehicle and its session, with every outgoing message packed and decoded as on the wire."""

    def __init__(self, vehicle=None):
        self.vehicle = vehicle or ready_vehicle()
        self.session = Session(self.vehicle, new_codec(SYSTEM_ID))
        self._decoder = new_codec(GCS_SYSTEM, GCS_COMPONENT)

    def _decode(self, messages) -> list:
        out = []
        for m in messages:
            decoded = self._decoder.parse_buffer(m.pack(self.session.codec))
            assert decoded and len(decoded) == 1, m
            assert decoded[0].get_srcSystem() == SYSTEM_ID
            out.extend(decoded)
        return out

    def send(self, msg, now: float | None = None) -> list:
        now = self.vehicle.time_s if now is None else now
        return self._decode(self.session.receive(msg, now))

    def poll(self, now: float | None = None) -> list:
        now = self.vehicle.time_s if now is None else now
        return self._decode(self.session.poll(now))

    def command(self, command: int, *params, now=None, **kw):
        out = self.send(command_long(command, *params, **kw), now)
        acks = of_type(out, "COMMAND_ACK")
        assert len(acks) == 1, out
        assert acks[0].command == command
        return acks[0], out


@pytest.fixture
def link():
    return Link()


def gcs():
    return client_codec()


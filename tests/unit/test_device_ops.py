"""DEVICE_OP_READ / WRITE: every operation fails with the code ArduCopter SITL gives (measured)."""
from __future__ import annotations

import pytest

from firefly.autopilot.mavlink.dialect import mavlink as mav
from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.mavlink.session import Session
from firefly.autopilot.vehicle import Vehicle, VehicleConfig

from ._util import client_codec, wire

GCS = client_codec()


@pytest.fixture
def setup():
    v = Vehicle(VehicleConfig())
    return v, Session(v, new_codec(1))


def send(session, msg):
    return session.receive(wire(msg), 0.0, 1.0)


@pytest.mark.parametrize("bustype, result", [(mav.DEVICE_OP_BUSTYPE_I2C, 4), (mav.DEVICE_OP_BUSTYPE_SPI, 2), (7, 1)])
def test_device_operations_fail_with_arducopters_codes(setup, bustype, result):
    _, session = setup
    replies = send(session, GCS.device_op_read_encode(1, 1, 7, bustype, 0, 0x1E, b"", 3, 4))
    assert [(r.get_type(), r.request_id, r.result, r.regstart, r.count) for r in replies] == \
        [("DEVICE_OP_READ_REPLY", 7, result, 3, 0)]
    replies = send(session, GCS.device_op_write_encode(1, 1, 8, bustype, 0, 0x1E, b"", 0x7F, 1, [0] * 128))
    assert [(r.get_type(), r.request_id, r.result) for r in replies] == [("DEVICE_OP_WRITE_REPLY", 8, result)]

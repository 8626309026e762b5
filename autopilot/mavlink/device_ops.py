"""DEVICE_OP_READ / DEVICE_OP_WRITE (MAVProxy's devop module): raw register access to the board's
I2C and SPI devices. Firefly's simulated board has no bus devices, so every operation fails and
says why with ArduPilot's result codes, measured on ArduCopter SITL: an I2C transfer finds no
device answering (4, as SITL's bus 0 at 0x1E answers), an SPI device name is unknown (2), any
other bus type is unsupported (1). A failed read carries no data (count 0)."""
from __future__ import annotations

from .dialect import mavlink as mav

UNSUPPORTED_BUS, NO_DEVICE, TRANSFER_FAILED = 1, 2, 4


def _result(bustype: int) -> int:
    if bustype == mav.DEVICE_OP_BUSTYPE_I2C:
        return TRANSFER_FAILED
    if bustype == mav.DEVICE_OP_BUSTYPE_SPI:
        return NO_DEVICE
    return UNSUPPORTED_BUS


def read_reply(codec, msg):
    return codec.device_op_read_reply_encode(msg.request_id, _result(msg.bustype), msg.regstart, 0, [0] * 128,
                                             msg.bank)


def write_reply(codec, msg):
    return codec.device_op_write_reply_encode(msg.request_id, _result(msg.bustype))

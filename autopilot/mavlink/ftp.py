"""MAVLink FTP: not offered. Every request gets a NAK "file not found" at once, so QGroundControl
and MAVProxy fall back to the parameter and mission protocols without waiting for a timeout."""
from __future__ import annotations

import struct

OP_NAK = 129
ERR_FAIL = 1
ERR_FILE_NOT_FOUND = 10
OP_RESET_SESSIONS = 2
OP_TERMINATE_SESSION = 1
OP_ACK = 128


def reply(msg, codec):
    payload = bytes(msg.payload)
    if len(payload) < 12:
        return None
    seq, session, opcode = struct.unpack_from("<HBB", payload, 0)
    if opcode in (OP_ACK, OP_NAK):
        return None  # a reply from someone else; never answer a reply
    if opcode in (OP_RESET_SESSIONS, OP_TERMINATE_SESSION):
        out_op, size, data = OP_ACK, 0, b""
    else:
        out_op, size, data = OP_NAK, 1, bytes([ERR_FILE_NOT_FOUND])
    header = struct.pack("<HBBBBBBI", (seq + 1) & 0xFFFF, session, out_op, size, opcode, 0, 0, 0)
    body = (header + data).ljust(251, b"\0")
    return codec.file_transfer_protocol_encode(0, msg.get_srcSystem(), msg.get_srcComponent(),
                                               list(body))

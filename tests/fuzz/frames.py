"""Seeded MAVLink frames for the byte-level fuzz: well-formed messages of every kind the vehicle
handles (with hostile field values), and mutations of them as a broken radio or a fuzzer makes:
bit flips, truncation, splicing, garbage, bad CRCs, MAVLink 1 framing, unknown ids, oversize."""
from __future__ import annotations

import math
import random
import struct

from firefly.autopilot.mavlink.dialect import mavlink as mav
from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.params import PARAM_TABLE

SPECIAL = (0.0, 1.0, -1.0, 2989.0, 21196.0, 4.0, 1e30, -1e30, 3.4e38, math.nan, math.inf, -math.inf)
COMMANDS = (400, 400, 22, 21, 20, 176, 178, 179, 192, 410, 511, 512, 300, 115, 31999)
# Every parameter but the link faults: a noisy client that set SIM_LINK_LOSS to 100 % would silence
# the rest of a fuzz or soak run (tests/sitl/test_faults.py covers those on their own).
PARAM_NAMES = [s.name.encode() for s in PARAM_TABLE if not s.name.startswith("SIM_LINK")] + \
    [b"", b"X" * 16, b"\xff\xfe", b"SYSID_THISMAV"]


class FrameSource:
    def __init__(self, seed: int, target_system: int = 1, others: tuple = (0, 2, 255), source_system: int = 255,
                 param_names: list[bytes] = PARAM_NAMES):
        """`others`: the other target ids mixed in (0 is broadcast: it reaches the vehicle too);
        `source_system`: the id the frames come from (255 is the ground station's)."""
        self.rng = random.Random(seed)
        self.param_names = param_names
        self.source_system = source_system
        self.codec = new_codec(source_system, 190)
        self.v1 = mav.MAVLink(None, srcSystem=source_system, srcComponent=190)
        self.v1.WIRE_PROTOCOL_VERSION = "1.0"
        self.targets = (target_system,) * 3 + tuple(others)

    # ----- values -----------------------------------------------------------------------------
    def f(self) -> float:
        r = self.rng
        return r.choice(SPECIAL) if r.random() < 0.4 else r.uniform(-1e4, 1e4)

    def i(self, lo: int, hi: int) -> int:
        r = self.rng
        return r.choice((lo, hi, 0 if lo <= 0 <= hi else lo)) if r.random() < 0.3 else r.randint(lo, hi)

    def tgt(self) -> int:
        return self.rng.choice(self.targets)

    # ----- well-formed messages ----------------------------------------------------------------
    def message(self):
        c, r, f, i, t = self.codec, self.rng, self.f, self.i, self.tgt
        kind = r.randrange(14)
        if kind <= 3:
            return c.command_long_encode(t(), 1, r.choice(COMMANDS), i(0, 255), *(f() for _ in range(7)))
        if kind == 4:
            return c.command_int_encode(t(), 1, i(0, 21), r.choice(COMMANDS), 0, 0, *(f() for _ in range(4)),
                                        i(-2**31, 2**31 - 1), i(-2**31, 2**31 - 1), f())
        if kind == 5:
            return c.set_mode_encode(t(), i(0, 255), i(0, 20) if r.random() < 0.8 else i(0, 2**32 - 1))
        if kind == 6:
            return c.set_position_target_local_ned_encode(0, t(), 1, i(0, 21), i(0, 65535), *(f() for _ in range(11)))
        if kind == 7:
            return c.set_position_target_global_int_encode(0, t(), 1, i(0, 21), i(0, 65535), i(-2**31, 2**31 - 1),
                                                           i(-2**31, 2**31 - 1), *(f() for _ in range(9)))
        if kind == 8:
            return c.param_set_encode(t(), 1, r.choice(self.param_names), f(), i(0, 10))
        if kind == 9:
            return c.mission_count_encode(t(), 1, i(0, 800), r.choice((0, 1, 2, 3, 255)))
        if kind == 10:
            return c.mission_item_int_encode(t(), 1, i(0, 10), i(0, 21), r.choice(COMMANDS), 0, 1,
                                             *(f() for _ in range(4)), i(-2**31, 2**31 - 1),
                                             i(-2**31, 2**31 - 1), f(), r.choice((0, 1, 2, 255)))
        if kind == 11:
            return c.manual_control_encode(t(), *(i(-32768, 32767) for _ in range(4)), i(0, 65535))
        if kind == 12:
            return c.rc_channels_override_encode(t(), 1, *(i(0, 65535) for _ in range(8)))
        return c.heartbeat_encode(r.choice((6, 2, 0, 13)), 8, i(0, 255), i(0, 20), 4)

    def valid_frame(self) -> bytes:
        return bytes(self.message().pack(self.codec))

    # ----- what reaches a vehicle on a bad day -----------------------------------------------------
    def frame(self) -> tuple[str, bytes]:
        """One datagram and what kind of damage it carries."""
        r = self.rng
        kind = r.randrange(12)
        if kind == 6:
            return "garbage", r.randbytes(r.randint(1, 300))
        if kind == 9:
            return "unknown_id", self.unknown_id_frame()
        if kind == 10:
            return "many_in_one", b"".join(self.valid_frame() for _ in range(r.randint(2, 20)))
        good = self.valid_frame()  # what the other kinds damage
        if kind <= 2:
            return "valid", good
        if kind == 3:
            b = bytearray(good)
            for _ in range(r.randint(1, 4)):
                b[r.randrange(len(b))] ^= 1 << r.randrange(8)
            return "bit_flips", bytes(b)
        if kind == 4:
            return "truncated", good[:r.randrange(1, len(good))]
        if kind == 5:
            other = self.valid_frame()
            return "spliced", good[:r.randrange(len(good))] + other[r.randrange(len(other)):]
        if kind == 7:
            b = bytearray(good)
            b[-1] ^= 0xFF  # the CRC's high byte
            return "bad_crc", bytes(b)
        if kind == 8:
            msg = self.message()
            try:
                return "mavlink1", bytes(msg.pack(self.v1))
            except Exception:  # noqa: BLE001 - a message id above 255 has no MAVLink 1 form
                return "mavlink1", good
        return "oversize", good + r.randbytes(r.randint(300, 2000))

    def unknown_id_frame(self) -> bytes:
        """A MAVLink 2 frame with a well-formed header and an id no dialect defines."""
        r = self.rng
        payload = r.randbytes(r.randint(0, 40))
        msgid = r.choice((59999, 0xFFFFFF, 42000, 180))
        header = struct.pack("<BBBBBBBHB", 0xFD, len(payload), 0, 0, r.randrange(256), self.source_system, 190,
                             msgid & 0xFFFF, msgid >> 16)
        return header + payload + struct.pack("<H", r.getrandbits(16))

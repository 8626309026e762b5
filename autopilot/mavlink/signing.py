"""MAVLink 2 message signing of one vehicle's link, sans-IO.

`admit(frame)` decides, from the raw bytes of one received frame, whether it may reach the
session (the link, autopilot/mavlink/link.py, asks it for every frame while signing is on);
`setup(msg, armed)` handles SETUP_SIGNING. Outgoing frames are signed by the session's pymavlink
codec: this object owns that codec's signing state (key, link id, timestamp), so what the link
packs is signed exactly when a key is set, as ArduPilot does. Nothing here reads a clock: the
wall-clock time comes in through `advance`, from the I/O edge by way of the link.

The rules, from mavlink.io "Message Signing" and ArduPilot's GCS_Signing.cpp (and the C
library's mavlink_signature_check, which ArduPilot uses):
- signature = first 6 bytes of SHA-256(key + frame up to and including link id and timestamp);
- unsigned or wrongly signed frames are dropped, except RADIO_STATUS and RADIO (ArduPilot's
  accept list: a telemetry radio cannot sign what it injects);
- per stream (system id, component id, link id) a timestamp must exceed the last one accepted;
  a new stream must not be more than a minute behind the local timestamp (and here, new since a
  restart, must be above the saved mark: see below);
- (here) no timestamp may be more than a minute ahead of the vehicle's clock: see below;
- the local timestamp (10 µs units since 2015-01-01) never goes back: it is the larger of the
  wall clock handed in (ArduPilot takes GPS time), every accepted timestamp and, after a
  restart, the saved one.

Across a restart. ArduPilot saves the timestamp every 30 s and boots a minute past the saved one
("prevents a window for replay attacks", says its comment). Each restart thus moves it up to a
minute ahead of the clock, a minute more at each quick restart; and since a stream new to the
rebooted vehicle may be a minute behind, a frame accepted in the up to 30 s since the last save
is accepted again after a crash. Here the saved timestamp is a high-water mark that covers every
timestamp accepted before the process ended, however it ended: before a frame stamped above the
saved mark is let in, the mark is saved RESERVE past it (so a save every RESERVE of timestamps
while signed frames arrive, besides ArduPilot's one every 30 s; a disk that refuses it is
counted, and the frame let in all the same). At boot the local timestamp is the larger of that
mark and the clock, at most RESERVE ahead of the clock however many restarts, and a stream new
since the boot must be stamped above the mark: a frame captured before the restart is refused
after it (a client with a correct clock is past the mark once the restart has taken RESERVE).

Frames from the future. ArduPilot lets a correctly signed frame move its timestamp forward
without limit, and keeps it: one frame stamped a year ahead (a key holder with a wrong clock)
moves the vehicle a year ahead for good, and a client that starts a stream with a correct clock
is refused as more than a minute behind, across restarts too. Here, as a deliberate difference,
a frame stamped more than FUTURE_WINDOW (a minute, ArduPilot's own tolerance the other way) ahead
of the vehicle's clock is dropped ("future"), and SETUP_SIGNING's initial timestamp is taken up
to that window. No frame moves the vehicle more than a minute ahead of its clock, so a correct
clock is never refused as behind, and after a restart for a minute at most.

Unlike pymavlink's own verifier, a stream's timestamp is recorded only once the signature is
good, so a forged frame with a huge timestamp cannot lock a real client out.
"""
from __future__ import annotations

import hashlib
import hmac

from .dialect import mavlink as mav

SIGNING_EPOCH_UNIX_S = 1420070400  # 2015-01-01 00:00:00 UTC
TICKS_PER_S = 100_000  # the signing timestamp counts 10 µs units
NEW_STREAM_WINDOW = 60 * TICKS_PER_S
FUTURE_WINDOW = 60 * TICKS_PER_S  # how far ahead of the vehicle's clock a frame may be stamped
SAVE_EVERY = 30 * TICKS_PER_S  # the local timestamp is saved this often, as ArduPilot does
RESERVE = TICKS_PER_S // 2  # the saved high-water mark runs this far past the accepted timestamps
MAX_STREAMS = 256  # streams only a key holder can create; stale ones are forgotten when full
KEY_LEN = 32
MAX_TIMESTAMP = (1 << 48) - 1  # 48 bits on the wire
ACCEPT_UNSIGNED = frozenset({mav.MAVLINK_MSG_ID_RADIO_STATUS, mav.MAVLINK_MSG_ID_RADIO})

_V1_MAGIC, _V2_MAGIC = 0xFE, 0xFD
_V2_HEADER_LEN, _CRC_LEN, _SIGNATURE_BLOCK_LEN, _SIGNATURE_LEN = 10, 2, 13, 6
_IFLAG_SIGNED = 0x01

DROP_REASONS = ("unsigned", "bad_signature", "replay", "future", "stream_table_full")


def signing_time(unix_s: float) -> int:
    """Wall-clock seconds since 1970 as a signing timestamp (10 µs units since 2015)."""
    return max(0, int((unix_s - SIGNING_EPOCH_UNIX_S) * TICKS_PER_S))


def frame_signature(key: bytes, frame_to_timestamp: bytes) -> bytes:
    """The 6 signature bytes of a frame given up to the end of its 6-byte timestamp."""
    return hashlib.sha256(key + frame_to_timestamp).digest()[:_SIGNATURE_LEN]


def _frame_header(frame: bytes):
    """(msg id, system id, component id, signed) of a frame, or None if it is too short to say."""
    if len(frame) >= 6 and frame[0] == _V1_MAGIC:
        return frame[5], frame[3], frame[4], False
    if len(frame) >= _V2_HEADER_LEN and frame[0] == _V2_MAGIC:
        msg_id = frame[7] | frame[8] << 8 | frame[9] << 16
        return msg_id, frame[5], frame[6], bool(frame[2] & _IFLAG_SIGNED)
    return None


class LinkSigning:
    def __init__(self, codec):
        self._out = codec.signing  # pymavlink signs every frame `codec` packs from this state
        self._out.link_id = 0
        self.streams: dict[tuple, int] = {}  # (sysid, compid, link id) -> last accepted timestamp
        self.last_verified = False  # whether admit() last let a frame in for a good signature
        self.setup_key: bytes | None = None  # the key set by SETUP_SIGNING, which is persisted
        self.persist = None  # callable(record) -> bool that saves record() durably, or None
        self._saved_timestamp = 0  # the high-water mark saved last
        self._boot_mark = 0  # the mark saved before this boot: a new stream must be above it
        self._clock = 0  # the wall clock last handed in, as a signing timestamp (0: none yet)
        self.counters = {"accepted_signed": 0, "accepted_unsigned": 0, "setup_applied": 0,
                         "setup_refused_armed": 0, "save_failed": 0}
        self.counters.update({f"dropped_{r}": 0 for r in DROP_REASONS})

    # ----- key and timestamp ------------------------------------------------------------------
    @property
    def key(self) -> bytes | None:
        return self._out.secret_key

    @property
    def enabled(self) -> bool:
        return self._out.secret_key is not None

    @property
    def timestamp(self) -> int:
        return self._out.timestamp

    @property
    def saved_timestamp(self) -> int:
        """The high-water mark saved last: above every timestamp accepted so far."""
        return self._saved_timestamp

    def set_key(self, key: bytes | None) -> None:
        """Sign and require signatures with `key`; None turns signing off."""
        if key is not None and (len(key) != KEY_LEN or not any(key)):
            # an all-zero key is no secret: SETUP_SIGNING sends it to mean "off"
            raise ValueError(f"a signing key is {KEY_LEN} bytes, not all zero")
        self._out.secret_key = key
        self._out.sign_outgoing = key is not None

    def advance(self, clock: int) -> None:
        """The wall clock now, as a signing timestamp: the local timestamp moves forward to it
        (never back), and is saved now and then."""
        self._clock = clock
        self._forward(clock)
        if self.enabled and self._out.timestamp - self._saved_timestamp >= SAVE_EVERY:
            self.save()

    def _forward(self, timestamp: int) -> None:
        if self._out.timestamp < timestamp <= MAX_TIMESTAMP:
            self._out.timestamp = timestamp

    def _latest_allowed(self) -> int:
        """The latest timestamp a frame may carry: FUTURE_WINDOW past the vehicle's own time (its
        clock, or the mark it booted with if the clock is behind it). Before any clock is handed
        in there is nothing to judge by, and no limit (as ArduPilot before its GPS time)."""
        if not self._clock:
            return MAX_TIMESTAMP
        return max(self._clock, self._boot_mark) + FUTURE_WINDOW

    def record(self) -> dict:
        """What survives a restart: the SETUP_SIGNING key and the high-water mark."""
        return {"setup_key": self.setup_key.hex() if self.setup_key else None,
                "timestamp": self._saved_timestamp}

    def restore(self, record) -> None:
        """Take back record() after a restart; a malformed record is ignored."""
        if not isinstance(record, dict):
            return
        stamp = record.get("timestamp")
        if isinstance(stamp, int) and not isinstance(stamp, bool) and 0 < stamp <= MAX_TIMESTAMP:
            self._boot_mark = self._saved_timestamp = stamp
            self._forward(stamp)
        try:
            key = bytes.fromhex(record.get("setup_key") or "")
        except (TypeError, ValueError):
            return
        if len(key) == KEY_LEN and any(key):
            self.setup_key = key
            self.set_key(key)

    def save(self, mark: int = 0) -> None:
        """Save the high-water mark: at least `mark`, the local timestamp and the last mark."""
        self._saved_timestamp = max(self._saved_timestamp, self._out.timestamp, mark)
        if self.persist is not None and not self.persist(self.record()):
            self.counters["save_failed"] += 1

    # ----- incoming ---------------------------------------------------------------------------
    def admit(self, frame: bytes) -> bool:
        """True if the frame may reach the session; a dropped frame is counted by its reason."""
        self.last_verified = False
        if not self.enabled:
            return True
        header = _frame_header(frame)
        if header is None:
            return self._drop("unsigned")
        msg_id, sysid, compid, signed = header
        reason = self._check_signed(bytes(frame), sysid, compid) if signed else "unsigned"
        if reason is None:
            self.counters["accepted_signed"] += 1
            self.last_verified = True
            return True
        if msg_id in ACCEPT_UNSIGNED:  # as the C library: its callback overrides any failed check
            self.counters["accepted_unsigned"] += 1
            return True
        return self._drop(reason)

    def _drop(self, reason: str) -> bool:
        self.counters[f"dropped_{reason}"] += 1
        return False

    def _check_signed(self, frame: bytes, sysid: int, compid: int) -> str | None:
        """None if the signed frame is good and new on its stream, else the reason to drop it."""
        if len(frame) != _V2_HEADER_LEN + frame[1] + _CRC_LEN + _SIGNATURE_BLOCK_LEN:
            return "bad_signature"
        expected = frame_signature(self._out.secret_key, frame[:-_SIGNATURE_LEN])
        if not hmac.compare_digest(expected, frame[-_SIGNATURE_LEN:]):
            return "bad_signature"
        link_id = frame[-_SIGNATURE_BLOCK_LEN]
        stamp = int.from_bytes(frame[-12:-_SIGNATURE_LEN], "little")
        stream = (sysid, compid, link_id)
        last = self.streams.get(stream)
        if last is not None and stamp <= last:
            return "replay"
        if last is None:
            # a new stream: not more than a minute old (ArduPilot), and, new since the boot,
            # above every timestamp accepted before it (the saved mark)
            if stamp + NEW_STREAM_WINDOW < self._out.timestamp or stamp <= self._boot_mark:
                return "replay"
        if stamp > self._latest_allowed():
            return "future"
        if last is None and len(self.streams) >= MAX_STREAMS and not self._forget_stale_streams():
            return "stream_table_full"
        if stamp > self._saved_timestamp:  # kept before it is let in: a kill cannot lose it
            self.save(stamp + RESERVE)
        self.streams[stream] = stamp
        self._forward(stamp)
        return None

    def _forget_stale_streams(self) -> bool:
        """Forget streams whose frames would fail the new-stream check anyway; True if any went."""
        oldest_allowed = self._out.timestamp - NEW_STREAM_WINDOW
        stale = [s for s, t in self.streams.items() if t < oldest_allowed]
        for stream in stale:
            del self.streams[stream]
        return bool(stale)

    # ----- SETUP_SIGNING ----------------------------------------------------------------------
    def setup(self, msg, armed: bool) -> None:
        """SETUP_SIGNING: set (or, with an all-zero key, clear) the key and persist it.

        It reaches here only through admit(): once signing is on, only a frame signed with the
        current key can change it. Refused while armed, as ArduPilot does."""
        if armed:
            self.counters["setup_refused_armed"] += 1
            return
        key = bytes(msg.secret_key)
        self.setup_key = key if len(key) == KEY_LEN and any(key) else None
        self.set_key(self.setup_key)
        self._forward(min(msg.initial_timestamp, self._latest_allowed()))  # see "Frames from the future"
        self.counters["setup_applied"] += 1
        self.save()

    def summary(self) -> str:
        """One line of what was dropped, for the process to report."""
        dropped = ", ".join(f"{self.counters[f'dropped_{r}']} {r.replace('_', ' ')}" for r in DROP_REASONS)
        return f"signing {'on' if self.enabled else 'off'}: dropped {dropped}"

"""One vehicle's MAVLink link, sans-IO: datagrams in, judged messages out; messages in, frames out.

Receiving, `receive(data, sender)`: one datagram is decoded by its sender's own parser, so partial
frames from interleaved clients never mix (a parser keeps a partial frame until that sender's next
datagram; at most MAX_PARSERS are kept, the longest silent goes first). Then each message is
judged in turn:
- BAD_DATA (what a damaged frame decodes to) goes on, for the session to count;
- with MAVLink 2 signing on, the session's LinkSigning admits or drops the frame (and counts it);
- the link-fault stage (SIM_LINK_DOWN / SIM_LINK_LOSS, autopilot/faults/link.py), when active,
  may lose it.
Each message that gets through comes out with whether its sender may be answered: only a sender of
a frame that passed signing (any valid frame while signing is off). An unsigned RADIO_STATUS passes
(a radio cannot sign what it injects) but does not make its sender a peer; nor does BAD_DATA.

Messages are judged lazily, one per draw from the iterator: a caller that hands each message to the
session before drawing the next has every frame judged against the key as it is after everything
before it, so the frames after a SETUP_SIGNING, in the same datagram or later, are judged under the
key it set. (Drawing the whole datagram into a list first would judge them under the old key.)

Sending, `pack(messages, to)`: the session's codec packs them and signs them when a key is set, each
frame with the next sequence number of the link `to` (as ArduPilot numbers each channel's frames:
a client counts the gaps as lost frames, and a client does not see what another link is answered);
then the link-fault stage may lose frames, which leaves gaps as a lossy radio would.

Time: nothing here reads a clock. The I/O edge calls `advance(unix_s, link_s)` before each
exchange with the wall clock it read: the signing timestamp follows that wall-clock time (Unix
seconds), and link outages run on the link clock (monotonic seconds).
"""
from __future__ import annotations

from collections import OrderedDict
from collections.abc import Iterator

from .dialect import new_codec
from .signing import signing_time

MAX_PARSERS = 64  # per-sender frame parsers kept (a parser holds a partial frame between datagrams)


class Link:
    def __init__(self, codec, signing, faults=None):
        """`codec`: the session's codec, which packs and signs what is sent; `signing`: the
        session's LinkSigning; `faults`: LinkFaults, or None for a perfect link."""
        self.codec = codec
        self.signing = signing
        self.faults = faults
        self._system_id = codec.srcSystem
        self._parsers: OrderedDict = OrderedDict()  # sender -> its parser, least recently heard first
        self.counters = {"decode_errors": 0, "parsers_evicted": 0, "unpackable": 0}
        # told (exception, message type) of a message that would not pack: the vehicle's internal
        # error (cli/main.py wires it), so that a test fails on it
        self.on_unpackable = None
        self.sender_answerable = False  # whether the last datagram's sender may be answered
        self._seq: dict = {}  # link key -> the sequence number of its next frame

    def advance(self, unix_s: float, link_s: float) -> None:
        """The time now, handed in by the I/O edge: wall clock (Unix s) and link clock (s)."""
        signing = self.signing
        if signing.enabled:
            signing.advance(signing_time(unix_s))
        faults = self.faults
        if faults is not None and faults.active:
            faults.advance(link_s)

    # ----- incoming ---------------------------------------------------------------------------
    def receive(self, data: bytes, sender) -> Iterator[tuple]:
        """(message, whether its sender may be answered) for each message of one datagram that
        gets through; each is judged when drawn (see the module docstring)."""
        self.sender_answerable = False
        messages = self._decode(data, sender)
        if not messages:
            return
        signing, faults = self.signing, self.faults
        # SIM_LINK_LOSS set by a message of this datagram applies from the next one
        lossy = faults is not None and faults.active
        for msg in messages:
            if msg.get_type() == "BAD_DATA":
                answerable = False
            elif not signing.enabled:
                answerable = True
            elif signing.admit(msg.get_msgbuf()):
                answerable = signing.last_verified  # False for an unsigned RADIO_STATUS
            else:
                continue
            # Who may be answered is judged before the fault stage: a frame the link then loses
            # still makes its sender a peer (the socket layer always judged it so).
            self.sender_answerable |= answerable
            if lossy and faults.lose_in():
                continue
            yield msg, answerable

    def forget(self, sender) -> None:
        """A link that closed: its parser and numbering go."""
        self._parsers.pop(sender, None)
        self._seq.pop(sender, None)

    def _decode(self, data: bytes, sender) -> list:
        parser = self._parsers.get(sender)
        if parser is None:
            if len(self._parsers) >= MAX_PARSERS:
                self._parsers.popitem(last=False)
                self.counters["parsers_evicted"] += 1
            parser = self._parsers[sender] = new_codec(self._system_id)
        else:
            self._parsers.move_to_end(sender)
        try:
            return parser.parse_buffer(data) or []
        except Exception:  # noqa: BLE001 - any malformed frame is counted and dropped
            self.counters["decode_errors"] += 1
            parser.buf = bytearray()
            parser.buf_index = 0
            return []

    # ----- outgoing ---------------------------------------------------------------------------
    def pack(self, messages: list, to=None) -> list:
        """The frames to send on link `to` for `messages`, signed when a key is set, less what the
        link loses."""
        codec = self.codec
        codec.seq = self._seq.get(to, 0)
        frames = []
        for m in messages:
            try:  # costs nothing until a message carries a value its field cannot hold (a bug)
                frames.append(m.pack(codec))
            except Exception as exc:  # noqa: BLE001 - the rest of the batch (a COMMAND_ACK) still goes
                self.counters["unpackable"] += 1
                if self.on_unpackable is not None:
                    self.on_unpackable(exc, m.get_type())
                continue
            codec.seq = (codec.seq + 1) & 0xFF
        seqs = self._seq
        if to not in seqs and len(seqs) >= MAX_PARSERS:  # links come and go: the oldest known goes
            del seqs[next(iter(seqs))]
        seqs[to] = codec.seq
        faults = self.faults
        if frames and faults is not None and faults.active:
            return faults.pass_out(frames)
        return frames

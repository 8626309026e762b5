"""The only module with sockets: one UDP socket per vehicle.

It sends to the configured outputs (like MAVProxy's --out behind ArduPilot SITL) and to every
address that has sent it a valid MAVLink frame, so whoever talks to the vehicle is answered.
Each peer gets its own parser, so interleaved datagrams from different clients never mix.
With MAVLink 2 signing on, frames that fail it are dropped here (and counted by the link's
LinkSigning) before anything else sees them, and their senders are not answered. Frames are judged
in arrival order against the key as it is then: what follows a SETUP_SIGNING waits until the
session has handled it. The signing timestamp follows the wall clock, read here at the I/O edge.

Floods: one call reads at most MAX_DATAGRAMS_PER_RECEIVE datagrams, so a sender faster than the
vehicle cannot stall its loop; the rest wait in the kernel, which drops what overflows its buffer
(Linux counts those per socket in /proc/net/udp; totals() reads it). Answered peers and per-sender parsers are bounded too: a
flood from many source ports evicts the longest-silent, never the configured outputs.
"""
from __future__ import annotations

import os
import socket
import time
from collections import OrderedDict, deque

from ..mavlink.dialect import new_codec
from ..mavlink.signing import signing_time

MAX_DATAGRAM = 1400
MAX_DATAGRAMS_PER_RECEIVE = 512  # per loop tick: 51,200 a second at 1x, five times a 10 kHz flood
MAX_PEERS = 32  # answered addresses besides the configured outputs
MAX_PARSERS = 64  # per-sender frame parsers kept (a parser holds a partial frame between datagrams)


class UdpEndpoint:
    def __init__(self, bind: tuple, outs: list[tuple], system_id: int):
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.setblocking(False)
        self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 1 << 20)
        self.sock.bind(bind)
        self._outs = list(dict.fromkeys(outs))
        self._heard: OrderedDict = OrderedDict()  # peers that sent a valid frame, least recent first
        self._parsers: OrderedDict = OrderedDict()
        self._system_id = system_id
        self.signing = None  # the session's LinkSigning, to drop frames that fail signing
        self._held: deque = deque()  # (sender, messages) that arrived after a SETUP_SIGNING
        self.counters = {"datagrams": 0, "decode_errors": 0, "send_errors": 0, "peers_evicted": 0,
                         "parsers_evicted": 0}

    def totals(self) -> dict:
        """The counters, with the datagrams the kernel dropped for a full buffer (None if unknown)."""
        return self.counters | {"kernel_dropped": self.kernel_dropped()}

    def kernel_dropped(self) -> int | None:
        try:
            inode = str(os.fstat(self.sock.fileno()).st_ino)
            with open("/proc/net/udp") as table:
                for line in table:
                    fields = line.split()
                    if len(fields) > 12 and fields[9] == inode:
                        return int(fields[-1])
        except (OSError, ValueError):
            pass
        return None

    @property
    def peers(self) -> list[tuple]:
        """Where telemetry goes: the configured outputs, then everyone recently heard."""
        return self._outs + [p for p in self._heard if p not in self._outs]

    @property
    def decode_errors(self) -> int:
        return self.counters["decode_errors"]

    @property
    def send_errors(self) -> int:
        return self.counters["send_errors"]

    @property
    def address(self) -> tuple:
        return self.sock.getsockname()

    def fileno(self) -> int:
        return self.sock.fileno()

    def receive(self) -> list:
        """Every message waiting on the socket, decoded (bad frames come back as BAD_DATA)."""
        if self.signing is not None and self.signing.enabled:
            self.signing.advance(signing_time(time.time()))
        messages = []
        for _ in range(MAX_DATAGRAMS_PER_RECEIVE):
            batch = self._held.popleft() if self._held else self._read_datagram()
            if batch is None:
                return messages
            addr, decoded = batch
            for k, msg in enumerate(decoded):
                if not self._admit(msg, addr):
                    continue
                messages.append(msg)
                if msg.get_type() == "SETUP_SIGNING":
                    # The key may change once the session handles it: judge what follows after.
                    if k + 1 < len(decoded):
                        self._held.appendleft((addr, decoded[k + 1:]))
                    return messages
        return messages  # the rest waits for the next tick

    def _read_datagram(self):
        """(sender, its decoded messages) for the next datagram, or None when there is none."""
        while True:
            try:
                data, addr = self.sock.recvfrom(65535)
            except (BlockingIOError, InterruptedError):
                return None
            except OSError:  # e.g. ICMP port unreachable reported on some systems
                continue
            self.counters["datagrams"] += 1
            parser = self._parser_for(addr)
            try:
                return addr, parser.parse_buffer(data) or []
            except Exception:  # noqa: BLE001 - any malformed frame is counted and dropped
                self.counters["decode_errors"] += 1
                parser.buf = bytearray()
                parser.buf_index = 0

    def _parser_for(self, addr):
        parser = self._parsers.get(addr)
        if parser is None:
            if len(self._parsers) >= MAX_PARSERS:
                self._parsers.popitem(last=False)
                self.counters["parsers_evicted"] += 1
            parser = self._parsers[addr] = new_codec(self._system_id)
        else:
            self._parsers.move_to_end(addr)
        return parser

    def _admit(self, msg, addr) -> bool:
        """Whether `msg` goes on to the session; its sender becomes a peer if it passed signing."""
        if msg.get_type() == "BAD_DATA":  # the session counts it
            return True
        signing = self.signing
        if signing is not None and not signing.admit(msg.get_msgbuf()):
            return False
        if signing is not None and signing.enabled and not signing.last_verified:
            return True  # an unsigned RADIO_STATUS may pass, but must not make its sender a peer
        if addr in self._heard:
            self._heard.move_to_end(addr)
        else:
            if len(self._heard) >= MAX_PEERS:
                self._heard.popitem(last=False)
                self.counters["peers_evicted"] += 1
            self._heard[addr] = True
        return True

    def send(self, frames: list[bytes]) -> None:
        """Send packed frames to every peer, several frames per datagram."""
        peers = self.peers
        if not frames or not peers:
            return
        datagrams, current = [], b""
        for frame in frames:
            if current and len(current) + len(frame) > MAX_DATAGRAM:
                datagrams.append(current)
                current = b""
            current += frame
        datagrams.append(current)
        for peer in peers:
            for datagram in datagrams:
                try:
                    self.sock.sendto(datagram, peer)
                except OSError:
                    self.counters["send_errors"] += 1

    def close(self) -> None:
        self.sock.close()

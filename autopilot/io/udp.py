"""A vehicle's UDP socket, and the table of who it answers (tcp.py has its TCP links).

It reads and sends datagrams and knows nothing of MAVLink: what a datagram holds, whether its
frames pass signing and whether its sender may be answered is the vehicle's sans-IO link's to say
(autopilot/mavlink/link.py). Each peer is a link of its own: the configured outputs (like
ArduPilot SITL's udpclient serial ports, or MAVProxy's --out) and every address the link found may
be answered (`answer`), each sent what is queued for it.

Floods: what one receive hands the loop is bounded, so that no sender can stall it: at most
MAX_DATAGRAMS_PER_RECEIVE datagrams and, past the first, MAX_BYTES_PER_RECEIVE bytes (decoding
costs up to about 1 µs a byte of junk in pymavlink's parser, handling a message some 25-50 µs);
a datagram larger than MAX_DATAGRAM_IN is read but dropped unseen and counted. The loop reads
again as soon as its tick's work is done, so a bounded receive costs a legitimate client nothing
but a turn; the rest waits in the kernel, which drops what overflows its buffer (Linux counts
those per socket in /proc/net/udp; totals() reads it). Answered peers are bounded too: a flood
from many source ports evicts the longest silent, never the configured outputs.
"""
from __future__ import annotations

import os
import socket
from collections import OrderedDict

MAX_DATAGRAM = 1400  # bytes per datagram sent: several frames, under a typical MTU
# Per receive, so that one exchange costs at most a few milliseconds (a 10 ms tick at 1x): 64
# messages are 2-3 ms of decoding and handling, 2 KB of the costliest junk about 2 ms. The loop
# reads again whenever its tick leaves time (at 1x it waits on the socket), so a legitimate
# burst is read in several turns of the same tick.
MAX_DATAGRAMS_PER_RECEIVE = 64
MAX_BYTES_PER_RECEIVE = 2048
# Larger than a MAVLink sender makes: a frame is at most 280 bytes, clients send one a datagram and
# radio bridges at most an MTU's worth (ArduPilot's SITL likewise reads a datagram into a fixed buffer).
MAX_DATAGRAM_IN = 2048
MAX_PEERS = 32  # answered addresses besides the configured outputs


class UdpEndpoint:
    def __init__(self, bind: tuple, outs: list[tuple]):
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.setblocking(False)
        self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 1 << 20)
        self.sock.bind(bind)
        self._outs = list(dict.fromkeys(outs))
        self._heard: OrderedDict = OrderedDict()  # senders the link let be answered, least recent first
        self.counters = {"datagrams": 0, "oversize_dropped": 0, "send_errors": 0, "peers_evicted": 0}
        self._peers = list(self._outs)
        self._queued: dict = {}  # peer -> [frames waiting for a flush (runner.py says when), their bytes]

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
        """Where telemetry goes: the configured outputs, then everyone recently answered."""
        return self._peers

    def _update_peers(self) -> None:
        self._peers = self._outs + [p for p in self._heard if p not in self._outs]

    def heard(self, peer: tuple) -> bool:
        """Whether `peer` has sent something answerable (ArduPilot's 'active' channel)."""
        return peer in self._heard

    @property
    def address(self) -> tuple:
        return self.sock.getsockname()

    def fileno(self) -> int:
        return self.sock.fileno()

    def receive(self) -> list[tuple]:
        """(datagram, sender) for datagrams waiting: at most MAX_DATAGRAMS_PER_RECEIVE, and no
        more once they hold MAX_BYTES_PER_RECEIVE bytes; oversize ones are dropped and counted."""
        datagrams = []
        recvfrom = self.sock.recvfrom
        size = oversize = 0
        for _ in range(MAX_DATAGRAMS_PER_RECEIVE):
            if size >= MAX_BYTES_PER_RECEIVE:
                break
            try:
                data, sender = recvfrom(65535)
            except (BlockingIOError, InterruptedError):
                break
            except OSError:  # e.g. ICMP port unreachable reported on some systems; it uses a read
                continue
            if len(data) > MAX_DATAGRAM_IN:
                oversize += 1
                size += MAX_DATAGRAM_IN
                continue
            size += len(data)
            datagrams.append((data, sender))
        counters = self.counters
        counters["datagrams"] += len(datagrams) + oversize
        counters["oversize_dropped"] += oversize
        return datagrams

    def answer(self, sender: tuple) -> None:
        """Send to `sender` from now on; when MAX_PEERS are answered, the longest silent goes."""
        heard = self._heard
        if sender in heard:
            heard.move_to_end(sender)
            return
        if len(heard) >= MAX_PEERS:
            gone, _ = heard.popitem(last=False)
            self._queued.pop(gone, None)
            self.counters["peers_evicted"] += 1
        heard[sender] = True
        self._update_peers()

    def queue(self, frames: list[bytes], peer: tuple) -> None:
        """Keep packed frames for `peer` until the next flush; a datagram's worth goes at once."""
        waiting = self._queued.get(peer)
        if waiting is None:
            waiting = self._queued[peer] = [[], 0]
        for frame in frames:
            if waiting[0] and waiting[1] + len(frame) > MAX_DATAGRAM:
                self._send(b"".join(waiting[0]), peer)
                waiting[0], waiting[1] = [], 0
            waiting[0].append(frame)
            waiting[1] += len(frame)

    def flush(self) -> None:
        """Send what is queued, several frames per datagram, to each peer."""
        if self._queued:
            for peer, (frames, _) in self._queued.items():
                if frames:
                    self._send(b"".join(frames), peer)
            self._queued = {}

    def _send(self, datagram: bytes, peer: tuple) -> None:
        try:
            self.sock.sendto(datagram, peer)
        except OSError:
            self.counters["send_errors"] += 1

    def close(self) -> None:
        self.sock.close()

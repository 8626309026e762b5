"""The pymavlink connection `firefly.mavlink()` hands a test: one that loses nothing while the test
is busy elsewhere.

A vehicle flat out sends about 30,000 messages a second (in about 750 datagrams); at 10x, 600 a
second. A plain pymavlink connection reads its socket only inside recv_match, so during a
`firefly.sleep(30)` the kernel's buffer (about 200 datagrams by default) overflows and messages
vanish: a STATUSTEXT never seen, ATTITUDE jumping seconds. Here a thread of the connection's own
moves every datagram from the socket into a queue as it arrives, and pymavlink's recv_msg and
recv_match read that queue. The thread only copies bytes (about 750 recvfrom calls a second flat
out); decoding stays in the test's thread, when the test asks for a message.
"""
from __future__ import annotations

import collections
import select
import socket
import threading
import time

from pymavlink import mavutil

RCVBUF_BYTES = 4 << 20  # the kernel's share: covers the thread's waits for the GIL
MAX_QUEUED_BYTES = 1 << 28  # 256 MiB: minutes of flat-out telemetry nobody reads; then the oldest go


class QueuedUdpConnection(mavutil.mavudp):
    """pymavlink's `udpin:` connection, whose socket a reader thread empties into an unbounded-
    until-MAX_QUEUED_BYTES queue. Everything else (recv_match, mav.*_send, messages, ...) is
    pymavlink's own; `dropped_datagrams` counts what the cap ever discarded (0 in any test that
    reads its messages at all)."""

    def __init__(self, address: str, source_system: int = 255, source_component: int = 0):
        super().__init__(address, input=True, source_system=source_system, source_component=source_component)
        self.port.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, RCVBUF_BYTES)
        self.dropped_datagrams = 0
        self._queue: collections.deque[tuple[bytes, tuple]] = collections.deque()
        self._queued_bytes = 0
        self._arrived = threading.Condition()
        self._stop_r, self._stop_w = socket.socketpair()
        self._reader = threading.Thread(target=self._read_socket, name=f"firefly mavlink {address}", daemon=True)
        self._reader.start()

    def _read_socket(self) -> None:
        sock, stop = self.port, self._stop_r
        while True:
            try:
                ready, _, _ = select.select([sock, stop], [], [])
            except (OSError, ValueError):  # closed under us
                return
            if stop in ready:
                return
            batch = []
            try:
                while True:  # the socket is non-blocking (pymavlink's choice): read until it is empty
                    batch.append(sock.recvfrom(65535))
            except (BlockingIOError, InterruptedError):
                pass
            except OSError:
                return
            with self._arrived:
                for datagram in batch:
                    self._queue.append(datagram)
                    self._queued_bytes += len(datagram[0])
                while self._queued_bytes > MAX_QUEUED_BYTES:
                    self._queued_bytes -= len(self._queue.popleft()[0])
                    self.dropped_datagrams += 1
                self._arrived.notify_all()

    def recv(self, n=None):
        """The oldest datagram not yet read ("" when none), as pymavlink's mavudp.recv returns it."""
        with self._arrived:
            if not self._queue:
                return ""
            data, address = self._queue.popleft()
            self._queued_bytes -= len(data)
        # what mavudp.recv does for a udpin link: replies go to every address heard from
        self.clients.add(address)
        self.clients_last_alive[address] = time.time()
        return data

    def select(self, timeout):
        """Wait up to `timeout` seconds for a datagram (pymavlink's blocking recv_match calls this)."""
        with self._arrived:
            return self._arrived.wait_for(lambda: bool(self._queue), timeout)

    def close(self) -> None:
        """Stop the reader and close the socket; again is harmless (a test may close it before
        the fixture does)."""
        if self._stop_w.fileno() < 0:
            return
        self._stop_w.send(b"x")
        self._reader.join(timeout=2.0)
        self._stop_r.close()
        self._stop_w.close()
        super().close()


def queued_connection(url: str, source_system: int = 255) -> QueuedUdpConnection:
    """As `mavutil.mavlink_connection(url, source_system=..., dialect="ardupilotmega")` for a
    `udpin:HOST:PORT` url, with the queue."""
    if not url.startswith("udpin:"):
        raise ValueError(f"expected a udpin:HOST:PORT url, got {url!r}")
    mavutil.set_dialect("ardupilotmega")
    return QueuedUdpConnection(url[len("udpin:"):], source_system=source_system)

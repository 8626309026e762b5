"""TCP links, as ArduPilot SITL's serial ports give them: a server many clients connect to
(SERIAL0 is tcp:5760 + 10 * instance), and a client that connects out and retries.

Each connection is one link, named by a key (("tcp", port, n) or ("tcpclient", host, port)); what
the bytes hold is the sans-IO link's to decode (a stream: a frame may arrive in pieces, the link's
parser for that key keeps the partial frame). Sending never blocks the loop: what the kernel does
not take waits in the connection's buffer, and past MAX_PENDING bytes new frames are dropped, as a
full serial port's are, until the client reads again.
"""
from __future__ import annotations

import errno
import socket
import time

MAX_RECEIVE = 4096  # bytes read from one connection per receive (a flood waits its turn)
MAX_PENDING = 1 << 18  # bytes kept for a client that does not read
MAX_CLIENTS = 16
RETRY_CONNECT_S = 1.0  # wall time between a client's connection attempts


class TcpConnection:
    def __init__(self, sock: socket.socket, key):
        sock.setblocking(False)
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self.sock, self.key = sock, key
        self.pending = bytearray()
        self.open = True
        self.dropped_bytes = 0

    def fileno(self) -> int:
        return self.sock.fileno()

    def receive(self) -> bytes:
        try:
            data = self.sock.recv(MAX_RECEIVE)
        except (BlockingIOError, InterruptedError):
            return b""
        except OSError:
            data = b""
        if not data:  # the peer closed (or the connection broke)
            self.close()
        return data

    def send(self, data: bytes) -> None:
        """Keep `data` for the next flush (dropped whole if the client has stopped reading)."""
        pending = self.pending
        if len(pending) + len(data) > MAX_PENDING:
            self.dropped_bytes += len(data)
        else:
            pending += data

    def flush(self) -> None:
        if not self.pending or not self.open:
            return
        try:
            sent = self.sock.send(self.pending)
        except (BlockingIOError, InterruptedError):
            return
        except OSError:
            self.close()
            return
        del self.pending[:sent]

    def close(self) -> None:
        if self.open:
            self.open = False
            self.sock.close()


class TcpServer:
    """Accepts clients on `bind`; each is a link until it closes."""

    def __init__(self, bind: tuple):
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        self.sock.bind(bind)
        self.sock.listen(MAX_CLIENTS)
        self.sock.setblocking(False)
        self.port = self.sock.getsockname()[1]
        self.connections: list[TcpConnection] = []
        self._accepted = 0
        self.counters = {"tcp_accepted": 0, "tcp_refused": 0}

    @property
    def address(self) -> tuple:
        return self.sock.getsockname()

    def filenos(self) -> list[int]:
        return [self.sock.fileno(), *(c.fileno() for c in self.connections)]

    def accept(self) -> bool:
        """Take every client waiting; whether any came."""
        came = False
        while True:
            try:
                sock, _ = self.sock.accept()
            except (BlockingIOError, InterruptedError):
                return came
            except OSError as exc:  # e.g. too many open files: try again next time
                if exc.errno in (errno.EMFILE, errno.ENFILE, errno.ENOBUFS, errno.ENOMEM):
                    return came
                continue
            if len(self.connections) >= MAX_CLIENTS:
                sock.close()
                self.counters["tcp_refused"] += 1
                continue
            self._accepted += 1
            self.counters["tcp_accepted"] += 1
            self.connections.append(TcpConnection(sock, ("tcp", self.port, self._accepted)))
            came = True

    def close(self) -> None:
        for c in self.connections:
            c.close()
        self.sock.close()


class TcpClient:
    """Connects to `target` and keeps trying (every RETRY_CONNECT_S of wall time) while it cannot."""

    def __init__(self, target: tuple):
        self.target = target
        self.connection: TcpConnection | None = None
        self._connecting: socket.socket | None = None
        self._next_try = 0.0
        self.counters = {"tcp_connects": 0}

    def filenos(self) -> list[int]:
        if self.connection is not None:
            return [self.connection.fileno()]
        return []

    def poll(self) -> bool:
        """Advance the connection attempt; whether it just connected."""
        if self.connection is not None:
            if self.connection.open:
                return False
            self.connection = None
        now = time.monotonic()
        if self._connecting is None:
            if now < self._next_try:
                return False
            self._next_try = now + RETRY_CONNECT_S
            sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
            sock.setblocking(False)
            code = sock.connect_ex(self.target)
            if code not in (0, errno.EINPROGRESS):
                sock.close()
                return False
            self._connecting = sock
        sock = self._connecting
        code = sock.getsockopt(socket.SOL_SOCKET, socket.SO_ERROR)
        if code == 0:
            try:
                sock.getpeername()
            except OSError:  # still connecting
                if now >= self._next_try:
                    sock.close()
                    self._connecting = None
                return False
            self._connecting = None
            self.counters["tcp_connects"] += 1
            self.connection = TcpConnection(sock, ("tcpclient", *self.target))
            return True
        sock.close()
        self._connecting = None
        return False

    def close(self) -> None:
        if self.connection is not None:
            self.connection.close()
        if self._connecting is not None:
            self._connecting.close()

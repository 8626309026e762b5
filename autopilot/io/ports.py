"""A vehicle's serial ports, as ArduPilot SITL's --serialN gives them: one UDP socket (its
configured outputs and whoever it answers) and any number of TCP servers and clients.

To the loop they are one set of links, each named by a key: a UDP peer's address, or a TCP
connection's key (tcp.py). `receive()` hands over (bytes, key) pairs, `queue(key, frames)` and
`flush()` send, `links` lists every link there is to send on now, and `heard(key)` says whether
a link has spoken (ArduPilot's active channel). Links that closed since the last call come out of
`take_closed()`, so the sans-IO side can forget their routes and numbering.
"""
from __future__ import annotations

import time

from .tcp import TcpClient, TcpServer
from .udp import UdpEndpoint

ACCEPT_EVERY_S = 0.005  # wall time between looks for new TCP clients


class Ports:
    def __init__(self, udp: UdpEndpoint | None = None, tcp_servers: list[TcpServer] | None = None,
                 tcp_clients: list[TcpClient] | None = None):
        self.udp = udp
        self.tcp_servers = tcp_servers or []
        self.tcp_clients = tcp_clients or []
        self._connections: dict = {}  # key -> TcpConnection, every open TCP link
        self._spoken: set = set()  # TCP links that have sent something answerable
        self.closed: list = []  # keys of links that closed since take_closed()
        self.version = 0  # changes whenever the set of sockets to wait on changes
        self._next_accept_s = 0.0
        self.notes: list[str] = []  # what a person starting the vehicle should hear (a default port taken)
        self._links: list = []
        self._filenos: list[int] = []
        self._refresh()

    # ----- what there is ---------------------------------------------------------------------
    def _refresh(self) -> None:
        udp_peers = self.udp.peers if self.udp is not None else []
        self._links = [*udp_peers, *self._connections]
        filenos = [self.udp.fileno()] if self.udp is not None else []
        for server in self.tcp_servers:
            filenos += server.filenos()
        for client in self.tcp_clients:
            filenos += client.filenos()
        if filenos != self._filenos:
            self._filenos = filenos
            self.version += 1

    @property
    def links(self) -> list:
        """Every link to send on: UDP outputs and answered peers, then open TCP connections."""
        return self._links

    def filenos(self) -> list[int]:
        return self._filenos

    @property
    def address(self) -> tuple:
        if self.udp is not None:
            return self.udp.address
        return self.tcp_servers[0].address

    @property
    def tcp_addresses(self) -> list[tuple]:
        return [s.address for s in self.tcp_servers]

    def heard(self, key) -> bool:
        if key in self._connections:
            return key in self._spoken
        return self.udp is not None and self.udp.heard(key)

    def take_closed(self) -> list:
        closed, self.closed = self.closed, []
        return closed

    # ----- in --------------------------------------------------------------------------------
    def receive(self) -> list[tuple]:
        """(bytes, link key) for what is waiting on every port; accepts and connects as it goes."""
        got = self.udp.receive() if self.udp is not None else []
        changed = False
        if self.tcp_servers:
            # an accept that finds nobody raises inside the socket module: flat out, asking at every
            # receive cost a tenth of the loop; a client waits at most ACCEPT_EVERY_S to be taken
            now = time.monotonic()
            if now >= self._next_accept_s:
                self._next_accept_s = now + ACCEPT_EVERY_S
                for server in self.tcp_servers:
                    if server.accept():
                        for c in server.connections:
                            self._connections.setdefault(c.key, c)
                        changed = True
        for client in self.tcp_clients:
            if client.poll() and client.connection is not None:
                self._connections[client.connection.key] = client.connection
                changed = True
        if self._connections:
            for key, connection in list(self._connections.items()):
                data = connection.receive()
                if data:
                    got.append((data, key))
                elif not connection.open:
                    self._drop(key)
                    changed = True
        if changed:
            self._refresh()
        return got

    def _drop(self, key) -> None:
        del self._connections[key]
        self._spoken.discard(key)
        self.closed.append(key)
        for server in self.tcp_servers:
            server.connections = [c for c in server.connections if c.open]

    def answer(self, key) -> None:
        """`key` has sent something answerable: a UDP sender becomes a peer (answered from now on)."""
        if key in self._connections:
            self._spoken.add(key)
        elif self.udp is not None:
            new_peer = not self.udp.heard(key)
            self.udp.answer(key)
            if new_peer:  # the links to send on changed (and a long-silent peer may have gone)
                self._refresh()

    # ----- out -------------------------------------------------------------------------------
    def queue(self, key, frames: list[bytes]) -> None:
        connection = self._connections.get(key)
        if connection is not None:
            connection.send(b"".join(frames))
        elif self.udp is not None:
            self.udp.queue(frames, key)

    def flush(self) -> None:
        if self.udp is not None:
            self.udp.flush()
        if self._connections:
            closed = False
            for key, connection in list(self._connections.items()):
                connection.flush()
                if not connection.open:
                    self._drop(key)
                    closed = True
            if closed:
                self._refresh()

    # ----- accounts --------------------------------------------------------------------------
    def totals(self) -> dict:
        totals = self.udp.totals() if self.udp is not None else {}
        for server in self.tcp_servers:
            for name, n in server.counters.items():
                totals[name] = totals.get(name, 0) + n
        totals["tcp_dropped_bytes"] = sum(c.dropped_bytes for c in self._connections.values())
        return totals

    def close(self) -> None:
        if self.udp is not None:
            self.udp.close()
        for server in self.tcp_servers:
            server.close()
        for client in self.tcp_clients:
            client.close()

"""The only module with sockets: one UDP socket per vehicle.

It sends to the configured outputs (like MAVProxy's --out behind ArduPilot SITL) and to every
address that has sent it a valid MAVLink frame, so whoever talks to the vehicle is answered.
Each peer gets its own parser, so interleaved datagrams from different clients never mix.
"""
from __future__ import annotations

import socket

from .mavlink.dialect import new_codec

MAX_DATAGRAM = 1400


class UdpEndpoint:
    def __init__(self, bind: tuple, outs: list[tuple], system_id: int):
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.setblocking(False)
        self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 1 << 20)
        self.sock.bind(bind)
        self.peers: list[tuple] = list(dict.fromkeys(outs))
        self._parsers: dict = {}
        self._system_id = system_id
        self.decode_errors = 0
        self.send_errors = 0

    @property
    def address(self) -> tuple:
        return self.sock.getsockname()

    def fileno(self) -> int:
        return self.sock.fileno()

    def receive(self) -> list:
        """Every message waiting on the socket, decoded (bad frames come back as BAD_DATA)."""
        messages = []
        while True:
            try:
                data, addr = self.sock.recvfrom(65535)
            except (BlockingIOError, InterruptedError):
                return messages
            except OSError:  # e.g. ICMP port unreachable reported on some systems
                continue
            parser = self._parsers.get(addr)
            if parser is None:
                parser = self._parsers[addr] = new_codec(self._system_id)
            try:
                decoded = parser.parse_buffer(data) or []
            except Exception:  # noqa: BLE001 - any malformed frame is counted and dropped
                self.decode_errors += 1
                parser.buf = bytearray()
                parser.buf_index = 0
                continue
            if any(m.get_type() != "BAD_DATA" for m in decoded) and addr not in self.peers:
                self.peers.append(addr)
            messages.extend(decoded)

    def send(self, frames: list[bytes]) -> None:
        """Send packed frames to every peer, several frames per datagram."""
        if not frames or not self.peers:
            return
        datagrams, current = [], b""
        for frame in frames:
            if current and len(current) + len(frame) > MAX_DATAGRAM:
                datagrams.append(current)
                current = b""
            current += frame
        datagrams.append(current)
        for peer in self.peers:
            for datagram in datagrams:
                try:
                    self.sock.sendto(datagram, peer)
                except OSError:
                    self.send_errors += 1

    def close(self) -> None:
        self.sock.close()

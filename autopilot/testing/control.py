"""The plugin's own MAVLink link to one vehicle: parameters and the ready states, over pymavlink.

It listens on a port of its own (the autopilot sends to it as to any --out), so the user's MAVSDK
or pymavlink client never sees a reply it did not ask for, except the PARAM_VALUE ArduPilot sends
to every link when a parameter changes. Telemetry keeps arriving here whether or not anybody
reads it; before each request the socket is emptied without decoding, so a reply is found among
the few messages that follow it, even when the vehicle runs flat out.
"""
from __future__ import annotations

import math
import socket
import struct
import time

from .errors import FireflyError

MAV_RESULT = {0: "ACCEPTED", 1: "TEMPORARILY_REJECTED", 2: "DENIED", 3: "UNSUPPORTED", 4: "FAILED",
              5: "IN_PROGRESS", 6: "CANCELLED"}
REPLY_WALL_S = 2.0  # per attempt; loopback loses nothing unless the test asked for SIM_LINK_* faults
ATTEMPTS = 3
REASON_WALL_S = 0.5  # how long a refused PARAM_SET's STATUSTEXT is looked for
STATUSTEXT_CHARS = 50


class ControlError(FireflyError):
    """A request the vehicle refused or never answered."""


class ControlLink:
    def __init__(self, port: int, system_id: int, alive):
        from pymavlink import mavutil
        self.system_id = system_id
        self.alive = alive  # () -> None; raises if the autopilot process has exited
        self.conn = mavutil.mavlink_connection(f"udpin:127.0.0.1:{port}", source_system=255,
                                               source_component=191, dialect="ardupilotmega")
        self.conn.port.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 1 << 16)

    def close(self) -> None:
        self.conn.close()

    def _drain(self) -> None:
        # pymavlink's udpin socket is non-blocking and must stay so: its recv_match(timeout=...)
        # reads after a select and would wait forever on a blocking socket with nothing to read.
        sock = self.conn.port
        sock.setblocking(False)
        try:
            while True:
                sock.recv(65536)
        except (BlockingIOError, InterruptedError):
            pass

    def _await(self, send, match, what: str):
        """send(), then the first message for which match(msg) is not None, retried ATTEMPTS times."""
        for _ in range(ATTEMPTS):
            # nothing can be sent before the vehicle's first datagram (pymavlink >= 2.4.4x keeps
            # a udpin link's peers in `clients`, older ones in `last_address`)
            if getattr(self.conn, "clients", None) or self.conn.last_address is not None:
                self._drain()
            send()
            deadline = time.monotonic() + REPLY_WALL_S
            while time.monotonic() < deadline:
                msg = self.conn.recv_match(blocking=True, timeout=0.05)
                if msg is None:
                    self.alive()
                    continue
                if msg.get_srcSystem() != self.system_id:
                    continue
                found = match(msg)
                if found is not None:
                    return found
        raise ControlError(f"firefly: vehicle {self.system_id} did not answer {what}")

    def wait_heartbeat(self) -> None:
        self._await(lambda: None, lambda m: m if m.get_type() == "HEARTBEAT" else None, "with a HEARTBEAT")

    def set_param(self, name: str, value: float) -> float:
        """Set `name` and return the value the vehicle now holds; ControlError with the vehicle's
        own reason when it refuses (an unknown name, a value out of range)."""
        reasons = []
        # STATUSTEXT carries 50 characters: a 15- or 16-character name arrives cut short
        unknown = f"Param set failed: unknown parameter {name}"[:STATUSTEXT_CHARS]

        def match(m):
            kind = m.get_type()
            if kind == "STATUSTEXT" and m.text.startswith("Param set failed"):
                reasons.append(m.text)
                if m.text == unknown:  # no PARAM_VALUE follows this one
                    return math.nan
            elif kind == "PARAM_VALUE" and m.param_id == name:
                return m.param_value
            return None
        held = self._await(lambda: self.conn.mav.param_set_send(self.system_id, 1, name.encode(), float(value), 9),
                           match, f"PARAM_SET {name}")
        wanted = struct.unpack("<f", struct.pack("<f", float(value)))[0]  # what a float32 can hold
        if held == wanted:
            return held
        if not reasons:  # the reason is announced beside the unchanged value
            deadline = time.monotonic() + REASON_WALL_S
            while not reasons and time.monotonic() < deadline:
                m = self.conn.recv_match(type="STATUSTEXT", blocking=True, timeout=0.05)
                if m is not None and m.text.startswith("Param set failed"):
                    reasons.append(m.text)
        reason = reasons[0] if reasons else f"the vehicle holds {held:g}"
        raise ControlError(f"firefly: {name} = {value:g} refused: {reason}")

    def commands(self, *commands: tuple) -> dict[int, int]:
        """Several COMMAND_LONGs ((command, *params) each, distinct commands) in one datagram, so the
        vehicle handles them in the same tick, in order: each command's MAV_RESULT. Flat out, a
        round trip between an arm and its takeoff is seconds of vehicle time, long enough for
        the auto-disarm of a vehicle armed on the ground. A retry resends only the commands
        still unanswered (a takeoff sent again to a vehicle in the air would be refused)."""
        mav = self.conn.mav
        results: dict[int, int] = {}

        def send():
            frames = []
            for command, *params in commands:
                if command in results:
                    continue
                msg = mav.command_long_encode(self.system_id, 1, command, 0, *(list(params) + [0.0] * 7)[:7])
                frames.append(msg.pack(mav))
                mav.seq = (mav.seq + 1) % 256
            self.conn.write(b"".join(frames))

        def match(m):
            if m.get_type() == "COMMAND_ACK" and any(m.command == c for c, *_ in commands):
                results.setdefault(m.command, m.result)
                if len(results) == len(commands):
                    return dict(results)
            return None
        return self._await(send, match, "commands " + ", ".join(str(c) for c, *_ in commands))

    def command(self, command: int, *params: float) -> None:
        """COMMAND_LONG, which must be ACCEPTED."""
        self.check_accepted(command, self.commands((command, *params))[command])

    def check_accepted(self, command: int, result: int) -> None:
        """ControlError unless `result` (a MAV_RESULT) is ACCEPTED."""
        if result != 0:
            raise ControlError(f"firefly: vehicle {self.system_id} refused command {command}: "
                               f"MAV_RESULT_{MAV_RESULT.get(result, result)}")

"""A pymavlink ground station for probes: it keeps the vehicle's clock, mode, arming state and
texts, and waits on conditions in vehicle time, so a probe reads the same against a vehicle run
flat out and one run at 10x.

Vehicle time is the largest time_boot_ms seen in any message; both ArduCopter and Firefly stamp
ATTITUDE, GLOBAL_POSITION_INT and SYSTEM_TIME with it. Wall-clock limits are only a safety net for
a vehicle that stops talking.
"""
from __future__ import annotations

import math
import time
from contextlib import contextmanager

from pymavlink import mavutil

mav = mavutil.mavlink
PUMP_BATCH = 500  # messages read at most per pump()
WALL_LIMIT_S = 120.0  # a vehicle that says nothing for this long has failed the probe
GCS_HEARTBEAT_S = 0.5  # wall seconds between our heartbeats (a ground station sends 1 Hz)


class ProbeTimeout(RuntimeError):
    pass


class VehicleSilent(ProbeTimeout):
    """The vehicle's clock stopped: it died or stopped sending (see Client.stall_s)."""


class Client:
    def __init__(self, url: str, streams_hz: int | None = 10):
        self.url = url
        self.conn = mavutil.mavlink_connection(url, source_system=255, source_component=190,
                                               autoreconnect=True)
        self.now_ms = 0           # vehicle time
        self.mode = None          # custom_mode of the last HEARTBEAT
        self.armed = False
        self.system_status = None
        self.base_mode = 0
        self.texts: list[tuple[int, int, str]] = []   # (time_boot_ms, severity, text)
        self.last: dict[str, object] = {}              # last message of each type
        self.log: list[tuple[int, object]] = []        # (time_boot_ms, msg) while logging
        self.logging = False
        self.acks: list[object] = []
        self.received: dict[str, int] = {}  # messages of each type so far, to wait for one sent after a moment
        self.listeners: list = []  # callables given every message from the vehicle (protocol exchanges)
        self._last_hb_sent = 0.0
        # With stall_s set (a probe that expects a vehicle may die), a wait ends with
        # VehicleSilent once vehicle time has not moved for that many wall seconds.
        self.stall_s: float | None = None
        self._clock_moved_wall = time.monotonic()
        self.wait(lambda: self.mode is not None, 60, what="first HEARTBEAT")
        if streams_hz:  # ArduCopter streams nothing on a link until asked, as MAVProxy asks
            self.request_streams(streams_hz)
            self.wait(lambda: "ATTITUDE" in self.last, 60, what="requested streams")

    # ----- receiving -----------------------------------------------------------------------------
    def pump(self, block_s: float = 0.02, until=None) -> None:
        """Read what the vehicle sent, a batch at a time; with `until`, stop at the message that
        makes it hold (see wait's `exact`)."""
        wall = time.monotonic()
        if wall - self._last_hb_sent > GCS_HEARTBEAT_S:
            self.conn.mav.heartbeat_send(mav.MAV_TYPE_GCS, mav.MAV_AUTOPILOT_INVALID, 0, 0, 0)
            self._last_hb_sent = wall
        msg = self.conn.recv_match(blocking=True, timeout=block_s)
        taken = 0
        while msg is not None:
            self._take(msg)
            if until is not None and until():
                break
            taken += 1
            if taken == PUMP_BATCH:  # a vehicle streaming faster than a loaded machine reads would
                break                # keep this loop going: no wait would look at its condition
            msg = self.conn.recv_match(blocking=False)

    def _take(self, msg) -> None:
        kind = msg.get_type()
        if kind == "BAD_DATA" or msg.get_srcSystem() != 1 or msg.get_srcComponent() != 1:
            return
        stamp = getattr(msg, "time_boot_ms", None)
        if stamp is not None and stamp > self.now_ms and kind != "TIMESYNC":
            self.now_ms = stamp
            self._clock_moved_wall = time.monotonic()
        self.last[kind] = msg
        self.received[kind] = self.received.get(kind, 0) + 1
        if self.logging:
            self.log.append((self.now_ms, msg))
        if kind == "HEARTBEAT":
            self.mode = msg.custom_mode
            self.base_mode = msg.base_mode
            self.armed = bool(msg.base_mode & mav.MAV_MODE_FLAG_SAFETY_ARMED)
            self.system_status = msg.system_status
        elif kind == "STATUSTEXT":
            self.texts.append((self.now_ms, msg.severity, msg.text))
        elif kind == "COMMAND_ACK":
            self.acks.append(msg)
        for listener in self.listeners:
            listener(msg)

    @contextmanager
    def listening(self, listener):
        """`listener(msg)` sees every message from the vehicle inside the block: for a protocol
        exchange (mission transfer, FTP) that answers messages as they come."""
        self.listeners.append(listener)
        try:
            yield
        finally:
            self.listeners.remove(listener)

    def wait(self, condition, sim_s: float, what: str = "condition", exact: bool = False) -> float:
        """Pump until condition() holds; returns the vehicle seconds it took. ProbeTimeout after
        `sim_s` vehicle seconds (or a wall-clock safety limit). `exact` stops reading at the
        message that makes it hold, for a probe whose windows are cut at its waits: a batch read
        past it on a loaded machine ends the window seconds of vehicle time late at speedup 20.
        Otherwise the wait reads what has come (the clock is then as fresh as it can be when the
        probe sends its next command and times what follows from now_ms)."""
        start_ms, wall0 = self.now_ms, time.monotonic()
        while not condition():
            if self.now_ms - start_ms > sim_s * 1000:
                raise ProbeTimeout(f"no {what} within {sim_s:g} s of vehicle time")
            if time.monotonic() - wall0 > WALL_LIMIT_S:
                raise ProbeTimeout(f"no {what} within {WALL_LIMIT_S:g} s of wall time "
                                   f"({(self.now_ms - start_ms) / 1000:g} s of vehicle time)")
            if self.stall_s is not None and time.monotonic() - self._clock_moved_wall > self.stall_s:
                raise VehicleSilent(f"no {what}: vehicle time stood still for {self.stall_s:g} s of wall time")
            self.pump(until=condition if exact else None)
        return (self.now_ms - start_ms) / 1000.0

    def try_wait(self, condition, sim_s: float) -> bool:
        try:
            self.wait(condition, sim_s)
            return True
        except ProbeTimeout:
            return False

    def idle(self, sim_s: float, exact: bool = False) -> None:
        """Let `sim_s` of vehicle time pass."""
        end = self.now_ms + sim_s * 1000
        self.wait(lambda: self.now_ms >= end, sim_s + 5, what="vehicle time", exact=exact)

    # ----- sending -----------------------------------------------------------------------------
    def command(self, command: int, *params: float, sim_s: float = 5.0) -> int | None:
        """COMMAND_LONG; the ACK's result, or None when none came within `sim_s`."""
        p = (list(params) + [0.0] * 7)[:7]
        self.acks.clear()
        self.conn.mav.command_long_send(1, 1, command, 0, *p)
        return self._ack_result(command, sim_s)

    def command_int(self, command: int, frame: int, p1=0.0, p2=0.0, p3=0.0, p4=0.0, x=0, y=0, z=0.0,
                    sim_s: float = 5.0) -> int | None:
        self.acks.clear()
        self.conn.mav.command_int_send(1, 1, frame, command, 0, 0, p1, p2, p3, p4, x, y, z)
        return self._ack_result(command, sim_s)

    def _ack_result(self, command: int, sim_s: float) -> int | None:
        found = []

        def acked():
            found.extend(a for a in self.acks if a.command == command)
            self.acks.clear()
            return bool(found)
        return found[0].result if self.try_wait(acked, sim_s) else None

    def set_mode(self, mode: int) -> int | None:
        return self.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, mode)

    def set_param(self, name: str, value: float, sim_s: float = 5.0) -> bool:
        self.conn.mav.param_set_send(1, 1, name.encode(), value, mav.MAV_PARAM_TYPE_REAL32)

        def echoed():
            m = self.last.get("PARAM_VALUE")
            return m is not None and m.param_id == name and math.isclose(m.param_value, value, abs_tol=1e-4)
        self.last.pop("PARAM_VALUE", None)
        return self.try_wait(echoed, sim_s)

    def request_streams(self, hz: int = 10) -> None:
        self.conn.mav.request_data_stream_send(1, 1, mav.MAV_DATA_STREAM_ALL, hz, 1)

    # ----- state -------------------------------------------------------------------------------
    def fresh_heartbeat(self, sim_s: float = 3.0, exact: bool = False) -> None:
        """Wait for a HEARTBEAT sent from now on: at 1 Hz the last one can predate a change made
        a second ago (the beat may fall in the same tick as the end of the wait), so mode and
        arming read after this are the vehicle's present state on both vehicles."""
        self.fresh("HEARTBEAT", sim_s, exact)

    def fresh(self, kind: str, sim_s: float = 3.0, exact: bool = False) -> None:
        """Wait for a message of `kind` sent from now on (see fresh_heartbeat)."""
        seen = self.received.get(kind, 0)
        self.wait(lambda: self.received.get(kind, 0) > seen, sim_s, what=f"a new {kind}", exact=exact)

    def texts_since(self, t_ms: int, within_s: float | None = None) -> list[str]:
        """Texts stamped at or after vehicle time t_ms (and, with within_s, no later than that
        after it: a client that fell behind reads past the end of its wait in one go)."""
        end = math.inf if within_s is None else t_ms + within_s * 1000
        return [text for stamp, _, text in self.texts if t_ms <= stamp <= end]

    def rel_alt_m(self) -> float:
        m = self.last.get("GLOBAL_POSITION_INT")
        return m.relative_alt / 1000.0 if m else 0.0

    def close(self) -> None:
        self.conn.close()

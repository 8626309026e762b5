"""The vehicle loop: advance sim time, exchange MAVLink, pace against wall time.

Wall time enters only here: with a finite speedup the loop waits (on the sockets) until wall
time catches up with sim time / speedup; with speedup = inf it never waits. Each exchange reads
the wall clock and hands it to every vehicle's sans-IO link (the signing timestamp follows it) and
session (the link clock its failsafes and retries run on). Incoming messages are applied between
sim ticks, at the sim time they are read: datagrams from the socket go through the link, which
judges each message just before the session handles it, so that a SETUP_SIGNING takes effect for
the very next frame.
"""
from __future__ import annotations

import math
import select
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, TextIO

from .shared_air import SharedAir
from .state_log import state_line

if TYPE_CHECKING:
    from ..dataflash.recorder import Recorder
    from ..mavlink.link import Link
    from ..mavlink.routing import Router
    from ..mavlink.session import Session
    from ..vehicle import Vehicle
    from .dataflash_files import LogFiles
    from .ports import Ports
    from .tlog import TlogWriter

MAX_LAG_WALL_S = 0.5  # if the sim falls further behind than this, pacing restarts from now
READ_EVERY_WALL_S = 0.0002  # flat out, sockets are read this often (wall): a command waits no longer
# Flat out, the rest of the queued telemetry leaves this often (wall); a full datagram
# (MAX_DATAGRAM) leaves at once, and answers to a client too. Far fewer part-filled datagrams than
# every 0.2 ms: a client saw 969x instead of 909x at 1 ms (medians of five, alternated), and a
# MAVSDK flight flat out took 0.27 s against 0.28 s at 0.2 ms (medians of eight).
FLUSH_EVERY_WALL_S = 0.002
SWARM_MIN_VEHICLES = 10  # from this many vehicles in one process, a finite speedup ticks in batches
SWARM_BATCH_TICKS = 5  # ticks per batch (sim time leads wall by up to 50 ms at 1x)
STATE_LOG_EVERY = 10  # ticks (0.1 s of sim time)


def incoming(datagrams: list, link, answer):
    """(message, link key) for each message of `datagrams` ((bytes, link key) pairs) that gets
    through `link`, judged when drawn; `answer(key)` once for a datagram of which the link found a
    message may be answered (also when a link fault then lost it)."""
    for data, sender in datagrams:
        for msg, _ in link.receive(data, sender):
            yield msg, sender
        if link.sender_answerable:
            answer(sender)


@dataclass
class Node:
    vehicle: Vehicle
    session: Session
    endpoint: Ports  # the vehicle's serial ports: its sockets and who they answer
    link: Link  # (autopilot/mavlink/link.py): decodes, judges and packs, between the two
    router: Router  # (autopilot/mavlink/routing.py): which messages go on to the other links
    tlog: TlogWriter | None = None
    state_log: TextIO | None = None  # open text file (state_log.py): a line every STATE_LOG_EVERY ticks, or None
    dataflash: Recorder | None = None  # the dataflash log's recorder, told of each tick, or None
    log_files: LogFiles | None = None  # its files (the recorder's sink), flushed every STATE_LOG_EVERY ticks
    # builds the vehicle and session again from the saved state: power_on(epoch_us=, powered_on_at_s=)
    power_on: Callable[..., tuple] | None = None
    reboots: int = 0

    def reboot(self) -> None:
        """Boot the vehicle again in place (io/reboot.py); without power_on, it just carries on."""
        self.vehicle.reboot_requested = False
        if self.power_on is not None:
            from .reboot import reboot
            reboot(self)

    @property
    def link_faults(self):
        """The link's LinkFaults (SIM_LINK_*), or None."""
        return self.link.faults


class Runner:
    def __init__(self, nodes: list[Node], speedup: float, tick_s: float = 0.01):
        if not (speedup > 0):
            raise ValueError("speedup must be positive")
        self.nodes = nodes
        self.air = SharedAir(nodes) if len(nodes) > 1 else None  # the vehicles hear each other's positions
        self.speedup = speedup
        self.tick_s = tick_s
        self.sim_time_s = 0.0
        self._fds: list[int] = []  # raw descriptors: select need not ask each endpoint
        self._endpoint_of: dict = {}
        self._fds_version = -1
        self._stop = False
        self.ticks = 0
        # At a finite speedup a swarm's loop sleeps between ticks, and each tick then finds its
        # vehicles' memory colder: ticking each vehicle several times in a row, then sleeping
        # longer, costs less (3-5 % on one machine, a quarter or more on another with colder
        # caches: docs/performance.md). Sim time then leads wall time by up to the batch; a
        # message is handled and answered within a batch's work (a few ms).
        self.batch_ticks = SWARM_BATCH_TICKS if (speedup != math.inf and len(nodes) >= SWARM_MIN_VEHICLES) else 1

    def stop(self) -> None:
        self._stop = True

    def _exchange(self, readable=None, nodes=None) -> bool:
        """The MAVLink exchange of every vehicle (or of `nodes`); only the sockets in `readable`
        are read (None: all). Whether anything was read (its answers should leave at once)."""
        heard = False
        nodes = self.nodes if nodes is None else nodes
        unix_s, link_s = time.time(), time.monotonic()  # one reading for every vehicle of this exchange
        if readable is None and len(nodes) > 1:  # one system call says which of them to read
            readable = self._readable(0.0)
        for node in nodes:
            try:  # costs nothing until it catches (CPython 3.11)
                now = node.vehicle.time_s
                session, link, endpoint = node.session, node.link, node.endpoint
                unread = readable is not None and endpoint not in readable
                if unread and session.idle(now, link_s):  # most ticks, flat out or in a swarm
                    continue
                link.advance(unix_s, link_s)
                datagrams = () if unread else endpoint.receive()
                received: Sequence[Any] = ()
                replies: dict = {}
                forwards: dict = {}
                if datagrams:  # most ticks have none
                    heard = True
                    got: list[Any] = []
                    route = node.router.route
                    # each message is judged only after the one before it was handled
                    for msg, key in incoming(datagrams, link, endpoint.answer):
                        got.append(msg)
                        if msg.get_type() != "BAD_DATA":
                            local, onward = route(msg, key)
                            if onward:
                                frame = bytes(msg.get_msgbuf())
                                for to in onward:
                                    forwards.setdefault(to, []).append(frame)
                                if not local:  # for a component served on another link
                                    continue
                        answer = session.receive(msg, now, link_s, key)
                        if answer:
                            replies.setdefault(key, []).extend(answer)
                    received = got
                if endpoint.closed:  # a TCP client went: its routes and numbering go too
                    for key in endpoint.take_closed():
                        node.router.forget(key)
                        link.forget(key)
                if replies and node.state_log is not None:
                    # the true state as it is when the answer leaves: a harness reading the state
                    # log after an ACK never finds a state older than the ACK (what it changed)
                    node.state_log.write(state_line(node.vehicle))  # line buffered: on disk now
                out = session.poll(now, link_s)
                if out and self.air is not None:
                    self.air.broadcast(node, out)
                directed, announced = session.take_directed(), session.take_announced()
                sent = self._send(node, out, replies, directed, announced, forwards)
                if node.tlog is not None:
                    self._log(node, received, sent)
                if node.vehicle.reboot_requested:  # its ACK is queued: now it boots again
                    node.reboot()
            except Exception as exc:  # noqa: BLE001 - one vehicle's bug never takes the others down
                node.vehicle.internal_error(exc, "exchange", in_flight_code=False)
        return heard

    @staticmethod
    def _send(node: Node, out: list, replies: dict, directed: dict | None, announced: list | None,
              forwards: dict) -> list:
        """Pack and queue for each link: its answers, what was made for it alone, parameter values
        another link set if it has spoken, what is due for every link, then others' messages routed to it.
        Returns the frames the tlog keeps: the shared output once, the rest for every link."""
        endpoint, link = node.endpoint, node.link
        if not (replies or directed or announced or forwards):  # most exchanges: telemetry alone
            logged = []
            for n, key in enumerate(endpoint.links if out else ()):
                frames = link.pack(out, key)
                if n == 0:
                    logged = frames
                if frames:
                    endpoint.queue(key, frames)
            return logged
        logged = []
        for n, key in enumerate(endpoint.links):
            own = replies.get(key)
            if directed and key in directed:
                own = (own or []) + directed[key]
            if announced and endpoint.heard(key):
                own = (own or []) + [m for asker, m in announced if asker != key]
            frames = link.pack(own, key) if own else []
            logged += frames
            if out:
                shared = link.pack(out, key)
                if n == 0:
                    logged += shared
                frames += shared
            if forwards and key in forwards:
                frames += forwards[key]
            if frames:
                endpoint.queue(key, frames)  # sent at the next flush (see run())
        return logged

    @staticmethod
    def _log(node: Node, received: Sequence[Any], sent: list) -> None:
        tlog = node.tlog
        if tlog is None:
            return
        stamp = node.vehicle.unix_time_us()
        for msg in received:
            if msg.get_type() != "BAD_DATA":
                tlog.write(stamp, bytes(msg.get_msgbuf()))
        for frame in sent:
            tlog.write(stamp, frame)
        tlog.maybe_flush()

    def _advance(self) -> None:
        self.ticks += 1
        self.sim_time_s = self.ticks * self.tick_s  # counted, not summed: 0.01 added 500 times is not 5.0
        target = self.sim_time_s
        for node in self.nodes:
            try:  # a bug that escapes the vehicle's own guards: its internal error, the rest go on
                node.vehicle.run_until(target)
                if node.dataflash is not None:
                    node.dataflash.tick()
            except Exception as exc:  # noqa: BLE001
                node.vehicle.internal_error(exc, "step")
        if self.ticks % STATE_LOG_EVERY == 0:
            for node in self.nodes:
                if node.state_log is not None:
                    node.state_log.write(state_line(node.vehicle))
                if node.log_files is not None:
                    node.log_files.maybe_flush()

    def _batch(self, ticks: int) -> None:
        """`ticks` ticks of every vehicle, one vehicle after another: each vehicle's exchange and
        step as _exchange and _advance would make them tick by tick (the vehicles share nothing,
        so the order between them changes no trajectory), its socket read at the first."""
        readable = self._readable(0.0)
        first = self.ticks
        for node in self.nodes:
            state_log, one = node.state_log, (node,)
            for tick in range(first + 1, first + ticks + 1):
                self._exchange(readable if tick == first + 1 else (), one)
                vehicle, dataflash = node.vehicle, node.dataflash  # new ones after a reboot
                try:
                    vehicle.run_until(tick * self.tick_s)
                    if dataflash is not None:
                        dataflash.tick()
                except Exception as exc:  # noqa: BLE001 - as in _advance
                    vehicle.internal_error(exc, "step")
                if state_log is not None and tick % STATE_LOG_EVERY == 0:
                    state_log.write(state_line(vehicle))
            if node.log_files is not None:
                node.log_files.maybe_flush()
        self.ticks = first + ticks
        self.sim_time_s = self.ticks * self.tick_s

    def _batch_ticks(self, duration_s: float) -> int:
        """How many ticks a swarm's batch runs: self.batch_ticks, never past duration_s."""
        left = round((duration_s - self.sim_time_s) / self.tick_s) if duration_s < math.inf else self.batch_ticks
        return max(1, min(self.batch_ticks, left))

    def _readable(self, wait_s: float) -> set:
        """The endpoints with something to read, waiting up to wait_s for one."""
        version = sum(n.endpoint.version for n in self.nodes)  # a TCP client came or went
        if version != self._fds_version:
            self._fds_version = version
            self._endpoint_of = {fd: n.endpoint for n in self.nodes for fd in n.endpoint.filenos()}
            self._fds = list(self._endpoint_of)
        ready, _, _ = select.select(self._fds, [], [], wait_s)
        by_fd = self._endpoint_of
        return {by_fd[fd] for fd in ready}

    def _flush(self) -> None:
        for node in self.nodes:
            node.endpoint.flush()

    def run(self, duration_s: float = math.inf) -> None:
        wall0 = time.monotonic()
        sim0 = self.sim_time_s
        read = None  # the sockets the next exchange reads: None all, () none (known quiet)
        last_read_wall = last_flush_wall = -math.inf
        while not self._stop and self.sim_time_s < duration_s - 1e-9:
            # Reading a socket that holds nothing and sending a datagram per tick cost more than
            # the telemetry itself when ticks are microseconds of wall time apart: unless a wait
            # on the sockets said what is readable, they are read at most every READ_EVERY_WALL_S,
            # and frames go out every FLUSH_EVERY_WALL_S, or as soon as a datagram is full, or
            # before a wait, or at once when a client has just been heard (its answer is among them).
            wall = time.monotonic()
            if read is None:
                if wall - last_read_wall < READ_EVERY_WALL_S:
                    read = ()
                else:
                    last_read_wall = wall
            if self.air is not None:
                self.air.refresh()
            if self.batch_ticks > 1:  # a swarm at a finite speedup
                self._batch(self._batch_ticks(duration_s))
                self._flush()
            else:
                heard = self._exchange(read)
                self._advance()
                if heard or wall - last_flush_wall >= FLUSH_EVERY_WALL_S:  # a client waits for its answer
                    self._flush()
                    last_flush_wall = wall
            read = None
            if self.speedup == math.inf:
                continue
            while not self._stop:
                wait = wall0 + (self.sim_time_s - sim0) / self.speedup - time.monotonic()
                if wait < -MAX_LAG_WALL_S:
                    wall0, sim0 = time.monotonic(), self.sim_time_s
                if wait <= 0:
                    break
                self._flush()
                readable = self._readable(wait)
                if readable:  # answer at once; sim time does not move until wall time allows
                    self._exchange(readable)
                    self._flush()
                else:
                    read = ()  # the wait ended with nothing to read
        self._exchange()
        self._flush()

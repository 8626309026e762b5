"""One simulated vehicle as a test holds it: its URLs, its clients, its true state, waits in its time.

Each vehicle sends to three ports of the test's own (autopilot --out): one for MAVSDK, one for
pymavlink or MAVProxy, one for the plugin's control link, so a test may use MAVSDK and pymavlink
at once and neither sees the other's replies.
"""
from __future__ import annotations

import asyncio
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..instances import system_id_of
from ..params import INVERSE_OLD_NAMES, served_equivalent
from .control import ControlLink
from .errors import FireflyError
from .state import StateLogReader, VehicleState

if TYPE_CHECKING:
    from .mavlink_client import QueuedUdpConnection  # imports pymavlink: only when a test asks for it

POLL_WALL_S = 0.005  # how often a wait looks at the state log
STALL_WALL_S = 30.0  # a wait fails if vehicle time stands still this long (the process hung)
CONNECT_WALL_S = 10.0
ARMABLE_WITHIN_S = 90.0  # vehicle seconds from the ready-state request; a realistic start-up needs ~42


class Wait:
    """One wait on the state log: the first state, from now on, for which `condition` holds, or
    FireflyError once `timeout_s` of vehicle time has passed without it."""

    def __init__(self, vehicle: "FireflyVehicle", condition, timeout_s: float, what: str):
        if not timeout_s > 0:
            raise ValueError(f"timeout must be positive vehicle seconds, got {timeout_s!r}")
        self.vehicle, self.condition, self.timeout_s, self.what = vehicle, condition, timeout_s, what
        self.reader = StateLogReader(vehicle.state_log_path, from_end=True)
        self.start_s = vehicle.state().time_s
        self.last: VehicleState | None = None
        self.moved_wall = time.monotonic()

    def poll(self) -> VehicleState | None:
        """The state that ends the wait, or None to keep waiting."""
        states = self.reader.new_states()
        for state in states:
            self.last = state
            if self.condition(state):
                self.reader.close()
                return state
            if state.time_s - self.start_s > self.timeout_s:
                self.reader.close()
                raise FireflyError(f"firefly: vehicle {self.vehicle.system_id}: timed out after {self.timeout_s:g} s "
                                   f"of vehicle time waiting for {self.what}; last state: {state}")
        now = time.monotonic()
        if states:
            self.moved_wall = now
            return None
        self.vehicle.check_alive()
        if now - self.moved_wall > STALL_WALL_S:
            self.reader.close()
            raise FireflyError(f"firefly: vehicle {self.vehicle.system_id}: vehicle time stood still for "
                               f"{STALL_WALL_S:g} s of wall time while waiting for {self.what}")
        return None


class FireflyVehicle:
    """A vehicle of a running autopilot process (see FireflyRun)."""

    def __init__(self, run, index: int, ports: dict, state_log: Path, tlog: Path):
        self.run = run
        self.index = index
        self.system_id = system_id_of(index)  # from 1 again past 255: each part of a fleet its own network
        self.ports = ports  # {"mavsdk": port, "mavlink": port, "control": port}
        self.state_log_path = state_log
        self.tlog_path = tlog
        self._state = StateLogReader(state_log)
        self._control: ControlLink | None = None
        self._mavsdk: tuple[Any, Any] | None = None  # (Mavsdk, System)
        self._mavlink: QueuedUdpConnection | None = None

    # ----- where clients connect ------------------------------------------------------------
    @property
    def mavsdk_url(self) -> str:
        """For MAVSDK, native (`add_any_connection`) or gRPC (`System().connect(system_address=...)`)."""
        return f"udpin://127.0.0.1:{self.ports['mavsdk']}"

    @property
    def mavlink_url(self) -> str:
        """For pymavlink (`mavutil.mavlink_connection`) and MAVProxy (`--master`)."""
        return f"udpin:127.0.0.1:{self.ports['mavlink']}"

    @property
    def seed(self) -> int:
        return self.run.settings.seed + self.index  # as the autopilot seeds vehicle k of a process

    # ----- ready-made clients -------------------------------------------------------------
    async def mavsdk(self, timeout_s: float = CONNECT_WALL_S):
        """A MAVSDK (native 4.x) `System` connected to this vehicle; the same one on every call,
        destroyed after the test."""
        if self._mavsdk is None:
            from mavsdk.asyncio import ComponentType, Configuration, Mavsdk
            instance = Mavsdk(Configuration.create_with_component_type(ComponentType.GROUND_STATION))
            try:
                await instance.add_any_connection(self.mavsdk_url)
                system = await instance.first_autopilot(timeout_s=timeout_s)
                if system is None:
                    self.check_alive()
                    raise FireflyError(f"firefly: vehicle {self.system_id} was not seen by MAVSDK on "
                                       f"{self.mavsdk_url} within {timeout_s:g} s")
            except BaseException:  # not kept: the next call tries afresh
                instance.destroy()
                raise
            self._mavsdk = (instance, system)
        return self._mavsdk[1]

    def mavlink(self, timeout_s: float = CONNECT_WALL_S):
        """A pymavlink connection (system 255, ardupilotmega dialect) that has seen this
        vehicle's HEARTBEAT; the same one on every call, closed after the test. A thread of its
        own reads the socket as datagrams arrive, so nothing is lost while the test does
        something else (mavlink_client.py)."""
        if self._mavlink is None:
            from .mavlink_client import queued_connection
            connection = queued_connection(self.mavlink_url, source_system=255)
            try:
                deadline = time.monotonic() + timeout_s
                while connection.recv_match(type="HEARTBEAT", blocking=True, timeout=0.1) is None:
                    self.check_alive()
                    if time.monotonic() > deadline:
                        raise FireflyError(f"firefly: no HEARTBEAT from vehicle {self.system_id} on "
                                           f"{self.mavlink_url} within {timeout_s:g} s")
            except BaseException:  # not kept: the next call tries afresh
                connection.close()
                raise
            self._mavlink = connection
        return self._mavlink

    # ----- the true state and waits in vehicle time ----------------------------------------
    def state(self) -> VehicleState:
        """The vehicle's newest true state: the state log's last complete line, read at each call.
        The vehicle writes one every 0.1 s of vehicle time and one for the moment of each answer
        it sends a client, before sending it, so this is never older than a reply received."""
        state = self._state.latest_state()
        if state is None:
            self.check_alive()
            raise FireflyError(f"firefly: vehicle {self.system_id} has written no state yet")
        return state

    def wait_until(self, condition, timeout: float, what: str | None = None) -> VehicleState:
        """Block until `condition(state)` holds for a state from now on; `timeout` is in seconds of
        vehicle time. For synchronous tests (an async test uses wait_until_async)."""
        wait = Wait(self, condition, timeout, what or _describe(condition))
        while (state := wait.poll()) is None:
            time.sleep(POLL_WALL_S)
        return state

    async def wait_until_async(self, condition, timeout: float, what: str | None = None) -> VehicleState:
        """wait_until for async tests: the event loop (and MAVSDK) runs while it waits."""
        wait = Wait(self, condition, timeout, what or _describe(condition))
        while (state := wait.poll()) is None:
            await asyncio.sleep(POLL_WALL_S)
        return state

    def sleep(self, seconds: float) -> VehicleState:
        """Let `seconds` of vehicle time pass."""
        end = self.state().time_s + seconds
        return self.wait_until(lambda s: s.time_s >= end - 1e-9, seconds + 1.0, f"t = {end:g} s")

    async def sleep_async(self, seconds: float) -> VehicleState:
        end = self.state().time_s + seconds
        return await self.wait_until_async(lambda s: s.time_s >= end - 1e-9, seconds + 1.0, f"t = {end:g} s")

    # ----- acting on the vehicle from the side ---------------------------------------------
    def set_param(self, name: str, value: float) -> float:
        """Set a parameter (a SIM_* fault among them) now, over the plugin's own link; returns the
        value held, FireflyError with the vehicle's reason if it refuses. ArduPilot 4.5's names,
        which the vehicle does not serve, are set as their 4.7 equivalents (params.served_equivalent)."""
        served, served_value = served_equivalent(name, value)
        held = self.control().set_param(served, served_value)
        return float(not held) if name in INVERSE_OLD_NAMES else held

    def control(self) -> ControlLink:
        if self._control is None:
            link = ControlLink(self.ports["control"], self.system_id, self.check_alive)
            try:
                link.wait_heartbeat()
            except BaseException:
                link.close()
                raise
            self._control = link
        return self._control

    def take_off(self, height_m: float, timeout: float = 120.0) -> VehicleState:
        """GUIDED, arm, take off to `height_m` and wait (in vehicle time) until it hovers there."""
        link = self.control()
        # A realistic start-up refuses GUIDED and ARM until its position is good (ArduCopter's
        # ~42 s): ask again each vehicle second until it is armable or ARMABLE_WITHIN_S has passed.
        # The three go in one datagram: flat out, a round trip after the arm is long enough in
        # vehicle time for the auto-disarm of a vehicle left on the ground.
        give_up_s = self.state().time_s + ARMABLE_WITHIN_S
        while True:
            # DO_SET_MODE custom mode GUIDED, arm, NAV_TAKEOFF
            results = link.commands((176, 1, 4), (400, 1), (22, 0, 0, 0, 0, 0, 0, height_m))
            if results[176] == 0 and results[400] == 0 or self.state().time_s >= give_up_s:
                break
            self.sleep(1.0)
        for command in (176, 400, 22):
            link.check_accepted(command, results[command])
        return self.wait_until(lambda s: abs(s.altitude_m - height_m) < 0.3 and abs(s.velocity_ned_m_s[2]) < 0.2,
                               timeout, f"a hover at {height_m:g} m after takeoff")

    def check_alive(self) -> None:
        self.run.check_alive()

    def close(self) -> None:
        self._state.close()
        if self._control is not None:
            self._control.close()
            self._control = None
        if self._mavlink is not None:
            self._mavlink.close()
            self._mavlink = None
        if self._mavsdk is not None:
            self._mavsdk[0].destroy()
            self._mavsdk = None

    def __repr__(self) -> str:
        return f"<FireflyVehicle system {self.system_id} {self.mavsdk_url}>"


def _describe(condition) -> str:
    name = getattr(condition, "__name__", "")
    return "the condition" if name in ("", "<lambda>") else name

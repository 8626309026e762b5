"""The flight most existing MAVSDK-Python scripts fly, with the gRPC API (`mavsdk_grpc`):
System() starts its bundled mavsdk_server, connect, wait for connection and health, arm, take off
to 10 m, go 30 m north, return to launch, disarm at home. And a float parameter round trip.

Every await on a stream or an RPC is bounded by asyncio.wait_for, and the mavsdk_server child is
killed and reaped whatever happens.
"""
from __future__ import annotations

import asyncio
import math
import socket
import time

import pytest
from mavsdk_grpc import System

from .conftest import free_udp_port
from .pymav import Gcs

pytestmark = [
    pytest.mark.sitl,
    # mavsdk_grpc's own use of importlib.resources.path, nothing this test can change
    pytest.mark.filterwarnings("ignore:path is deprecated:DeprecationWarning"),
]

M_PER_DEG_LAT = 111_320.0


def free_tcp_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def north_east_m(pos, home) -> tuple:
    n = (pos.latitude_deg - home.latitude_deg) * M_PER_DEG_LAT
    e = (pos.longitude_deg - home.longitude_deg) * M_PER_DEG_LAT * math.cos(math.radians(home.latitude_deg))
    return n, e


async def first(stream, condition, timeout: float, what: str):
    """First item of a mavsdk_grpc stream satisfying `condition`, or fail after `timeout` s.

    The async generator is closed afterwards, which cancels its gRPC subscription."""
    async def scan():
        async for item in stream:
            if condition(item):
                return item
        raise AssertionError(f"stream ended while waiting for {what}")
    try:
        return await asyncio.wait_for(scan(), timeout)
    except asyncio.TimeoutError:
        raise AssertionError(f"timed out after {timeout:g} s waiting for {what}") from None
    finally:
        await stream.aclose()


async def call(awaitable, timeout: float = 10.0):
    """One RPC (action, param), bounded in time."""
    return await asyncio.wait_for(awaitable, timeout)


def stop_mavsdk_server(drone: System) -> None:
    """mavsdk_grpc's own cleanup (System._stop_mavsdk_server) SIGKILLs mavsdk_server but never
    waits for it; reap it here so no zombie or port is left behind."""
    proc = drone._server_process
    drone._stop_mavsdk_server()
    if proc is not None:
        proc.wait(timeout=10)
        assert proc.returncode is not None


async def connected_system(url: str):
    """A connected mavsdk_grpc System on its own gRPC port (parallel runs never share 50051);
    yields it, then stops its mavsdk_server."""
    system = System(port=free_tcp_port())
    try:
        await asyncio.wait_for(system.connect(system_address=url), 20)
        await first(system.core.connection_state(), lambda s: s.is_connected, 20, "is_connected")
        yield system
    finally:
        stop_mavsdk_server(system)


@pytest.fixture
async def drone(autopilot):
    async for system in connected_system(autopilot.mavsdk_url):
        yield system


@pytest.fixture
def observed_autopilot(autopilot_factory):
    """The autopilot with a second --out port, where a pymavlink Gcs can check it independently."""
    port = free_udp_port()
    return autopilot_factory(extra=("--out", f"udp:127.0.0.1:{port}")), port


@pytest.fixture
async def observed_drone(observed_autopilot):
    ap, port = observed_autopilot
    gcs = Gcs(f"udpin:127.0.0.1:{port}", timeout=15)
    try:
        async for system in connected_system(ap.mavsdk_url):
            yield system, gcs
    finally:
        gcs.close()


def read_param(gcs: Gcs, name: str, timeout: float = 10.0) -> float:
    """The autopilot's current value of `name`: what is already queued on the socket (telemetry,
    the PARAM_VALUEs MAVSDK fetched) is drained first, then PARAM_REQUEST_READ is re-sent every
    0.5 s until the PARAM_VALUE for it arrives."""
    while gcs.conn.recv_match(blocking=False) is not None:
        pass
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        gcs.mav.param_request_read_send(gcs.conn.target_system, gcs.conn.target_component,
                                        name.encode(), -1)
        msg = gcs.recv("PARAM_VALUE", timeout=0.5, condition=lambda m: m.param_id == name)
        if msg is not None:
            return msg.param_value
    raise AssertionError(f"no PARAM_VALUE for {name} within {timeout:g} s")


async def wait_ready(drone: System):
    health = await first(drone.telemetry.health(),
                         lambda h: h.is_global_position_ok and h.is_home_position_ok and h.is_armable,
                         20, "global position, home position and armable")
    assert health.is_local_position_ok
    return await first(drone.telemetry.home(), lambda h: True, 10, "home position")


async def test_mavsdk_grpc_takeoff_goto_rtl(drone):
    home = await wait_ready(drone)
    assert math.isfinite(home.latitude_deg) and math.isfinite(home.absolute_altitude_m)

    await call(drone.action.arm())
    await first(drone.telemetry.armed(), bool, 10, "armed")
    await call(drone.action.set_takeoff_altitude(10.0))
    await call(drone.action.takeoff())
    at_alt = await first(drone.telemetry.position(), lambda p: p.relative_altitude_m >= 9.5, 30,
                         "relative altitude >= 9.5 m")
    assert math.hypot(*north_east_m(at_alt, home)) < 1.5, "drifted during the climb"

    target_lat = home.latitude_deg + 30.0 / M_PER_DEG_LAT
    target_alt = home.absolute_altitude_m + 10.0
    await call(drone.action.goto_location(target_lat, home.longitude_deg, target_alt, 0.0))

    def near_target(p) -> bool:
        n, e = north_east_m(p, home)
        return math.dist((n, e, p.absolute_altitude_m), (30.0, 0.0, target_alt)) < 1.5
    arrived = await first(drone.telemetry.position(), near_target, 40, "within 1.5 m of 30 m north")
    assert abs(arrived.relative_altitude_m - 10.0) < 1.5

    await call(drone.action.return_to_launch())
    await first(drone.telemetry.armed(), lambda a: not a, 60, "disarm after RTL")
    final = await first(drone.telemetry.position(), lambda p: True, 10, "position after disarm")
    assert math.hypot(*north_east_m(final, home)) < 2.0, "landed away from home"
    assert abs(final.relative_altitude_m) < 0.5
    assert not await first(drone.telemetry.in_air(), lambda a: True, 10, "in_air after landing")


async def test_mavsdk_grpc_param_float_round_trip(observed_drone):
    drone, gcs = observed_drone
    await wait_ready(drone)
    assert await call(drone.param.get_param_float("WPNAV_SPEED")) == pytest.approx(1000.0)
    await call(drone.param.set_param_float("WPNAV_SPEED", 800.0))
    assert await call(drone.param.get_param_float("WPNAV_SPEED")) == pytest.approx(800.0)
    # Not just mavsdk_server's cache: the autopilot itself now answers 800 to another client.
    assert await asyncio.to_thread(read_param, gcs, "WPNAV_SPEED") == pytest.approx(800.0)

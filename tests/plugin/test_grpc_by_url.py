"""The gRPC MAVSDK flavour (`mavsdk_grpc`, what most existing scripts use) flies the plugin's
vehicle by its URL. This test runs in this suite's own pytest session with the plugin's `firefly`
fixture and no conftest of its own: the installed plugin works in the repository's suite too."""
from __future__ import annotations

import asyncio

import pytest
from mavsdk_grpc import System

from ..sitl.test_mavsdk_grpc import first, free_tcp_port, stop_mavsdk_server

pytestmark = [
    pytest.mark.sitl,
    pytest.mark.filterwarnings("ignore:path is deprecated:DeprecationWarning"),  # mavsdk_grpc's own
]


@pytest.mark.firefly(speedup=20)
async def test_grpc_mavsdk_arms_the_plugins_vehicle_by_its_url(firefly):
    """System().connect(system_address=firefly.mavsdk_url) starts mavsdk_server on that URL; once
    it reports the connection and the vehicle armable, action.arm() arms the very vehicle whose
    true state the plugin reads (armed, still on the ground, in the boot mode). Every await is
    bounded; the mavsdk_server child is killed and reaped whatever happens."""
    drone = System(port=free_tcp_port())  # its own gRPC port: parallel sessions never share 50051
    try:
        await asyncio.wait_for(drone.connect(system_address=firefly.mavsdk_url), 20)
        await first(drone.core.connection_state(), lambda c: c.is_connected, 20, "is_connected")
        await first(drone.telemetry.health(), lambda h: h.is_armable, 20, "armable")
        assert not firefly.state().armed
        await asyncio.wait_for(drone.action.arm(), 10)
        armed = await firefly.wait_until_async(lambda s: s.armed, timeout=5, what="armed")
        assert armed.on_ground and armed.mode == "STABILIZE"
    finally:
        stop_mavsdk_server(drone)

"""The gRPC MAVSDK flavour (`mavsdk_grpc`, what most existing scripts use) flies the plugin's
vehicle by its URL, inside this suite's own pytest run: the plugin's `firefly` fixture with no
conftest, beside a client the plugin does not make."""
from __future__ import annotations

import asyncio

import pytest

from ..sitl.test_mavsdk_grpc import connected_system, first

pytestmark = [
    pytest.mark.sitl,
    pytest.mark.filterwarnings("ignore:path is deprecated:DeprecationWarning"),  # mavsdk_grpc's own
]


@pytest.mark.firefly(speedup=20)
async def test_grpc_mavsdk_arms_the_plugins_vehicle_by_url(firefly):
    async for drone in connected_system(firefly.mavsdk_url):
        await first(drone.telemetry.health(), lambda h: h.is_armable, 20, "armable")
        await asyncio.wait_for(drone.action.arm(), 10)
        armed = await firefly.wait_until_async(lambda s: s.armed, timeout=5, what="armed")
        assert armed.on_ground and armed.mode == "STABILIZE"

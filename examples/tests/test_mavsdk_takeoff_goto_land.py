"""Example: a MAVSDK (native 4.x) flight against a fresh simulated ArduCopter.

Take off to 10 m, go 30 m north, land there. Copy this file into your own project: the `firefly`
fixture comes with `pip install firefly-sitl`, no conftest needed. The waits count vehicle
seconds, so the test means the same at `--firefly-speedup 1`, 50 or inf.
"""
import asyncio
import math

from mavsdk.asyncio.plugins.action import ActionAsync
from mavsdk.asyncio.plugins.telemetry import TelemetryAsync

M_PER_DEG_LAT = 111_320.0


async def home_when_known(telemetry):
    """Home, once MAVSDK has it (before that, telemetry.home() may answer zeros)."""
    async def known():
        async for health in telemetry.subscribe_health():
            if health.is_global_position_ok and health.is_home_position_ok:
                return await telemetry.home()
    return await asyncio.wait_for(known(), timeout=10)


async def test_takeoff_goto_north_and_land(firefly):
    drone = await firefly.mavsdk()
    action, telemetry = ActionAsync(drone), TelemetryAsync(drone)
    home = await home_when_known(telemetry)

    await action.arm()
    await action.set_takeoff_altitude(10.0)
    await action.takeoff()
    await firefly.wait_until_async(lambda s: s.altitude_m > 9.5, timeout=30, what="10 m up")

    await action.goto_location(home.latitude_deg + 30.0 / M_PER_DEG_LAT, home.longitude_deg,
                               home.absolute_altitude_m + 10.0, math.nan)
    await firefly.wait_until_async(lambda s: abs(s.north_m - 30.0) < 1.0 and s.ground_speed_m_s < 0.5,
                                   timeout=60, what="a stop 30 m north")

    await action.land()
    landed = await firefly.wait_until_async(lambda s: s.landed, timeout=60, what="landed and disarmed")
    assert abs(landed.north_m - 30.0) < 2.0 and abs(landed.east_m) < 2.0
    assert landed.mode == "LAND"

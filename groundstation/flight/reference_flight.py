"""The reference flight a MAVSDK user's CI would fly, with the native MAVSDK 4.x binding: connect,
wait for armable, arm, take off to 10 m, hold, go 30 m north, RTL, land at home, disarm. It returns
what it observed on the way; tests/sitl/test_mavsdk_flight.py checks it, `make bench` times it."""
from __future__ import annotations

import math

from mavsdk.asyncio import ComponentType, Configuration, Mavsdk
from mavsdk.asyncio.plugins.action import ActionAsync
from mavsdk.asyncio.plugins.telemetry import FlightMode, LandedState, TelemetryAsync

from firefly.sim.geo import global_from_ned, ned_from_global

from .vehicle_link import LinkError, first, home_point  # first() fails (LinkError) naming what did not happen


def north_east_m(pos, home) -> tuple:
    """(n, e) metres of a MAVSDK position from MAVSDK's home."""
    return ned_from_global(home_point(home), pos.latitude_deg, pos.longitude_deg, home.absolute_altitude_m)[:2]


async def connect(url: str):
    mavsdk = Mavsdk(Configuration.create_with_component_type(ComponentType.GROUND_STATION))
    await mavsdk.add_any_connection(url)
    system = await mavsdk.first_autopilot(timeout_s=10.0)
    if system is None:
        mavsdk.destroy()
        raise LinkError(f"MAVSDK found no autopilot on {url} within 10 s")
    return mavsdk, system


async def fly_takeoff_goto_rtl(url: str, timeout_scale: float = 1.0) -> dict:
    """The reference flight; returns what it observed. Used by the test and by `make bench`."""
    t = timeout_scale
    mavsdk, system = await connect(url)
    try:
        telemetry, action = TelemetryAsync(system), ActionAsync(system)
        await first(telemetry.subscribe_health(), lambda h: h.is_armable and h.is_global_position_ok
                    and h.is_home_position_ok, 10 * t, "armable")
        home = await telemetry.home()
        await action.arm()
        await first(telemetry.subscribe_armed(), bool, 5 * t, "armed")
        await action.set_takeoff_altitude(10.0)
        await action.takeoff()
        climbing = await first(telemetry.subscribe_landed_state(),
                               lambda s: s in (LandedState.TAKING_OFF, LandedState.IN_AIR), 10 * t,
                               "landed state TAKING_OFF/IN_AIR")
        at_alt = await first(telemetry.subscribe_position(), lambda p: p.relative_altitude_m > 9.7,
                             30 * t, "10 m altitude")
        mode = await first(telemetry.subscribe_flight_mode(), lambda m: True, 5 * t, "flight mode")
        target = global_from_ned(home_point(home), 30.0, 0.0, -10.0)
        await action.goto_location(target.lat_deg, target.lon_deg, target.alt_m, float("nan"))
        arrived = await first(telemetry.subscribe_position(),
                              lambda p: math.dist(north_east_m(p, home), (30.0, 0.0)) < 1.0,
                              40 * t, "arrival 30 m north")
        velocity = await first(telemetry.subscribe_velocity_ned(), lambda v: True, 5 * t, "velocity")
        await action.return_to_launch()
        await first(telemetry.subscribe_flight_mode(), lambda m: m == FlightMode.RETURN_TO_LAUNCH,
                    5 * t, "RTL mode")
        await first(telemetry.subscribe_armed(), lambda a: not a, 120 * t, "disarm after RTL")
        final = await telemetry.position()
        landed = await first(telemetry.subscribe_landed_state(),
                             lambda s: s == LandedState.ON_GROUND, 5 * t, "on ground")
        return {"home": home, "climbing": climbing, "at_alt": at_alt, "mode": mode,
                "arrived": arrived, "velocity": velocity, "final": final, "landed": landed}
    finally:
        mavsdk.destroy()

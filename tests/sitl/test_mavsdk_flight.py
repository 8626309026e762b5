"""The flight a MAVSDK user's CI would fly, with the native MAVSDK 4.x binding:
connect, wait for armable, arm, take off to 10 m, hold, go 30 m north, RTL, land at home, disarm.
Telemetry is checked against the flight as it happens."""
from __future__ import annotations

import math

import pytest
from mavsdk.asyncio import ComponentType, Configuration, Mavsdk
from mavsdk.asyncio.plugins.action import ActionAsync
from mavsdk.asyncio.plugins.param import ParamAsync
from mavsdk.asyncio.plugins.telemetry import FlightMode, LandedState, TelemetryAsync

from groundstation.flight.vehicle_link import first  # fails (LinkError) naming what did not happen

pytestmark = pytest.mark.sitl

M_PER_DEG_LAT = 111_320.0


def north_east_m(pos, home) -> tuple:
    n = (pos.latitude_deg - home.latitude_deg) * M_PER_DEG_LAT
    e = (pos.longitude_deg - home.longitude_deg) * M_PER_DEG_LAT * math.cos(math.radians(home.latitude_deg))
    return n, e


async def connect(url: str):
    mavsdk = Mavsdk(Configuration.create_with_component_type(ComponentType.GROUND_STATION))
    await mavsdk.add_any_connection(url)
    system = await mavsdk.first_autopilot(timeout_s=10.0)
    assert system is not None, "MAVSDK found no autopilot"
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
        target_lat = home.latitude_deg + 30.0 / M_PER_DEG_LAT
        await action.goto_location(target_lat, home.longitude_deg, home.absolute_altitude_m + 10.0,
                                   float("nan"))
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


async def test_takeoff_goto_rtl_lands_at_home(autopilot):
    seen = await fly_takeoff_goto_rtl(autopilot.mavsdk_url)
    home = seen["home"]
    assert seen["mode"] == FlightMode.OFFBOARD, seen["mode"]  # MAVSDK's name for ArduCopter GUIDED
    assert abs(seen["at_alt"].absolute_altitude_m - home.absolute_altitude_m - seen["at_alt"].relative_altitude_m) < 0.05
    n, e = north_east_m(seen["arrived"], home)
    assert abs(n - 30.0) < 1.0 and abs(e) < 1.0
    assert 8.5 < seen["arrived"].relative_altitude_m < 11.5
    assert abs(seen["velocity"].down_m_s) < 2.0
    n, e = north_east_m(seen["final"], home)
    assert math.hypot(n, e) < 2.0, f"landed {math.hypot(n, e):.2f} m from home"
    assert seen["final"].relative_altitude_m < 0.3


async def test_parameter_set_and_read_back(autopilot):
    mavsdk, system = await connect(autopilot.mavsdk_url)
    try:
        param = ParamAsync(system)
        await param.set_param_float("WPNAV_SPEED", 750.0)
        assert await param.get_param_float("WPNAV_SPEED") == pytest.approx(750.0)
        await param.set_param_int("ARMING_CHECK", 0)
        assert await param.get_param_int("ARMING_CHECK") == 0
    finally:
        mavsdk.destroy()

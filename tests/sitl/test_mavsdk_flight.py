"""The flight a MAVSDK user's CI would fly, with the native MAVSDK 4.x binding
(groundstation/flight/reference_flight.py): connect, wait for armable, arm, take off to 10 m, hold,
go 30 m north, RTL, land at home, disarm. Telemetry is checked against the flight as it happens."""
from __future__ import annotations

import math

import pytest
from mavsdk.asyncio.plugins.param import ParamAsync
from mavsdk.asyncio.plugins.telemetry import FlightMode

from firefly.groundstation.flight.reference_flight import connect, fly_takeoff_goto_rtl, north_east_m
from firefly.groundstation.flight.vehicle_link import first  # noqa: F401 - test_mavsdk_mission takes it from here

pytestmark = pytest.mark.sitl


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

"""A thin MAVSDK (native 4.x) link with waits measured on conditions, never on durations.

Everything the companion learns about the vehicle arrives as MAVLink telemetry through MAVSDK;
waits end on a condition or fail with a message saying what did not happen.
"""
from __future__ import annotations

import asyncio
import math

from mavsdk.asyncio import ComponentType, Configuration, Mavsdk
from mavsdk.asyncio.plugins.action import ActionAsync
from mavsdk.asyncio.plugins.telemetry import TelemetryAsync

from firefly.sim.geo import GeoPoint, global_from_ned, ned_from_global


class LinkError(RuntimeError):
    pass


async def first(stream, condition, timeout: float, what: str):
    async def scan():
        async for item in stream:
            if condition(item):
                return item
    try:
        return await asyncio.wait_for(scan(), timeout)
    except asyncio.TimeoutError:
        raise LinkError(f"timed out after {timeout:g} s waiting for {what}") from None


def home_point(home) -> GeoPoint:
    """MAVSDK's home position as the sim's GeoPoint."""
    return GeoPoint(home.latitude_deg, home.longitude_deg, home.absolute_altitude_m)


class VehicleLink:
    def __init__(self, mavsdk: Mavsdk, system):
        self.mavsdk = mavsdk
        self.system = system
        self.telemetry = TelemetryAsync(system)
        self.action = ActionAsync(system)
        self.home = None

    @classmethod
    async def connect(cls, url: str, timeout: float = 15.0) -> "VehicleLink":
        mavsdk = Mavsdk(Configuration.create_with_component_type(ComponentType.GROUND_STATION))
        try:
            await mavsdk.add_any_connection(url)
            system = await mavsdk.first_autopilot(timeout_s=timeout)
        except BaseException:  # cancelled (the autopilot process exited) or failed: no link left open
            mavsdk.destroy()
            raise
        if system is None:
            mavsdk.destroy()
            raise LinkError(f"no autopilot answered on {url} within {timeout:g} s")
        return cls(mavsdk, system)

    def close(self) -> None:
        self.mavsdk.destroy()

    async def wait_armable(self, timeout: float = 15.0) -> None:
        await first(self.telemetry.subscribe_health(),
                    lambda h: h.is_armable and h.is_global_position_ok and h.is_home_position_ok,
                    timeout, "the vehicle to become armable")
        self.home = await self.telemetry.home()

    @property
    def origin(self) -> GeoPoint:
        """Home, the origin of the local north/east metres (the projection the sim itself uses)."""
        return home_point(self.home)

    def north_east_m(self, pos) -> tuple:
        """(n, e) metres from home of a MAVSDK position."""
        return self.north_east_of(pos.latitude_deg, pos.longitude_deg)

    def north_east_of(self, lat_deg: float, lon_deg: float) -> tuple:
        return ned_from_global(self.origin, lat_deg, lon_deg, self.origin.alt_m)[:2]

    def lat_lon_of(self, n: float, e: float) -> tuple:
        point = global_from_ned(self.origin, n, e, 0.0)
        return point.lat_deg, point.lon_deg

    async def position(self):
        return await first(self.telemetry.subscribe_position(), lambda p: True, 5.0, "a position")

    async def takeoff(self, alt_m: float, timeout: float) -> None:
        await self.action.arm()
        await self.action.set_takeoff_altitude(alt_m)
        await self.action.takeoff()
        await first(self.telemetry.subscribe_position(), lambda p: p.relative_altitude_m > alt_m - 0.3,
                    timeout, f"takeoff to {alt_m:g} m")

    async def goto_ned(self, n: float, e: float, alt_m: float, tolerance_m: float, timeout: float,
                       on_position=None, settle_m_s: float | None = None):
        lat, lon = self.lat_lon_of(n, e)
        await self.action.goto_location(lat, lon, self.home.absolute_altitude_m + alt_m, float("nan"))

        def arrived(p):
            if on_position:
                on_position(p)
            return math.dist(self.north_east_m(p), (n, e)) < tolerance_m
        reached = await first(self.telemetry.subscribe_position(), arrived, timeout, f"arrival at N{n:g} E{e:g}")
        if settle_m_s is not None:
            await first(self.telemetry.subscribe_velocity_ned(),
                        lambda v: math.hypot(v.north_m_s, v.east_m_s) < settle_m_s, timeout,
                        f"the vehicle to slow below {settle_m_s:g} m/s at N{n:g} E{e:g}")
        return reached

    async def land_and_disarm(self, timeout: float, rtl: bool = False, on_position=None) -> None:
        await (self.action.return_to_launch() if rtl else self.action.land())

        async def disarmed():
            async for armed in self.telemetry.subscribe_armed():
                if not armed:
                    return
        watcher = None
        if on_position:
            async def track():
                async for p in self.telemetry.subscribe_position():
                    on_position(p)
            watcher = asyncio.ensure_future(track())
        try:
            await asyncio.wait_for(disarmed(), timeout)
        except asyncio.TimeoutError:
            raise LinkError(f"vehicle still armed {timeout:g} s after {'RTL' if rtl else 'LAND'}") from None
        finally:
            if watcher:
                watcher.cancel()

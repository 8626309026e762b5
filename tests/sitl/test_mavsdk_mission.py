"""A mission flown with the native MAVSDK mission_raw plugin: upload, download back identical,
start, progress to the end with each waypoint passed within 2 m, RTL to home, disarm."""
from __future__ import annotations

import asyncio
import math

import pytest
from mavsdk.asyncio.plugins.mission_raw import MissionItem, MissionRawAsync
from mavsdk.asyncio.plugins.telemetry import TelemetryAsync
from mavsdk.asyncio.plugins.action import ActionAsync

from .test_mavsdk_flight import connect, first, north_east_m

pytestmark = pytest.mark.sitl

NAV_WAYPOINT, NAV_RTL, NAV_TAKEOFF, DO_CHANGE_SPEED = 16, 20, 22, 178
FRAME_GLOBAL, FRAME_REL_ALT_INT, FRAME_MISSION = 0, 6, 2
SQUARE = [(25.0, 0.0), (25.0, 25.0), (0.0, 25.0), (-10.0, 5.0)]


def plan(home) -> list:
    m_per_deg_lon = 111_320.0 * math.cos(math.radians(home.latitude_deg))

    def item(seq, command, frame=FRAME_REL_ALT_INT, n=0.0, e=0.0, alt=0.0, p1=0.0, p2=0.0):
        x = int(round((home.latitude_deg + n / 111_320.0) * 1e7)) if frame != FRAME_MISSION else 0
        y = int(round((home.longitude_deg + e / m_per_deg_lon) * 1e7)) if frame != FRAME_MISSION else 0
        return MissionItem(seq, frame, command, 1 if seq == 0 else 0, 1, p1, p2, 0.0, 0.0, x, y, alt, 0)

    items = [item(0, NAV_WAYPOINT, FRAME_GLOBAL, alt=home.absolute_altitude_m),
             item(1, NAV_TAKEOFF, alt=12.0),
             item(2, DO_CHANGE_SPEED, FRAME_MISSION, p2=6.0)]
    for n, e in SQUARE:
        items.append(item(len(items), NAV_WAYPOINT, n=n, e=e, alt=12.0))
    items.append(item(len(items), NAV_RTL, FRAME_MISSION))
    return items


def fields(it) -> tuple:
    return (it.seq, it.frame, it.command, it.autocontinue, it.param1, it.param2, it.param3, it.param4,
            it.x, it.y, round(it.z, 3), it.mission_type)


def downloaded_fields(it) -> tuple:
    """What ArduCopter gives back for an uploaded item: the frame only of the items it stores with
    a location (AP_Mission::stored_in_location); DO_CHANGE_SPEED and RTL come back in frame 0."""
    f = fields(it)
    return f if it.command in (NAV_WAYPOINT, NAV_TAKEOFF) else (f[0], 0, *f[2:])


async def test_mission_upload_download_and_fly(autopilot):
    mavsdk, system = await connect(autopilot.mavsdk_url)
    try:
        telemetry, action, mission = TelemetryAsync(system), ActionAsync(system), MissionRawAsync(system)
        await first(telemetry.subscribe_health(), lambda h: h.is_armable and h.is_home_position_ok, 10, "armable")
        home = await telemetry.home()
        items = plan(home)
        await mission.upload_mission(items)
        downloaded = await mission.download_mission()
        assert [fields(i) for i in downloaded[1:]] == [downloaded_fields(i) for i in items[1:]]
        assert downloaded[0].command == NAV_WAYPOINT  # seq 0 is home, ArduPilot's convention
        assert abs(downloaded[0].x / 1e7 - home.latitude_deg) < 1e-6

        closest = [math.inf] * len(SQUARE)

        def track(pos):
            here = north_east_m(pos, home)
            for k, wp in enumerate(SQUARE):
                closest[k] = min(closest[k], math.dist(here, wp))

        async def follow_positions():
            async for pos in telemetry.subscribe_position():
                track(pos)
        watcher = asyncio.ensure_future(follow_positions())
        try:
            await action.arm()
            await mission.start_mission()
            total = len(items) - 1
            await first(mission.subscribe_mission_progress(), lambda p: p.current >= total - 1, 90,
                        "mission progress to the RTL item")
            await first(telemetry.subscribe_armed(), lambda a: not a, 90, "disarm after the mission's RTL")
        finally:
            watcher.cancel()
        assert max(closest) < 2.0, f"closest approach to each waypoint: {closest}"
        final = await telemetry.position()
        n, e = north_east_m(final, home)
        assert math.hypot(n, e) < 2.0 and final.relative_altitude_m < 0.3
    finally:
        mavsdk.destroy()

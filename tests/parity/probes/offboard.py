"""MAVSDK's Offboard plugin as a user's code drives it (native MAVSDK 4.x, not its messages sent
by hand as the guided area does): what each call answers, the mode it leaves the vehicle in, and
what the vehicle does, reduced to what such code would check.

* flying: position NED, velocity NED, velocity body with a yaw speed, attitude, then stop.
* landed: Offboard velocity started on the ground, then the vehicle armed: ArduCopter stays
  there and disarms after DISARM_DELAY (issue 28: Firefly took off and flew 150 m).
The vehicle is booted and made armable through the pymavlink probe client, whose port MAVSDK then
takes over (as the mavsdk area does). MAVSDK streams the last setpoint itself at 20 Hz.
"""
from __future__ import annotations

import asyncio
import math

from mavsdk.asyncio.plugins.action import ActionAsync
from mavsdk.asyncio.plugins.offboard import (Attitude, OffboardAsync, OffboardError, PositionNedYaw,
                                              VelocityBodyYawspeed, VelocityNedYaw)
from mavsdk.asyncio.plugins.telemetry import TelemetryAsync

from firefly.groundstation.flight.reference_flight import connect

from ..facts import Tol, Trace
from .mavsdk_client import mode, outcome, until
from .mavsdk_client import run as run_with_mavsdk

AREA = "offboard"
SPEED = Tol(abs=0.4, rel=0.15, why="two airframes and controller tunings: speeds within 15 %")
HEADING = Tol(abs=10.0, why="a heading within 10 degrees")
ANGLE = Tol(abs=2.0, why="an attitude held within 2 degrees")


async def offboard_outcome(call) -> str:
    return await outcome(call, (OffboardError,))


async def sample(stream):
    return await until(stream, lambda x: True, "a sample")


async def during(telemetry, vehicle_s: float, reader) -> list:
    """reader's values from the position-velocity stream for about vehicle_s of flight: counted
    in samples (ArduCopter and Firefly both stream it at the rate MAVSDK asks, in vehicle time)."""
    values = []
    rate_hz = 10.0
    await telemetry.set_rate_position_velocity_ned(rate_hz)
    async for pv in telemetry.subscribe_position_velocity_ned():
        values.append(reader(pv))
        if len(values) >= vehicle_s * rate_hz:
            return values
    return values


async def fly(url: str) -> dict[str, Trace]:
    mavsdk, system = await connect(url)
    telemetry, action, offboard = TelemetryAsync(system), ActionAsync(system), OffboardAsync(system)
    traces = {"landed": Trace(), "flying": Trace()}
    try:
        await until(telemetry.subscribe_health(), lambda h: h.is_armable and h.is_home_position_ok, "armable")
        t = traces["flying"]
        await action.set_takeoff_altitude(10.0)
        t.fact("arm", await outcome(action.arm()))
        t.fact("takeoff", await outcome(action.takeoff()))
        await until(telemetry.subscribe_position(), lambda p: p.relative_altitude_m > 9.3, "10 m")
        here = (await sample(telemetry.subscribe_position_velocity_ned())).position
        heading = (await sample(telemetry.subscribe_heading())).heading_deg
        await offboard.set_position_ned(PositionNedYaw(here.north_m + 15.0, here.east_m, here.down_m, heading))
        t.fact("start", await offboard_outcome(offboard.start()))
        t.fact("mode", await mode(telemetry))
        await until(telemetry.subscribe_position_velocity_ned(),
                    lambda pv: abs(pv.position.north_m - here.north_m - 15.0) < 1.0, "15 m north")
        await offboard.set_velocity_ned(VelocityNedYaw(0.0, 2.0, 0.0, 90.0))
        speeds = await during(telemetry, 4.0, lambda pv: math.hypot(pv.velocity.north_m_s, pv.velocity.east_m_s))
        t.fact("velocity_ned_speed", max(speeds), SPEED)
        t.fact("velocity_ned_heading_deg", round((await sample(telemetry.subscribe_heading())).heading_deg),
               HEADING)
        await offboard.set_velocity_body(VelocityBodyYawspeed(2.0, 0.0, 0.0, 30.0))
        speeds = await during(telemetry, 4.0, lambda pv: math.hypot(pv.velocity.north_m_s, pv.velocity.east_m_s))
        t.fact("velocity_body_speed", max(speeds), SPEED)
        yaw_rate = (await sample(telemetry.subscribe_attitude_angular_velocity_body())).yaw_rad_s
        t.fact("velocity_body_yaw_deg_s", math.degrees(yaw_rate), Tol(abs=5.0, why="30 deg/s asked"))
        heading = (await sample(telemetry.subscribe_heading())).heading_deg
        await offboard.set_attitude(Attitude(0.0, -10.0, heading, 0.5))
        await during(telemetry, 2.0, lambda pv: None)
        t.fact("attitude_pitch_deg", (await sample(telemetry.subscribe_attitude_euler())).pitch_deg, ANGLE)
        t.fact("stop", await offboard_outcome(offboard.stop()))
        t.fact("mode_after_stop", await mode(telemetry))
        t.fact("armed_after", await sample(telemetry.subscribe_armed()))
        t.fact("land", await outcome(action.land()))
        await until(telemetry.subscribe_armed(), lambda a: not a, "disarmed after landing")

        t = traces["landed"]
        await offboard.set_velocity_ned(VelocityNedYaw(3.0, 0.0, -1.0, 0.0))
        t.fact("start", await offboard_outcome(offboard.start()))
        t.fact("mode", await mode(telemetry))
        await telemetry.set_rate_position_velocity_ned(10.0)
        t.fact("arm", await outcome(action.arm()))
        await until(telemetry.subscribe_armed(), bool, "armed")
        top, ticks = [0.0], [0]

        async def count_ticks():  # vehicle time, as 10 Hz samples of the vehicle's own stream
            async for _ in telemetry.subscribe_position_velocity_ned():
                ticks[0] += 1
        counter = asyncio.ensure_future(count_ticks())

        async def watch_altitude():
            async for p in telemetry.subscribe_position():
                top[0] = max(top[0], p.relative_altitude_m)
        watcher = asyncio.ensure_future(watch_altitude())
        try:
            await asyncio.wait_for(until(telemetry.subscribe_armed(), lambda a: not a, "the disarm"), 60)
            t.fact("disarmed", True)
            t.fact("disarmed_after_s", ticks[0] / 10.0, Tol(abs=1.5, why="DISARM_DELAY from the land "
                                                             "detector's verdict, counted in 10 Hz samples"))
        except (AssertionError, asyncio.TimeoutError):
            t.fact("disarmed", False)
        watcher.cancel()
        counter.cancel()
        t.fact("left_ground", top[0] > 0.5)
        t.fact("stop", await offboard_outcome(offboard.stop()))
        t.fact("mode_after_stop", await mode(telemetry))

    except AssertionError as exc:  # what was not seen: the facts after it are missing, and say so
        print(f"offboard probe stopped: {exc}")
    finally:
        mavsdk.destroy()
    return traces


def run(target) -> dict[str, Trace]:
    return run_with_mavsdk(target, fly)

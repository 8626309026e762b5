"""What a MAVSDK (native 4.x) user's code sees: health once armable, the result of each Action call
in the state it is made in (takeoff disarmed, arm, takeoff, disarm in flight, hold, goto, speed,
RTL, land), the flight modes and landed states MAVSDK reports through a flight, and a mission
flown with the mission plugin (progress, finished).

MAVSDK maps ArduCopter's modes and results to its own enums; the facts are those enum names, as a
user's asserts would compare them. The vehicle is booted and made armable through the pymavlink
probe client, whose port MAVSDK then takes over.
"""
from __future__ import annotations

import asyncio
import math

from mavsdk.asyncio.plugins.action import ActionAsync, ActionError
from mavsdk.asyncio.plugins.mission import MissionAsync, MissionError, MissionItem, MissionPlan
from mavsdk.asyncio.plugins.telemetry import TelemetryAsync

from firefly.groundstation.flight.reference_flight import connect

from ..facts import Trace

AREA = "mavsdk"
EARTH_M_PER_DEG = 111_195.0
WAIT_S = 60.0  # wall seconds for a condition; the vehicles run at 10x-20x, so minutes of flight


async def until(stream, condition, what: str, seen: list | None = None, key=lambda x: x):
    """The first item of `stream` for which condition holds; distinct keys of the items on the way
    are appended to `seen`."""
    async def scan():
        async for item in stream:
            if seen is not None and (not seen or seen[-1] != key(item)):
                seen.append(key(item))
            if condition(item):
                return item
    try:
        return await asyncio.wait_for(scan(), WAIT_S)
    except asyncio.TimeoutError:
        raise AssertionError(f"MAVSDK saw no {what}") from None


async def outcome(call, errors: tuple = (ActionError, MissionError)) -> str:
    """SUCCESS, or the name of the result a plugin's call failed with (its error types: `errors`),
    or "no answer"."""
    try:
        await asyncio.wait_for(call, 15.0)
        return "SUCCESS"
    except errors as exc:
        return exc.result.name
    except asyncio.TimeoutError:
        return "no answer"


async def mode(telemetry) -> str:
    return (await until(telemetry.subscribe_flight_mode(), lambda m: True, "a flight mode")).name


async def mode_after(telemetry, before: str, wall_s: float = 3.0) -> str:
    """The mode once it differs from `before`, or `before` if it has not changed within wall_s
    (30 s or more of vehicle time): an action's ACK comes before the HEARTBEAT that shows it."""
    async def changed():
        async for m in telemetry.subscribe_flight_mode():
            if m.name != before:
                return m.name
    try:
        return await asyncio.wait_for(changed(), wall_s)
    except asyncio.TimeoutError:
        return before


def offset(home, n_m: float, e_m: float) -> tuple[float, float]:
    return (home.latitude_deg + n_m / EARTH_M_PER_DEG,
            home.longitude_deg + e_m / (EARTH_M_PER_DEG * math.cos(math.radians(home.latitude_deg))))


async def fly(url: str) -> dict[str, Trace]:
    mavsdk, system = await connect(url)
    telemetry, action, mission = TelemetryAsync(system), ActionAsync(system), MissionAsync(system)
    traces = {name: Trace() for name in ("health", "actions", "mission")}
    texts: list[str] = []

    async def listen():
        async for st in telemetry.subscribe_status_text():
            texts.append(st.text)
    listener = asyncio.ensure_future(listen())
    try:
        t = traces["health"]
        health = await until(telemetry.subscribe_health(), lambda h: h.is_armable and h.is_home_position_ok,
                             "armable health")
        for field in ("is_gyrometer_calibration_ok", "is_accelerometer_calibration_ok",
                      "is_magnetometer_calibration_ok", "is_local_position_ok", "is_global_position_ok",
                      "is_home_position_ok", "is_armable"):
            t.fact(field, getattr(health, field))
        t.fact("gps_fix", (await telemetry.gps_info()).fix_type.name)
        home = await telemetry.home()

        t = traces["mission"]
        items = [MissionItem(*offset(home, n, e), 10.0, 5.0, True, float("nan"), float("nan"),
                             MissionItem.CameraAction.NONE, float("nan"), float("nan"), 1.0, float("nan"),
                             float("nan"), MissionItem.VehicleAction.NONE)
                 for n, e in ((30.0, 0.0), (30.0, 10.0), (20.0, 10.0))]
        t.fact("upload", await outcome(mission.upload_mission(MissionPlan(items))))
        # Subscribed a whole takeoff before the start: a gRPC stream takes a while to open, and a
        # late one misses the first items (at 20x on a loaded machine the first leg takes 0.15 s).
        progress: list[list[int]] = []
        ended = asyncio.Event()

        async def follow():
            async for p in mission.subscribe_mission_progress():
                if not progress or progress[-1] != [p.current, p.total]:
                    progress.append([p.current, p.total])
                if p.total and p.current >= p.total:
                    ended.set()
        follower = asyncio.ensure_future(follow())

        t = traces["actions"]
        t.fact("takeoff_disarmed", await outcome(action.takeoff()))
        t.fact("disarm_disarmed", await outcome(action.disarm()))
        t.fact("arm", await outcome(action.arm()))
        await until(telemetry.subscribe_armed(), bool, "armed")
        t.fact("mode_armed", await mode(telemetry))
        t.fact("set_takeoff_altitude", await outcome(action.set_takeoff_altitude(10.0)))
        t.fact("takeoff", await outcome(action.takeoff()))
        landed: list[str] = []
        await until(telemetry.subscribe_landed_state(), lambda s: s.name == "IN_AIR", "IN_AIR", landed, lambda s: s.name)
        t.fact("landed_states_takeoff", [s for s in landed if s != "ON_GROUND"])  # from where it was
        await until(telemetry.subscribe_position(), lambda p: p.relative_altitude_m > 9.3, "10 m")
        t.fact("mode_flying", await mode(telemetry))
        t.fact("in_air", await until(telemetry.subscribe_in_air(), lambda a: True, "in air"))
        t.fact("disarm_flying", await outcome(action.disarm()))
        t.fact("takeoff_flying", await outcome(action.takeoff()))
        flying = await mode(telemetry)
        t.fact("hold", await outcome(action.hold()))
        t.fact("mode_after_hold", await mode_after(telemetry, flying))
        t.fact("set_current_speed", await outcome(action.set_current_speed(4.0)))
        lat, lon = offset(home, 20.0, 0.0)
        t.fact("goto", await outcome(action.goto_location(lat, lon, home.absolute_altitude_m + 10.0, float("nan"))))
        t.fact("mode_after_goto", await mode_after(telemetry, "HOLD"))
        t.fact("set_current_speed_guided", await outcome(action.set_current_speed(4.0)))
        await until(telemetry.subscribe_position(),
                    lambda p: abs(p.latitude_deg - lat) * EARTH_M_PER_DEG < 1.5, "arrival 20 m north")

        t = traces["mission"]
        try:
            started = await outcome(mission.start_mission())
            t.fact("start_flying", started)
            if started == "SUCCESS":
                t.fact("mode_in_mission", await mode_after(telemetry, "OFFBOARD"))
                await asyncio.wait_for(ended.wait(), WAIT_S)
                t.fact("progress", progress)
                t.fact("finished", await mission.is_mission_finished())
            # After the flight: a failed download leaves MAVSDK without the uploaded plan's progress.
            # MAVSDK's mission plugin refuses ArduPilot's home item (seq 0, frame GLOBAL) on download.
            t.fact("download", await outcome(mission.download_mission()))
        except asyncio.TimeoutError:
            raise AssertionError(f"MAVSDK saw no mission end (progress {progress})") from None
        finally:
            follower.cancel()

        t = traces["actions"]
        t.fact("return_to_launch", await outcome(action.return_to_launch()))
        modes: list[str] = []
        await until(telemetry.subscribe_flight_mode(), lambda m: m.name == "RETURN_TO_LAUNCH", "RTL mode",
                    modes, lambda m: m.name)
        t.fact("mode_after_rtl", modes[-1])
        t.fact("land", await outcome(action.land()))
        landed = []
        await until(telemetry.subscribe_landed_state(), lambda s: s.name == "ON_GROUND", "ON_GROUND",
                    landed, lambda s: s.name)
        t.fact("landed_states_landing", [s for s in landed if s != "IN_AIR"])
        t.fact("mode_landing", await mode_after(telemetry, "RETURN_TO_LAUNCH"))
        await until(telemetry.subscribe_armed(), lambda a: not a, "disarmed after landing")
        t.fact("arm_in_land", await outcome(action.arm()))
        t.fact("hold_on_ground", await outcome(action.hold()))
        t.fact("mode_hold_on_ground", await mode_after(telemetry, "LAND"))
        t.fact("arm_in_hold", await outcome(action.arm()))
    except AssertionError as exc:  # what was not seen: the facts after it are missing, and say so
        print(f"mavsdk probe stopped: {exc}; the vehicle said {texts[-5:]}")
    finally:
        listener.cancel()
        mavsdk.destroy()
    return traces


def run(target, flight=fly) -> dict[str, Trace]:
    """Boot the vehicle through the probe client, then fly `flight(url)` with MAVSDK on its port."""
    client = target.boot()
    url = client.url.replace("udpin:", "udpin://")
    client.close()  # MAVSDK takes the port over
    try:
        return asyncio.run(flight(url))
    finally:
        target.close()

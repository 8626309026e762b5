"""`groundstation mission FILE`: fly a .plan or .waypoints mission with MAVSDK.

Uploads the mission (mission_raw), arms, starts it, shows progress (item k of n, distance to the
next waypoint, battery) on a progress bar, waits for the end measured in vehicle time (the GPS
timestamps the vehicle sends), returns home if the mission did not land, and writes a summary and
a PNG of the planned against the flown track, with the camera's photos where it took them.

The photos come from CAMERA_FEEDBACK, which MAVSDK's Python API does not expose: a pymavlink
listener (camera_feedback.py) reads it on a link of its own. When this command starts its own
autopilot it adds an `--out` for that listener, and for a plan that uses the camera boots it with
a servo camera (`--param CAM1_TYPE=1`); against a running vehicle (--url) it listens on
--camera-url if given (a MAVProxy output, say), else the photos are not watched and the summary
says so. A plan that uses the camera gets CAM1_TYPE 1 (a servo camera) when the vehicle has it at
0; ArduCopter makes its camera at boot, so there the photos start from its next boot.
"""
from __future__ import annotations

import asyncio
import math
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

from mavsdk.asyncio.plugins.mission_raw import MissionItem, MissionRawAsync, MissionRawError
from mavsdk.asyncio.plugins.param import ParamAsync, ParamError

from ..plots import draw_track, label_map, png
from ..progress import Progress
from .autopilot_process import free_udp_port, run_flight
from .camera_feedback import CameraFeedbackListener
from .mission_files import MissionPlan, load_mission
from .vehicle_link import LinkError, VehicleLink, first

FRAME_GLOBAL, FRAME_MISSION = 0, 2
NAV_RTL, NAV_LAND = 20, 21
CAMERA_COMMANDS = {202, 203, 206, 214, 2000, 2001}  # DIGICAM_CONFIGURE/CONTROL, CAM_TRIGG_DIST/INTERVAL, IMAGE_*
SERVO_CAMERA = 1
VEHICLE_TIME_MARGIN_S = 180.0


@dataclass
class FlightRecord:
    track: list = field(default_factory=list)  # (north, east, alt) in metres from home
    vehicle_time_s: float = 0.0
    battery_pct: float = math.nan
    battery_start_pct: float = math.nan
    current_item: int = 0
    furthest_item: int = 0  # the mission's end is judged by this: a landed vehicle resets to item 1


def to_raw_items(plan: MissionPlan, home) -> list:
    """Seq 0 is home (ArduPilot's convention), then the plan's items with integer coordinates."""
    raw = [MissionItem(0, FRAME_GLOBAL, 16, 1, 1, 0, 0, 0, 0, int(round(home.latitude_deg * 1e7)),
                       int(round(home.longitude_deg * 1e7)), home.absolute_altitude_m, 0)]
    for seq, it in enumerate(plan.items, start=1):
        scale = 1 if it.frame == FRAME_MISSION else 1e7  # a MISSION-frame item's x, y are plain numbers
        raw.append(MissionItem(seq, it.frame, it.command, 0, int(it.autocontinue), *it.params,
                               int(round(it.lat_deg * scale)), int(round(it.lon_deg * scale)), it.alt_m, 0))
    return raw


def planned_path(plan: MissionPlan, link: VehicleLink) -> list:
    """Horizontal points of the plan's positional items, in metres from home, starting at home."""
    return [(0.0, 0.0)] + [link.north_east_of(it.lat_deg, it.lon_deg) for it in plan.items if it.has_position]


def path_length(points: list) -> float:
    """Horizontal length of a track of (n, e, ...) points."""
    return sum(math.dist(a[:2], b[:2]) for a, b in zip(points, points[1:]))


def uses_camera(plan: MissionPlan) -> bool:
    return any(it.command in CAMERA_COMMANDS for it in plan.items)


async def camera_ready(link: VehicleLink) -> None:
    """CAM1_TYPE 1 where the vehicle has a camera parameter set to none."""
    params = ParamAsync(link.system)
    try:
        if await params.get_param_int("CAM1_TYPE") == 0:
            await params.set_param_int("CAM1_TYPE", SERVO_CAMERA)
            print("CAM1_TYPE set to 1 (servo camera); ArduCopter takes it at its next boot")
    except ParamError:
        print("the vehicle has no CAM1_TYPE: no camera to trigger")


async def fly_mission(url: str, plan: MissionPlan, plot: Path | None,
                      camera: CameraFeedbackListener | None = None) -> dict:
    link = await VehicleLink.connect(url)
    rec = FlightRecord()
    tasks = []
    try:
        await link.wait_armable()
        if uses_camera(plan):
            await camera_ready(link)
        mission = MissionRawAsync(link.system)
        raw = to_raw_items(plan, link.home)
        try:
            await mission.upload_mission(raw)
        except MissionRawError as exc:  # a command it does not fly, a parameter it refuses
            raise LinkError(f"the vehicle refused the mission: {exc.result.name}") from None
        print(f"uploaded {len(plan.items)} items")
        targets = {seq: link.north_east_of(it.lat_deg, it.lon_deg)
                   for seq, it in enumerate(plan.items, start=1) if it.has_position}
        planned = planned_path(plan, link)
        budget_s = path_length(planned) / 2.0 + VEHICLE_TIME_MARGIN_S  # vehicle seconds
        progress = Progress(len(plan.items), sys.stdout)
        t_start = None

        async def watch_time():
            nonlocal t_start
            async for gps in link.telemetry.subscribe_raw_gps():
                t = gps.timestamp_us * 1e-6
                t_start = t if t_start is None else t_start
                rec.vehicle_time_s = t - t_start

        async def watch_battery():
            async for b in link.telemetry.subscribe_battery():
                rec.battery_pct = b.remaining_percent
                if math.isnan(rec.battery_start_pct):
                    rec.battery_start_pct = b.remaining_percent

        async def watch_position():
            async for p in link.telemetry.subscribe_position():
                here = link.north_east_m(p)
                rec.track.append(here + (p.relative_altitude_m,))
                nxt = next((targets[s] for s in sorted(targets) if s >= max(rec.current_item, 1)), None)
                item = rec.current_item
                progress.show(item, f"item {item}/{len(plan.items)}  next {math.dist(here, nxt) if nxt else 0.0:.1f} m  "
                                    f"battery {rec.battery_pct:.1f} %  vehicle time {rec.vehicle_time_s:.1f} s",
                              milestone=item)

        async def watch_progress():
            async for mp in mission.subscribe_mission_progress():
                if mp.current == 0 and rec.current_item > 0:
                    continue  # ArduCopter resets the mission when it disarms: the last item stands
                rec.current_item = min(mp.current, len(plan.items))  # MAVSDK reports n+1 when done
                rec.furthest_item = max(rec.furthest_item, rec.current_item)

        tasks = [asyncio.ensure_future(c()) for c in (watch_time, watch_battery, watch_position, watch_progress)]
        await link.action.arm()
        await mission.start_mission()
        wall0 = time.monotonic()
        ends_landed = plan.items[-1].command in (NAV_RTL, NAV_LAND)

        async def mission_over():
            while True:
                if ends_landed and not await link.telemetry.armed() and rec.furthest_item >= len(plan.items) - 1:
                    return
                if not ends_landed and await mission.is_mission_finished():
                    return
                if rec.vehicle_time_s > budget_s:
                    raise LinkError(f"mission not finished after {budget_s:.0f} s of vehicle time")
                await first(link.telemetry.subscribe_position(), lambda p: True, 10.0, "telemetry")
        await mission_over()
        if not ends_landed:
            progress.close()
            print("mission complete; returning to launch")
            await link.land_and_disarm(budget_s, rtl=True)
        progress.close()
        final = await link.position()
        summary = {
            "items": len(plan.items), "vehicle_time_s": rec.vehicle_time_s,
            "wall_time_s": time.monotonic() - wall0, "flown_m": path_length(rec.track),
            "planned_m": path_length(planned), "battery_used_pct": rec.battery_start_pct - rec.battery_pct,
            "landed_from_home_m": math.hypot(*link.north_east_m(final)),
            "camera_triggers": len(camera.photos) if camera is not None else "not watched",
        }
        photos = [link.north_east_of(lat, lon) for lat, lon, _ in camera.photos] if camera is not None else []
    finally:
        for t in tasks:
            t.cancel()
        link.close()
    if plot is not None:
        write_plot(planned, rec.track, plot, photos=photos)
        summary["plot"] = str(plot)
    return summary


def write_plot(planned: list, flown: list, path: Path, title: str = "Mission: planned and flown",
               photos: list = ()) -> None:
    with png(path, (6, 6)) as (fig, ax):
        draw_track(ax, planned, "k--o", lw=0.9, ms=4, label="planned")
        draw_track(ax, flown, lw=1.5, label="flown")
        if photos:
            draw_track(ax, photos, "rx", ms=6, label=f"camera triggers ({len(photos)})")
        ax.plot(0, 0, "g^", ms=10, label="home")
        label_map(ax, title)
        ax.set_aspect("equal")
        ax.legend(loc="best")


def run(path: Path, url: str | None, speedup: float, plot: Path | None, camera_url: str | None = None) -> int:
    plan = load_mission(path)
    extra: tuple = ()
    if url is None:  # an autopilot of our own: one more output, for the camera listener
        port = free_udp_port()
        camera_url, extra = f"udpin:127.0.0.1:{port}", ("--out", f"udp:127.0.0.1:{port}")
        if uses_camera(plan):  # a servo camera, there from boot (the camera is made at boot)
            extra += ("--param", f"CAM1_TYPE={SERVO_CAMERA}")
    camera = CameraFeedbackListener(camera_url) if camera_url else None
    if camera is not None:
        camera.start()
    try:
        summary = run_flight(lambda at: fly_mission(at, plan, plot, camera), url, speedup, extra=extra)
    finally:
        if camera is not None:
            camera.stop()
    print("summary: " + ", ".join(f"{k} {v:.1f}" if isinstance(v, float) else f"{k} {v}"
                                  for k, v in summary.items()))
    return 0

"""`groundstation explore`: the fire-localization companion, flying the real vehicle over MAVLink.

It connects with MAVSDK, waits for armable, takes off to the survey altitude, and flies the search
controller's targets (strategy/controller.py) in GUIDED (DO_REPOSITION through MAVSDK's goto) at the
survey speed. The readings reach the controller through survey.py, which pairs each GND_TEMP
reading (NAMED_VALUE_FLOAT) with the vehicle's position at its own timestamp and averages them to the
evaluated density. When the controller declares the fire it prints the estimate, returns to launch,
lands, and writes a PNG of the flown track over the final belief.

The plume leans with the wind, so the search needs it. ArduCopter reports zero wind (WIND) unless
its EKF fuses the rotors' drag, so by default the search estimates the wind itself from how the
vehicle leans in steady flight (ATTITUDE and LOCAL_POSITION_NED, lean_samples.py). With told_wind it
asks for the vehicle's WIND report instead (ArduCopter sends it only when asked) and is told that.
With sensor "camera" it also takes a thermal still at each observation point through the camera
protocol and reads it by MAVLink FTP (camera_frames.py), and its planner scores what a frame would
see, as the decision-level episodes' camera search does. Everything it knows of the vehicle arrives
as MAVLink. On a lost link or a refused command it says
so, leaves the vehicle in RTL (or hold) if it can, and exits non-zero.
"""
from __future__ import annotations

import asyncio
import json
import math
import time
from pathlib import Path

import numpy as np
from mavsdk.asyncio.plugins.mavlink_direct import MavlinkDirectAsync

from firefly.sim.fire import FireWorld

from ..truth import fires_found, judge
from ..strategy import Geometry, make_policy
from ..strategy.controller import SearchConfig, SearchController
from ..strategy.stopping import Declaration
from ..plots import draw_track, label_map, png
from ..camera_view import nadir_footprint_m
from .autopilot_process import check_scenario, run_flight
from .camera_frames import FlightCamera
from .lean_samples import LeanSamples
from .survey import Survey
from .vehicle_link import LinkError, VehicleLink, first

TEMPERATURE_NAME = "GND_TEMP"
LINK_SILENCE_S = 5.0  # wall seconds without a position: the link is lost
POLICY_SEED = 7  # the flight's policy draws from its own fixed stream: the same choices run after run


class CommandRefused(RuntimeError):
    pass


class Feed:
    """The telemetry feeding the survey, one task per message kind. A handler that raises stops
    the flight with its error (and the vehicle is made safe) instead of dying unseen while the
    search flies on without readings."""

    def __init__(self, direct, moved: asyncio.Event):
        self.direct, self.moved = direct, moved
        self.tasks: list[asyncio.Future] = []
        self.failure: str | None = None

    def watch(self, name: str, handle) -> None:
        async def run():
            try:
                async for msg in self.direct.subscribe_message(name):
                    handle(json.loads(msg.fields_json))
            except asyncio.CancelledError:
                raise
            except Exception as exc:  # noqa: BLE001 - any handler error ends the flight, named
                self.failure = f"{name} handling failed: {type(exc).__name__}: {exc}"
                self.moved.set()  # wake the survey loop to see it
        self.tasks.append(asyncio.ensure_future(run()))

    def run(self, name: str, job) -> None:
        """A coroutine beside the telemetry (the camera's stills): its error ends the flight, named."""
        async def run():
            try:
                await job
            except asyncio.CancelledError:
                raise
            except Exception as exc:  # noqa: BLE001 - as watch's handlers
                self.failure = f"{name} failed: {type(exc).__name__}: {exc}"
                self.moved.set()
        self.tasks.append(asyncio.ensure_future(run()))

    def check(self) -> None:
        if self.failure is not None:
            raise FeedFailed(self.failure)

    def cancel(self) -> None:
        for t in self.tasks:
            t.cancel()


class FeedFailed(RuntimeError):
    pass


WIND_MSG_ID = 168
WIND_RATE_HZ = 1.0  # asked for: ArduCopter sends WIND only in a requested stream
WIND_WAIT_S = 10.0


class WindReport:
    """The vehicle's last WIND message: where the wind blows from [deg] and its speed [m/s]."""

    def __init__(self):
        self.from_deg = self.speed_m_s = None
        self.seen = asyncio.Event()

    def take(self, fields: dict) -> None:
        self.from_deg, self.speed_m_s = float(fields["direction"]), float(fields["speed"])
        self.seen.set()

    def air_velocity_ne(self) -> tuple[float, float]:
        """Where the air goes (north, east) [m/s]: toward from_deg + 180."""
        to = math.radians(self.from_deg + 180.0)
        return self.speed_m_s * math.cos(to), self.speed_m_s * math.sin(to)


async def request_message_rate(direct, system, msg_id: int, rate_hz: float) -> None:
    """SET_MESSAGE_INTERVAL for one message (what a ground station does to get a message no
    stream carries by default)."""
    from mavsdk.asyncio.plugins.mavlink_direct import MavlinkMessage
    fields = {"target_system": await system.get_system_id(), "target_component": 1, "command": 511,
              "confirmation": 0,
              "param1": float(msg_id), "param2": 1e6 / rate_hz, "param3": 0.0, "param4": 0.0,
              "param5": 0.0, "param6": 0.0, "param7": 0.0}
    ack = await command(direct.send_command(MavlinkMessage("COMMAND_LONG", 0, 0, fields["target_system"], 1,
                                                           json.dumps(fields))),
                        f"SET_MESSAGE_INTERVAL({msg_id})")
    result = json.loads(ack.fields_json).get("result") if ack.fields_json else None
    if result != 0:
        raise CommandRefused(f"vehicle refused SET_MESSAGE_INTERVAL({msg_id}): result {result}")


async def first_wind(wind: WindReport) -> None:
    try:
        await asyncio.wait_for(wind.seen.wait(), WIND_WAIT_S)
    except asyncio.TimeoutError:
        raise LinkError(f"no WIND message within {WIND_WAIT_S:g} s of asking for it") from None


async def explore(url: str, world: FireWorld, policy_name: str, plot: Path | None, truth: bool,
                  config: SearchConfig = SearchConfig(), say=print, told_wind: bool = False,
                  sensor: str = "point") -> dict:
    """Fly one search; `say` receives the progress lines (print by default); told_wind: tell the
    search the vehicle's WIND report instead of estimating the wind; sensor "camera": a thermal still
    at each observation point besides the point readings."""
    geometry = Geometry.from_world(world)
    policy = make_policy(policy_name)
    survey = Survey(geometry, config)
    moved = asyncio.Event()  # set by every position report
    link = await VehicleLink.connect(url)
    feed = None
    camera: FlightCamera | None = None
    yaw_behavior: int | None = None  # the vehicle's own WP_YAW_BEHAVIOR while the camera flight holds the heading
    try:
        await link.wait_armable()
        say(f"vehicle armable; surveying {geometry.area_m:g} m x {geometry.area_m:g} m "
            f"({geometry.cells_per_side}^2 cells) at {geometry.survey_alt_m:g} m with policy {policy_name}")
        feed = Feed(MavlinkDirectAsync(link.system), moved)
        await link.telemetry.set_rate_position_velocity_ned(10.0)
        await link.telemetry.set_rate_attitude_euler(10.0)
        leans = LeanSamples(geometry.survey_alt_m)

        def on_position(f):
            survey.add_position(int(f["time_boot_ms"]), f["x"], f["y"], f["z"])
            sample = leans.add_velocity(int(f["time_boot_ms"]), f["vx"], f["vy"], -f["z"])
            if sample is not None and survey.active:
                survey.controller.observe_lean(*sample)
            moved.set()

        def on_value(f):
            if str(f.get("name", "")).rstrip("\0") == TEMPERATURE_NAME:
                survey.add_reading(int(f["time_boot_ms"]), float(f["value"]))

        wind = WindReport()
        if sensor == "camera":
            camera = FlightCamera(link, feed.direct, survey)
            survey.on_observe = camera.on_observation
            policy.footprint_m = nadir_footprint_m(camera.spec, geometry.survey_alt_m)  # before the controller resets it
            feed.watch("CAMERA_IMAGE_CAPTURED", camera.on_captured)
        feed.watch("LOCAL_POSITION_NED", on_position)
        feed.watch("NAMED_VALUE_FLOAT", on_value)
        feed.watch("ATTITUDE", lambda f: leans.add_attitude(int(f["time_boot_ms"]), f["roll"], f["pitch"], f["yaw"]))
        if told_wind:
            feed.watch("WIND", wind.take)
            await request_message_rate(feed.direct, link.system, WIND_MSG_ID, WIND_RATE_HZ)
        if camera is not None:
            yaw_behavior = await command(camera.hold_heading(), "WP_YAW_BEHAVIOR 0 (hold the heading)")
        await command(link.action.arm(), "arm")
        await command(link.action.set_takeoff_altitude(geometry.survey_alt_m), "set takeoff altitude")
        await command(link.action.takeoff(), "takeoff")
        await first(link.telemetry.subscribe_position(),
                    lambda p: p.relative_altitude_m > geometry.survey_alt_m - 0.5, 60, "survey altitude")
        await command(link.action.set_current_speed(config.speed_m_s), "set speed")
        wall0 = time.monotonic()
        start_t_ms = survey.vehicle_t_ms
        if told_wind:
            await first_wind(wind)
            say(f"wind {wind.speed_m_s:.1f} m/s from {wind.from_deg % 360:.0f} deg (WIND)")
        else:
            say("wind: estimated from how the vehicle leans")
        controller = SearchController(geometry, policy, config, survey.here(), np.random.default_rng(POLICY_SEED),
                                      time.perf_counter, wind_ne_m_s=wind.air_velocity_ne() if told_wind else None)
        for sample in leans.samples:  # the hover at the survey height, before the search
            controller.observe_lean(*sample)
        feed.check()
        survey.start(controller)
        if camera is not None:
            feed.run("the camera's stills", camera.run())
        declared = await fly_survey(link, survey, moved, feed)
        est_n, est_e = declared.position
        est = link.lat_lon_of(est_n, est_e)
        result = {
            "declared_n_m": est_n, "declared_e_m": est_e, "declared_lat": est[0], "declared_lon": est[1],
            "mass_3x3": declared.mass, "forced": declared.forced, "declared_by": controller.finished_by,
            "spread_m": spread_m(controller.belief.probabilities(), geometry.cell_size_m),
            "survey_vehicle_s": (survey.vehicle_t_ms - start_t_ms) / 1000.0,
            "survey_wall_s": time.monotonic() - wall0,
            "path_m": survey.path_m, "first_find_path_m": controller.first_find_path_m,
            "readings": survey.readings, "observations": controller.observations,
            "wind_used_ne_m_s": list(controller.wind_ne_m_s), "lean_samples": len(leans.samples),
            "wind_source": "WIND" if told_wind else "estimated from the lean",
            "fires": [], "sensor": sensor,
            "decision_ms_mean": 1000.0 * float(np.mean(controller.decision_s)) if controller.decision_s else 0.0,
            "decision_ms_max": 1000.0 * max(controller.decision_s, default=0.0),
        }
        say(f"thinking: {len(controller.decision_s)} decisions, {result['decision_ms_mean']:.1f} ms mean, "
            f"{result['decision_ms_max']:.0f} ms max")
        if camera is not None:
            result.update(camera.summary(), footprints=list(camera.frames))
            say(f"{len(camera.frames)} thermal frames taken and read ({camera.missed} observation points without one); "
                f"a frame {result['frame_wall_ms_mean']:.0f} ms of wall time (max {result['frame_wall_ms_max']:.0f}) and "
                f"{result['frame_vehicle_ms_mean']:.0f} ms of vehicle time from capture to belief "
                f"({result['frame_download_ms_mean']:.0f} ms of wall time the download), "
                f"{result['frame_ms_mean']:.1f} ms of it the search's own")
        estimate = controller.wind_estimator.estimate() if controller.wind_estimator else None
        if estimate is not None:
            wn, we = estimate.air_ne_m_s
            result.update(wind_estimate_ne_m_s=[wn, we], wind_estimate_sd_m_s=estimate.sd_m_s, lean_sd=estimate.lean_sd)
            say(f"wind estimated from {len(leans.samples)} lean samples: {math.hypot(wn, we):.2f} m/s from "
                f"{math.degrees(math.atan2(-we, -wn)) % 360:.0f} deg (+- {estimate.sd_m_s:.2f} m/s; "
                f"lean spread {estimate.lean_sd:.4f})")
        if not controller.declarations:
            say(f"no fire: the search is confident there is none, after {result['path_m']:.0f} m "
                f"and {result['survey_vehicle_s']:.0f} s of vehicle time")
        elif controller.several and controller.first_find_path_m is not None:
            ended = {"clear": "confident there is no other fire", "confident": "every fire it looked for found",
                     "budget": "its path budget spent", "end": "nothing more to do"}.get(controller.finished_by, "")
            say(f"{len(controller.declarations)} fire(s): the first found after {controller.first_find_path_m:.0f} m; "
                f"the search ended {ended} after {result['path_m']:.0f} m (climbs included) and "
                f"{result['survey_vehicle_s']:.0f} s of vehicle time")
        for k, found in enumerate(controller.declarations):
            n_m, e_m = found.position
            lat, lon = link.lat_lon_of(n_m, e_m)
            fire = {"n_m": n_m, "e_m": e_m, "lat": lat, "lon": lon, "mass_3x3": found.mass}
            result["fires"].append(fire)
            first_m = result["path_m"] if controller.first_find_path_m is None else controller.first_find_path_m
            if k:  # the first declaration alone says when it came
                when = ""
            elif controller.several:
                when = f", found after {first_m:.0f} m"
            else:
                when = (f", spread {result['spread_m']:.1f} m, after {result['path_m']:.0f} m and "
                        f"{result['survey_vehicle_s']:.0f} s of vehicle time")
            say(f"fire declared at N {n_m:.1f} m E {e_m:.1f} m (lat {lat:.7f}, lon {lon:.7f}), "
                f"3x3 mass {found.mass:.3f}{when}")
            if truth and world.fires:
                error, within = judge(world, n_m, e_m)
                best = min(world.fires, key=lambda f: math.hypot(n_m - f.n_m, e_m - f.e_m))
                fire.update(true_n_m=best.n_m, true_e_m=best.e_m, error_m=error, within_one_cell=within)
                if k == 0:
                    result.update(true_n_m=best.n_m, true_e_m=best.e_m, error_m=error, within_one_cell=within)
                say(f"true fire at N {best.n_m:.1f} m E {best.e_m:.1f} m: error {error:.1f} m "
                    f"({'within' if within else 'NOT within'} one {geometry.cell_size_m:g} m cell)")
        if truth and world.fires and len(world.fires) > 1:
            result["fires_found"] = fires_found(world, [(f["n_m"], f["e_m"]) for f in result["fires"]])
            say(f"{result['fires_found']} of {len(world.fires)} fires found")
        say("returning to launch")
        await link.land_and_disarm(600, rtl=True)
        final = await link.position()
        result["landed_from_home_m"] = math.hypot(*link.north_east_m(final))
        say(f"landed and disarmed {result['landed_from_home_m']:.1f} m from home")
        if camera is not None and yaw_behavior is not None:
            await command(camera.restore_heading(yaw_behavior), f"WP_YAW_BEHAVIOR {yaw_behavior} (put back)")
            yaw_behavior = None
    except (LinkError, CommandRefused, FeedFailed) as exc:
        await make_safe(link)
        if camera is not None and yaw_behavior is not None:  # best effort: the vehicle's own setting back
            try:
                await asyncio.wait_for(camera.restore_heading(yaw_behavior), 5.0)
            except Exception:  # noqa: BLE001 - the link may be gone; the flight's error is what is said
                pass
        raise LinkError(str(exc)) from None
    finally:
        if feed is not None:
            feed.cancel()
        link.close()
    save_picture(plot, result, say, lambda path: write_plot(survey, world if truth else None, result, path))
    return result


def camera_options(sensor: str) -> tuple:
    """The autopilot options a search with this sensor needs of the vehicle it starts: the thermal
    camera fitted, its live video off (the search reads stills; the video would cost the vehicle
    some 5 ms of rendering and encoding per frame, 8.7 frames a vehicle second)."""
    return ("--thermal-camera", "--video-port", "0") if sensor == "camera" else ()


def save_picture(plot: Path | None, result: dict, say, draw) -> None:
    """draw(plot) if a picture is wanted, and say where it is."""
    if plot is not None:
        draw(plot)
        result["plot"] = str(plot)
        say(f"picture: {plot}")


def spread_m(p: np.ndarray, cell_m: float) -> float:
    """The belief's spread: root of the summed variances of its north and east marginals."""
    centres = (np.arange(p.shape[0]) + 0.5) * cell_m
    mean_n = float((p.sum(axis=1) * centres).sum())
    mean_e = float((p.sum(axis=0) * centres).sum())
    return math.sqrt(float((p.sum(axis=1) * (centres - mean_n) ** 2).sum()
                           + (p.sum(axis=0) * (centres - mean_e) ** 2).sum()))


async def command(awaitable, what: str):
    try:
        return await asyncio.wait_for(awaitable, 15.0)
    except asyncio.TimeoutError:
        raise LinkError(f"no answer to {what} (link lost?)") from None
    except Exception as exc:  # noqa: BLE001 - MAVSDK's ActionError and friends
        raise CommandRefused(f"vehicle refused {what}: {exc}") from None


async def make_safe(link: VehicleLink, say=print) -> None:
    """Leave the vehicle in RTL, or at least holding, when the companion gives up."""
    for action in (link.action.return_to_launch, link.action.hold):
        try:
            await asyncio.wait_for(action(), 5.0)
            say("vehicle left in " + ("RTL" if action == link.action.return_to_launch else "hold"))
            return
        except Exception:  # noqa: BLE001
            continue


async def fly_survey(link: VehicleLink, survey: Survey, moved: asyncio.Event, feed: Feed) -> Declaration:
    """Fly the controller's targets until it declares; its decisions come at new observations and
    arrivals (survey.next_move), and every position report is a chance to look."""
    sent = None
    while True:
        feed.check()
        moved.clear()
        move = survey.next_move()
        if isinstance(move, Declaration):
            return move
        height = survey.geometry.survey_alt_m if move is None or move.height_m is None else move.height_m
        if move is not None and (sent is None or math.dist((*move.target, height), sent) > 0.5):
            sent = (*move.target, height)
            lat, lon = link.lat_lon_of(*move.target)
            await command(link.action.goto_location(lat, lon, link.home.absolute_altitude_m + height, float("nan")),
                          "goto")
        try:
            await asyncio.wait_for(moved.wait(), LINK_SILENCE_S)
        except asyncio.TimeoutError:
            raise LinkError(f"vehicle link lost: no position for {LINK_SILENCE_S:g} s") from None


def write_plot(survey: Survey, world: FireWorld | None, result: dict, path: Path) -> None:
    with png(path, (6.4, 5.6)) as (fig, ax):
        draw_belief(fig, ax, survey.controller.belief.probabilities(), survey.geometry)
        draw_footprints(ax, result.get("footprints", ()))
        if survey.track:
            draw_track(ax, survey.track, color="cyan", lw=1.2, label="flown (readings)")
        for k, fire in enumerate(result["fires"]):
            ax.plot(fire["e_m"], fire["n_m"], "wx", ms=12, mew=2.5, label="declared" if k == 0 else None)
        draw_fires(ax, world)
        draw_wind(ax, result, survey.geometry)
        further = survey.controller.several and survey.controller.found
        frames = f", {result['frames']} thermal frames" if "frames" in result else ""
        label_map(ax, f"Fire search: {result['path_m']:.0f} m flown, {result['readings']} readings{frames}"
                  + ("\n(the map: where a further fire could be)" if further else ""))
        ax.legend(loc="upper left", fontsize=8)


def draw_footprints(ax, footprints) -> None:
    """Each thermal frame's ground rectangle, as the search judged it (frame.py)."""
    for k, (n_lo, n_hi, e_lo, e_hi) in enumerate(footprints):
        ax.plot([e_lo, e_hi, e_hi, e_lo, e_lo], [n_lo, n_lo, n_hi, n_hi, n_lo], color="white", lw=0.5,
                alpha=0.35, label="thermal frames" if k == 0 else None)


def draw_wind(ax, result: dict, g: Geometry) -> None:
    """The wind the search ended with (its last estimate, or what it was told), as an arrow where
    the air goes (the plume leans that way), near the picture's lower right corner; nothing in calm air."""
    wn, we = result.get("wind_estimate_ne_m_s", result.get("wind_used_ne_m_s", (0.0, 0.0)))
    speed = math.hypot(wn, we)
    if speed < 0.05:
        return
    length = 0.12 * g.area_m
    tail_e, tail_n = 0.78 * g.area_m, 0.12 * g.area_m
    ax.annotate("", xy=(tail_e + length * we / speed, tail_n + length * wn / speed), xytext=(tail_e, tail_n),
                arrowprops=dict(arrowstyle="->", color="white", lw=2))
    ax.text(tail_e, tail_n - 0.06 * g.area_m, f"wind {speed:.1f} m/s\n({result.get('wind_source', '')})",
            color="white", fontsize=7, ha="center", va="top")


def draw_belief(fig, ax, p: np.ndarray, g: Geometry) -> None:
    """The belief's log probabilities over the area, with their colour bar."""
    img = ax.imshow(np.log10(np.maximum(p, 1e-12)), origin="lower", extent=(0, g.area_m, 0, g.area_m),
                    cmap="inferno", vmin=-8, vmax=0)
    fig.colorbar(img, ax=ax, label="log10 P(fire in cell)")


def draw_fires(ax, world: FireWorld | None) -> None:
    """The true fires, when the picture may show them."""
    for k, f in enumerate(world.fires if world is not None else ()):
        ax.plot(f.e_m, f.n_m, "o", mfc="none", mec="lime", ms=14, mew=2, label="true fire" if k == 0 else None)


def run(url: str | None, scenario: Path | None, policy: str, speedup: float, plot: Path | None,
        truth: bool, max_fires: int | None = None, told_wind: bool = False, sensor: str = "point") -> int:
    from firefly.sim.scenario import Scenario, load_scenario
    sc = load_scenario(scenario) if scenario else Scenario()
    if scenario and not url:
        check_scenario(scenario)  # the vehicle's tables too, before a vehicle starts on them
    make_policy(policy)  # a bad name fails here, before anything starts
    config = SearchConfig(max_fires=max_fires)
    result = run_flight(lambda at: explore(at, sc.world, policy, plot, truth, config, told_wind=told_wind, sensor=sensor),
                        url, speedup, scenario, extra=camera_options(sensor))
    return 0 if result.get("landed_from_home_m", math.inf) < 5.0 else 1

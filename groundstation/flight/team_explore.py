"""`groundstation explore --vehicles K`: the cooperative fire search, flying K real vehicles over MAVLink.

One MAVSDK link per vehicle. Each vehicle takes off to its own survey height (ALTITUDE_STEP_M
apart: that is what keeps them apart, their tracks may cross), and the one team controller
(strategy/team.py) gets every vehicle's readings and gives every vehicle its target, flown in
GUIDED as the one-vehicle search flies (explore.py).

Positions come from GLOBAL_POSITION_INT and are turned into metres from the first vehicle's home,
the area's origin: a vehicle's LOCAL_POSITION_NED is relative to its own EKF origin (ArduCopter
sets that where the vehicle first had a fix), so local positions of different vehicles do not
share a frame. Heights are each vehicle's height above its own home.

A vehicle leaves the search when it stops being able to search: it falls below half its survey
height (a failed motor: long before anything on board says so), it disarms, it leaves GUIDED (a
battery or GPS failsafe put it in LAND or RTL, or a pilot took it), its position stops arriving
for LINK_SILENCE_S, or it refuses a target. The team
controller drops it and the others finish. At the declaration every vehicle still searching
returns to its own home and lands.
"""
from __future__ import annotations

import asyncio
import math
import time
from pathlib import Path

import numpy as np
from mavsdk.asyncio.plugins.mavlink_direct import MavlinkDirectAsync

from firefly.sim.fire import FireWorld
from firefly.sim.geo import ned_from_global

from ..truth import judge
from ..plots import draw_track, label_map, png
from ..strategy import Geometry
from ..strategy.controller import SearchConfig
from ..strategy.stopping import Declaration
from ..strategy.team import TeamController, make_team_policy, survey_heights
from .explore import (LINK_SILENCE_S, POLICY_SEED, TEMPERATURE_NAME, WIND_MSG_ID, WIND_RATE_HZ, CommandRefused, Feed,
                      FeedFailed, WindReport, command, draw_belief, draw_fires, first_wind, make_safe,
                      request_message_rate, save_picture, spread_m)
from .team_survey import TeamSurvey
from .vehicle_link import LinkError, VehicleLink, first

GUIDED = 4  # ArduCopter's custom mode number
ARMED_FLAG = 128  # MAV_MODE_FLAG_SAFETY_ARMED
FALLEN_SHARE = 0.5  # of its survey height: a searching vehicle lower than this has fallen
TRACK_COLOURS = ("cyan", "lime", "magenta", "yellow", "orange", "white")


class VehicleWatch:
    """What says whether one vehicle can still search: its HEARTBEATs and its positions' arrival."""

    def __init__(self):
        self.armed = False
        self.mode: int | None = None
        self.position_wall_s = time.monotonic()
        self.height_m = 0.0
        self.survey_height_m: float | None = None  # set once it is up there and searching

    def heartbeat(self, fields: dict) -> None:
        self.armed = bool(int(fields["base_mode"]) & ARMED_FLAG)
        self.mode = int(fields["custom_mode"])

    def positioned(self, height_m: float) -> None:
        self.position_wall_s = time.monotonic()
        self.height_m = height_m

    def why_out(self) -> str | None:
        if not self.armed:
            return "it disarmed"
        if self.mode != GUIDED:
            return f"it left GUIDED (mode {self.mode})"
        if time.monotonic() - self.position_wall_s > LINK_SILENCE_S:
            return f"no position for {LINK_SILENCE_S:g} s"
        if self.survey_height_m is not None and self.height_m < FALLEN_SHARE * self.survey_height_m:
            # a failed motor: it falls long before anything on board says so
            return f"it fell to {self.height_m:.0f} m, below half its survey height of {self.survey_height_m:g} m"
        return None


async def connect_all(urls: list[str]) -> list[VehicleLink]:
    links = []
    try:
        for url in urls:
            links.append(await VehicleLink.connect(url))
    except BaseException:
        for link in links:
            link.close()
        raise
    return links


async def explore_team(urls: list[str], world: FireWorld, policy_name: str, plot: Path | None, truth: bool,
                       config: SearchConfig = SearchConfig(), say=print) -> dict:
    """Fly one cooperative search with the vehicles at `urls` (the first one's home is the area's
    origin); `say` receives the progress lines."""
    geometry = Geometry.from_world(world)
    k = len(urls)
    heights = survey_heights(geometry, k)
    policy = make_team_policy(policy_name)
    survey = TeamSurvey(geometry, config, k)
    watches = [VehicleWatch() for _ in range(k)]
    moved = asyncio.Event()  # set by every position report of any vehicle
    links = await connect_all(urls)
    feeds: list[Feed] = []
    result: dict = {}
    try:
        await asyncio.gather(*(link.wait_armable() for link in links))
        origin = links[0].origin
        say(f"{k} vehicles armable; surveying {geometry.area_m:g} m x {geometry.area_m:g} m at heights "
            + ", ".join(f"{h:g}" for h in heights) + f" m with team policy {policy_name}")
        wind = WindReport()
        for i, link in enumerate(links):
            feed = Feed(MavlinkDirectAsync(link.system), moved)
            feeds.append(feed)
            feed.watch("GLOBAL_POSITION_INT", _on_position(survey, watches[i], origin, i, moved))
            feed.watch("NAMED_VALUE_FLOAT", _on_value(survey, i))
            feed.watch("HEARTBEAT", watches[i].heartbeat)
            await link.telemetry.set_rate_position(10.0)
        feeds[0].watch("WIND", wind.take)
        await request_message_rate(feeds[0].direct, links[0].system, WIND_MSG_ID, WIND_RATE_HZ)
        await asyncio.gather(*(_take_off(link, h) for link, h in zip(links, heights)))
        for watch, height in zip(watches, heights):
            watch.survey_height_m = height
        for link in links:
            await command(link.action.set_current_speed(config.speed_m_s), "set speed")
        await first_wind(wind)
        say(f"wind {wind.speed_m_s:.1f} m/s from {wind.from_deg % 360:.0f} deg (WIND)")
        wall0 = time.monotonic()
        start_t_ms = survey.members[0].vehicle_t_ms
        team = TeamController(geometry, policy, config, survey.heres(), np.random.default_rng(POLICY_SEED),
                              wind_ne_m_s=wind.air_velocity_ne())
        survey.start(team)
        declared = await fly_team(links, survey, watches, feeds, moved, heights, say)
        result = _result(survey, team, declared, links[0], start_t_ms, wall0)
        say(f"fire declared at N {declared.position[0]:.1f} m E {declared.position[1]:.1f} m, 3x3 mass "
            f"{declared.mass:.3f}" + (" (forced)" if declared.forced else "")
            + f", after {result['survey_vehicle_s']:.0f} s of vehicle time")
        if truth and world.fires:
            error, within = judge(world, *declared.position)
            fire = min(world.fires, key=lambda f: math.hypot(declared.position[0] - f.n_m, declared.position[1] - f.e_m))
            result.update(true_n_m=fire.n_m, true_e_m=fire.e_m, error_m=error, within_one_cell=within)
            say(f"true fire at N {fire.n_m:.1f} m E {fire.e_m:.1f} m: error {error:.1f} m "
                f"({'within' if within else 'NOT within'} one {geometry.cell_size_m:g} m cell)")
        for i in range(k):
            say(f"vehicle {i + 1}: path {result['paths_m'][i]:.0f} m"
                + ("" if team.active[i] else f", out of the search ({result['out'][i]})"))
        say("returning to launch")
        searching = [i for i in range(k) if team.active[i]]
        await asyncio.gather(*(links[i].land_and_disarm(600, rtl=True) for i in searching))
        landed = {}
        for i in searching:
            landed[i] = math.hypot(*links[i].north_east_m(await links[i].position()))
            say(f"vehicle {i + 1} landed and disarmed {landed[i]:.1f} m from its home")
        result["landed_from_home_m"] = [landed.get(i) for i in range(k)]
    except (LinkError, CommandRefused, FeedFailed) as exc:
        await asyncio.gather(*(make_safe(link, lambda text, i=i: say(f"vehicle {i + 1}: {text}"))
                               for i, link in enumerate(links)))
        raise LinkError(str(exc)) from None
    finally:
        for feed in feeds:
            feed.cancel()
        for link in links:
            link.close()
    save_picture(plot, result, say, lambda path: write_plot(survey, world if truth else None, result, path))
    return result


def _on_position(survey: TeamSurvey, watch: VehicleWatch, origin, i: int, moved: asyncio.Event):
    def on_position(f: dict) -> None:
        n, e, _ = ned_from_global(origin, f["lat"] / 1e7, f["lon"] / 1e7, origin.alt_m)
        height = f["relative_alt"] / 1000.0
        survey.add_position(i, int(f["time_boot_ms"]), n, e, -height)
        watch.positioned(height)
        moved.set()
    return on_position


def _on_value(survey: TeamSurvey, i: int):
    def on_value(f: dict) -> None:
        if str(f.get("name", "")).rstrip("\0") == TEMPERATURE_NAME:
            survey.add_reading(i, int(f["time_boot_ms"]), float(f["value"]))
    return on_value


async def _take_off(link: VehicleLink, height_m: float) -> None:
    await command(link.action.arm(), "arm")
    await command(link.action.set_takeoff_altitude(height_m), "set takeoff altitude")
    await command(link.action.takeoff(), "takeoff")
    await first(link.telemetry.subscribe_position(), lambda p: p.relative_altitude_m > height_m - 0.5, 60,
                f"survey height {height_m:g} m")


async def fly_team(links: list[VehicleLink], survey: TeamSurvey, watches: list[VehicleWatch], feeds: list[Feed],
                   moved: asyncio.Event, heights: list[float], say) -> Declaration:
    """Fly every vehicle's target until the team declares; a vehicle that can no longer search is
    dropped and the others go on."""
    team = survey.team
    sent: list[tuple | None] = [None] * len(links)

    def drop(i: int, why: str) -> None:
        survey.drop(i, why)
        say(f"vehicle {i + 1} is out of the search: {why}; {sum(team.active)} go on")

    while True:
        for feed in feeds:
            feed.check()
        for i, watch in enumerate(watches):
            if team.active[i] and (why := watch.why_out()) is not None:
                drop(i, why)
        moved.clear()
        moves = survey.next_moves()
        if isinstance(moves, Declaration):
            return moves
        for i, goto in enumerate(moves or ()):
            if goto is None or not team.active[i] or (sent[i] is not None and math.dist(goto.target, sent[i]) <= 0.5):
                continue
            link = links[i]
            lat, lon = links[0].lat_lon_of(*goto.target)  # the area's frame: the first vehicle's home
            try:
                await command(link.action.goto_location(lat, lon, link.home.absolute_altitude_m + heights[i],
                                                        float("nan")), f"goto (vehicle {i + 1})")
            except (CommandRefused, LinkError) as exc:
                drop(i, str(exc))
                continue
            sent[i] = goto.target
        try:
            await asyncio.wait_for(moved.wait(), LINK_SILENCE_S)
        except asyncio.TimeoutError:
            raise LinkError(f"every vehicle's link lost: no position for {LINK_SILENCE_S:g} s") from None


def _result(survey: TeamSurvey, team: TeamController, declared: Declaration, first_link: VehicleLink,
            start_t_ms: int, wall0: float) -> dict:
    n, e = declared.position
    lat, lon = first_link.lat_lon_of(n, e)
    out = survey.out
    return {
        "vehicles": team.k, "declared_n_m": n, "declared_e_m": e, "declared_lat": lat, "declared_lon": lon,
        "mass_3x3": declared.mass, "forced": declared.forced, "declared_by": team.finished_by,
        "spread_m": spread_m(team.belief.probabilities(), survey.geometry.cell_size_m),
        "survey_vehicle_s": (survey.members[0].vehicle_t_ms - start_t_ms) / 1000.0,
        "survey_wall_s": time.monotonic() - wall0,
        "paths_m": survey.paths_m, "path_m": max(survey.paths_m), "team_path_m": sum(survey.paths_m),
        "readings": sum(m.readings for m in survey.members), "observations": team.observations,
        "dropped": sorted(out), "out": {i: out[i] for i in sorted(out)},
    }


def write_plot(survey: TeamSurvey, world: FireWorld | None, result: dict, path: Path) -> None:
    with png(path, (6.4, 5.6)) as (fig, ax):
        draw_belief(fig, ax, survey.team.belief.probabilities(), survey.geometry)
        for i, member in enumerate(survey.members):
            if member.track:
                out = " (out)" if i in result.get("out", {}) else ""
                draw_track(ax, member.track, color=TRACK_COLOURS[i % len(TRACK_COLOURS)], lw=1.2,
                           label=f"vehicle {i + 1}{out}")
        if result:
            ax.plot(result["declared_e_m"], result["declared_n_m"], "wx", ms=12, mew=2.5, label="declared")
        draw_fires(ax, world)
        title = (f"Team search: {len(survey.members)} vehicles, {sum(survey.paths_m):.0f} m flown"
                 if result else "Team search")
        label_map(ax, title)
        ax.legend(loc="upper left", fontsize=8)


MAX_VEHICLES = 6


def run(url: str | None, scenario: Path | None, policy: str, speedup: float, plot: Path | None, truth: bool,
        vehicles: int, max_fires: int = 1) -> int:
    from firefly.sim.scenario import Scenario, load_scenario
    from ..strategy.team import TEAM_POLICIES
    from .autopilot_process import check_scenario, run_team_flight
    if policy not in TEAM_POLICIES:
        raise ValueError(f"--policy: {policy!r} is not a team policy (with --vehicles {vehicles}: "
                         f"{', '.join(TEAM_POLICIES)})")
    if vehicles > MAX_VEHICLES:
        raise ValueError(f"--vehicles: at most {MAX_VEHICLES}, got {vehicles}")
    if max_fires != 1:
        raise ValueError("--max-fires: a team searches for one fire")
    urls = [u.strip() for u in url.split(",")] if url else None
    if urls is not None and len(urls) != vehicles:
        raise ValueError(f"--url: {len(urls)} URL(s) for --vehicles {vehicles}: give one per vehicle, comma-separated")
    sc = load_scenario(scenario) if scenario else Scenario()
    if scenario and not urls:
        check_scenario(scenario)
    result = run_team_flight(lambda at: explore_team(at, sc.world, policy, plot, truth), urls, speedup, scenario,
                             count=vehicles)
    landed = [d for d in result.get("landed_from_home_m", []) if d is not None]
    return 0 if landed and all(d < 5.0 for d in landed) else 1

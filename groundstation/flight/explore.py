"""`groundstation explore`: the fire-localization companion, flying the real vehicle over MAVLink.

It connects with MAVSDK, waits for armable, takes off to the survey altitude, and flies the
policy's waypoints in GUIDED (DO_REPOSITION through MAVSDK's goto) at the survey speed. Every
GND_TEMP reading (NAMED_VALUE_FLOAT) is paired with the vehicle's position at the reading's own
timestamp (LOCAL_POSITION_NED, interpolated), and updates the belief. The policy replans on arrival
and as often as it asks (counted in distance flown). When the stopping rule declares the fire it prints the estimate, returns to
launch, lands, and writes a PNG of the flown track over the final belief.

Everything it knows of the vehicle arrives as MAVLink. On a lost link or a refused command it says
so, leaves the vehicle in RTL (or hold) if it can, and exits non-zero.
"""
from __future__ import annotations

import asyncio
import bisect
import json
import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from mavsdk.asyncio.plugins.mavlink_direct import MavlinkDirectAsync

from sim.fire import FireWorld

from ..strategy import Belief, Geometry, StoppingRule, make_policy
from ..evaluation.episodes import judge
from .vehicle_link import LinkError, VehicleLink, first

TEMPERATURE_NAME = "GND_TEMP"
SURVEY_SPEED_M_S = 5.0
ARRIVAL_M = 2.0
# The decision-level episodes take one reading per 5 m of track or per second, and the belief's
# resolution (3 x 3 sub-positions per cell, 3.3 m apart) was judged at that density. In flight the
# sensor reads ten times a second; fed one by one, those readings multiply the small misfit of a
# fire between two sub-positions tenfold, and on a straight pass that was seen to lock the belief,
# confidently, on the mirror image of the fire across the track. So the flight gives the belief one
# observation per 5 m or per second, as evaluated: the mean of the readings taken over it, at their
# mean position, with the sensor's own sigma (conservative: the mean is less noisy than that).
# The policies' replanning cadence (in readings of the episodes) is counted as distance / 5 m.
SIM_READING_SPACING_M = 5.0
SIM_READING_INTERVAL_MS = 1000
LINK_SILENCE_S = 5.0  # wall seconds without a reading or a position: the link is lost
BUDGET_M = 6000.0
THRESHOLD = 0.99  # 3x3 block mass that declares: the decision-level episodes' default
CONFIRM_M = 10.0  # declare only after a reading this close to the cell's centre (flown over it)


class CommandRefused(RuntimeError):
    pass


@dataclass
class Survey:
    geometry: Geometry
    belief: Belief
    policy: object
    rule: StoppingRule
    positions: list = field(default_factory=list)  # (t_ms, n, e, d) sorted by time
    pending: list = field(default_factory=list)  # readings waiting for a later position
    track: list = field(default_factory=list)  # (n, e) of paired readings
    readings: int = 0
    observations: int = 0  # belief updates: one per bin of readings
    bin: list = field(default_factory=list)  # (t_ms, n, e, height, z) not yet given to the belief
    active: bool = True  # readings update the belief only until the fire is declared
    updated: asyncio.Event = field(default_factory=asyncio.Event)  # set by every new position
    vehicle_t0_ms: int | None = None
    vehicle_t_ms: int = 0

    def add_position(self, t_ms: int, n: float, e: float, d: float) -> None:
        self.updated.set()
        self.vehicle_t_ms = max(self.vehicle_t_ms, t_ms)
        if self.vehicle_t0_ms is None:
            self.vehicle_t0_ms = t_ms
        if self.positions and t_ms <= self.positions[-1][0]:
            return
        self.positions.append((t_ms, n, e, d))
        del self.positions[:-400]
        ready = [r for r in self.pending if r[0] <= t_ms]
        self.pending = [r for r in self.pending if r[0] > t_ms]
        for t, z in ready:
            self._use(t, z)

    def add_reading(self, t_ms: int, z: float) -> None:
        if not math.isfinite(z):
            return
        if self.positions and t_ms <= self.positions[-1][0]:
            self._use(t_ms, z)
        else:
            self.pending.append((t_ms, z))

    def position_at(self, t_ms: int):
        """Linear interpolation of the position track at a reading's time."""
        times = [p[0] for p in self.positions]
        k = bisect.bisect_left(times, t_ms)
        if k == 0:
            return self.positions[0][1:]
        if k >= len(times):
            return self.positions[-1][1:]
        (t0, *a), (t1, *b) = self.positions[k - 1], self.positions[k]
        w = (t_ms - t0) / (t1 - t0) if t1 > t0 else 0.0
        return tuple(x + w * (y - x) for x, y in zip(a, b))

    def _use(self, t_ms: int, z: float) -> None:
        if not self.positions or not self.active:
            return
        n, e, d = self.position_at(t_ms)
        height = -d
        if height < self.geometry.survey_alt_m * 0.8:
            self.bin.clear()  # an observation averages only readings taken in one stretch
            return  # climbing or descending: readings from other heights are not used
        self.track.append((n, e))
        self.readings += 1
        self.bin.append((t_ms, n, e, height, z))
        first = self.bin[0]
        if math.dist(first[1:3], (n, e)) >= SIM_READING_SPACING_M or t_ms - first[0] >= SIM_READING_INTERVAL_MS:
            _, n, e, height, z = (sum(column) / len(self.bin) for column in zip(*self.bin))
            self.bin.clear()
            self.belief.update(n, e, z, height)
            self.policy.observe(n, e, z)
            self.observations += 1


def world_geometry(world: FireWorld) -> Geometry:
    return Geometry.from_world(world)


def path_length(points) -> float:
    return float(sum(math.dist(a, b) for a, b in zip(points, points[1:])))


async def explore(url: str, world: FireWorld, policy_name: str, plot: Path | None, truth: bool,
                  say=print) -> dict:
    """Fly one search; `say` receives the progress lines (print by default)."""
    geometry = world_geometry(world)
    survey = Survey(geometry, Belief(geometry, subcells=3), make_policy(policy_name),
                    StoppingRule(THRESHOLD, 1, BUDGET_M, CONFIRM_M))
    link = await VehicleLink.connect(url)
    tasks = []
    try:
        await link.wait_armable()
        say(f"vehicle armable; surveying {geometry.area_m:g} m x {geometry.area_m:g} m "
              f"({geometry.cells_per_side}^2 cells) at {geometry.survey_alt_m:g} m with policy {policy_name}")
        direct = MavlinkDirectAsync(link.system)
        await link.telemetry.set_rate_position_velocity_ned(10.0)

        async def watch(name, handle):
            async for msg in direct.subscribe_message(name):
                handle(json.loads(msg.fields_json))

        def on_position(f):
            survey.add_position(int(f["time_boot_ms"]), f["x"], f["y"], f["z"])

        def on_value(f):
            if str(f.get("name", "")).rstrip("\0") == TEMPERATURE_NAME:
                survey.add_reading(int(f["time_boot_ms"]), float(f["value"]))

        tasks = [asyncio.ensure_future(watch("LOCAL_POSITION_NED", on_position)),
                 asyncio.ensure_future(watch("NAMED_VALUE_FLOAT", on_value))]
        await command(link.action.arm(), "arm")
        await command(link.action.set_takeoff_altitude(geometry.survey_alt_m), "set takeoff altitude")
        await command(link.action.takeoff(), "takeoff")
        await first(link.telemetry.subscribe_position(),
                    lambda p: p.relative_altitude_m > geometry.survey_alt_m - 0.5, 60, "survey altitude")
        await command(link.action.set_current_speed(SURVEY_SPEED_M_S), "set speed")
        wall0 = time.monotonic()
        start_readings_t = survey.vehicle_t_ms
        here = survey.positions[-1][1:3]
        survey.policy.reset(geometry, here, np.random.default_rng(7))
        declaration = await fly_survey(link, survey)
        survey.active = False
        est_n, est_e = declaration.position
        est = link.lat_lon_of(est_n, est_e)
        p = survey.belief.probabilities()
        centres = (np.arange(p.shape[0]) + 0.5) * geometry.cell_size_m
        mean_n = float((p.sum(axis=1) * centres).sum())
        mean_e = float((p.sum(axis=0) * centres).sum())
        spread = math.sqrt(float((p.sum(axis=1) * (centres - mean_n) ** 2).sum()
                                 + (p.sum(axis=0) * (centres - mean_e) ** 2).sum()))
        result = {
            "declared_n_m": est_n, "declared_e_m": est_e, "declared_lat": est[0], "declared_lon": est[1],
            "mass_3x3": declaration.mass, "forced": declaration.forced, "spread_m": spread,
            "survey_vehicle_s": (survey.vehicle_t_ms - start_readings_t) / 1000.0,
            "survey_wall_s": time.monotonic() - wall0,
            "path_m": path_length(survey.track), "readings": survey.readings,
            "observations": survey.observations,
        }
        say(f"fire declared at N {est_n:.1f} m E {est_e:.1f} m (lat {est[0]:.7f}, lon {est[1]:.7f}), "
              f"3x3 mass {declaration.mass:.3f}, spread {spread:.1f} m, after {result['path_m']:.0f} m "
              f"and {result['survey_vehicle_s']:.0f} s of vehicle time")
        if truth and world.fires:
            error, within = judge(world, est_n, est_e)
            best = min(world.fires, key=lambda f: math.hypot(est_n - f.n_m, est_e - f.e_m))
            result.update(true_n_m=best.n_m, true_e_m=best.e_m, error_m=error, within_one_cell=within)
            say(f"true fire at N {best.n_m:.1f} m E {best.e_m:.1f} m: error {error:.1f} m "
                f"({'within' if within else 'NOT within'} one {geometry.cell_size_m:g} m cell)")
        say("returning to launch")
        await link.land_and_disarm(600, rtl=True)
        final = await link.position()
        result["landed_from_home_m"] = math.hypot(*link.north_east_m(final))
        say(f"landed and disarmed {result['landed_from_home_m']:.1f} m from home")
    except (LinkError, CommandRefused) as exc:
        await make_safe(link)
        raise LinkError(str(exc)) from None
    finally:
        for t in tasks:
            t.cancel()
        link.close()
    if plot is not None:
        write_plot(survey, world if truth else None, result, plot)
        result["plot"] = str(plot)
        say(f"picture: {plot}")
    return result


async def command(awaitable, what: str):
    try:
        return await asyncio.wait_for(awaitable, 15.0)
    except asyncio.TimeoutError:
        raise LinkError(f"no answer to {what} (link lost?)") from None
    except Exception as exc:  # noqa: BLE001 - MAVSDK's ActionError and friends
        raise CommandRefused(f"vehicle refused {what}: {exc}") from None


async def make_safe(link: VehicleLink) -> None:
    """Leave the vehicle in RTL, or at least holding, when the companion gives up."""
    for action in (link.action.return_to_launch, link.action.hold):
        try:
            await asyncio.wait_for(action(), 5.0)
            print("vehicle left in " + ("RTL" if action == link.action.return_to_launch else "hold"))
            return
        except Exception:  # noqa: BLE001
            continue


async def fly_survey(link: VehicleLink, survey: Survey):
    geometry, policy = survey.geometry, survey.policy
    target, flown_at_decision, confirming = None, 0.0, False
    alt = geometry.survey_alt_m

    async def fly_to(point) -> None:
        nonlocal target
        if target is None or math.dist(point, target) > 0.5:
            target = (float(point[0]), float(point[1]))
            lat, lon = link.lat_lon_of(*target)
            await command(link.action.goto_location(lat, lon, link.home.absolute_altitude_m + alt,
                                                    float("nan")), "goto")

    while True:
        declaration = survey.rule.confident(survey.belief) if survey.observations else None
        flown = path_length(survey.track)
        if declaration is not None:
            return declaration
        if flown >= BUDGET_M:
            return survey.rule.force(survey.belief, "budget")
        here = survey.positions[-1][1:3]
        # Confident but not yet flown over: go and look (the episodes' rule, stopping.py).
        check = survey.rule.to_confirm(survey.belief) if survey.observations else None
        if check is not None:
            confirming = True
            await fly_to(check)
        else:
            arrived = target is not None and math.dist(here, target) < ARRIVAL_M
            replan = policy.wants_replan(int((flown - flown_at_decision) / SIM_READING_SPACING_M))
            if target is None or arrived or replan or confirming:
                confirming = False  # the readings on the way overturned it: back to the policy
                choice = policy.next_waypoint(survey.belief, here)
                flown_at_decision = flown
                if choice is None:
                    return survey.rule.force(survey.belief, "end")
                await fly_to(choice)
        # The loop runs once per new position report: wait for the next one (or give up on the link).
        survey.updated.clear()
        try:
            await asyncio.wait_for(survey.updated.wait(), LINK_SILENCE_S)
        except asyncio.TimeoutError:
            raise LinkError(f"vehicle link lost: no position for {LINK_SILENCE_S:g} s") from None


def write_plot(survey: Survey, world: FireWorld | None, result: dict, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    g = survey.geometry
    p = survey.belief.probabilities()
    fig, ax = plt.subplots(figsize=(6.4, 5.6))
    img = ax.imshow(np.log10(np.maximum(p, 1e-12)), origin="lower", extent=(0, g.area_m, 0, g.area_m),
                    cmap="inferno", vmin=-8, vmax=0)
    fig.colorbar(img, ax=ax, label="log10 P(fire in cell)")
    if survey.track:
        tr = np.array(survey.track)
        ax.plot(tr[:, 1], tr[:, 0], color="cyan", lw=1.2, label="flown (readings)")
    ax.plot(result["declared_e_m"], result["declared_n_m"], "wx", ms=12, mew=2.5, label="declared")
    if world is not None:
        for k, f in enumerate(world.fires):
            ax.plot(f.e_m, f.n_m, "o", mfc="none", mec="lime", ms=14, mew=2, label="true fire" if k == 0 else None)
    ax.set_xlabel("east [m]")
    ax.set_ylabel("north [m]")
    ax.set_title(f"Fire search: {result['path_m']:.0f} m flown, {result['readings']} readings")
    ax.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def run(url: str | None, scenario: Path | None, policy: str, speedup: float, plot: Path | None,
        truth: bool) -> int:
    from sim.scenario import Scenario, load_scenario
    sc = load_scenario(scenario) if scenario else Scenario()
    make_policy(policy)  # a bad name fails here, before anything starts
    if url:
        result = asyncio.run(explore(url, sc.world, policy, plot, truth))
    else:
        from .autopilot_process import AutopilotProcess
        extra = ("--scenario", str(scenario)) if scenario else ()
        with AutopilotProcess(speedup, extra) as ap:
            print(f"started autopilot (speedup {speedup:g}{', scenario ' + str(scenario) if scenario else ''}), "
                  f"MAVSDK connecting on {ap.url}")
            result = asyncio.run(explore(ap.url, sc.world, policy, plot, truth))
    return 0 if result.get("landed_from_home_m", math.inf) < 5.0 else 1

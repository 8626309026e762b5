"""`groundstation evaluate`: every policy on the same seeded decision-level episodes
(episodes.py), a table of the metrics docs/strategy.md describes, the per-episode
results as JSON and a PNG of the path-length distributions."""
from __future__ import annotations

import dataclasses
import json
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

from ..plots import png
from ..progress import Progress
from ..strategy.policies import POLICIES, make_policy
from ..strategy.team import TEAM_POLICIES, make_team_policy
from .episodes import EpisodeConfig, episode_world, run_episode


class EvaluateError(ValueError):
    pass


DEFAULT_POLICIES = "gig,lawnmower,zigzag"
DEFAULT_TEAM_POLICIES = "joint,independent,strips"


def parse_policies(text: str, team: bool = False) -> list[str]:
    names = [p.strip() for p in text.split(",") if p.strip()]
    known = TEAM_POLICIES if team else POLICIES
    if not names:
        raise EvaluateError("--policies: give at least one policy")
    for name in names:
        if name not in known:
            raise EvaluateError(f"--policies: unknown {'team ' if team else ''}policy {name!r} (known: "
                                f"{', '.join(known)}" + ("; --vehicles above 1 runs team policies" if team else "")
                                + ")")
    if len(set(names)) != len(names):
        raise EvaluateError("--policies: a policy is listed twice")
    return names


def override_world(world, kernel: str | None, noise: float | None, survey_alt_m: float | None = None):
    changes: dict[str, object] = {} if survey_alt_m is None else {"survey_alt_m": survey_alt_m}
    if kernel is not None:
        changes["kernel"] = kernel
    if noise is not None:
        changes["noise_k"] = noise
    world = dataclasses.replace(world, **changes)
    world.validate()
    return world


class EpisodeProgress:
    """Episodes done, the policy running and the time to go."""

    def __init__(self, total: int):
        self.progress = Progress(total)
        self.done = 0
        self.t0 = time.monotonic()

    def step(self, policy: str) -> None:
        self.done += 1
        total = self.progress.total
        elapsed = time.monotonic() - self.t0
        eta = elapsed * (total - self.done) / self.done
        self.progress.show(self.done, f"evaluate: {self.done}/{total} episodes ({policy}), {elapsed:.0f} s elapsed, "
                                      f"~{eta:.0f} s to go", milestone=10 * self.done // total)

    def close(self) -> None:
        self.progress.close()


_warm = False


def warm_up() -> None:
    """One throwaway decision per process, so one-time costs are not booked as decision time."""
    global _warm
    if not _warm:
        from ..strategy import Belief, Geometry, Planner
        b = Belief(Geometry(), subcells=3)
        b.update(0.0, 0.0, 20.0, 30.0)
        b.update(5.0, 0.0, 20.5, 30.0)
        Planner(Geometry(), rng=np.random.default_rng(0)).choose(b, (5.0, 0.0))
        _warm = True


def _one(job):
    world, seed, index, name, config, team = job
    warm_up()
    if team is not None:  # (vehicles, start)
        from .team_episodes import run_team_episode
        vehicles, start = team
        return run_team_episode(world, seed, index, make_team_policy(name), vehicles, config, start)
    return run_episode(world, seed, index, make_policy(name), config).to_dict()


def run(world, policies: list[str], episodes: int, seed: int, config: EpisodeConfig, jobs: int = 1,
        progress: EpisodeProgress | None = None, team: tuple | None = None) -> dict[str, list[dict]]:
    """Per policy, the results of episodes 0..episodes-1 (the same worlds for every policy); with
    `team` = (vehicles, start), team episodes of team policies."""
    results: dict[str, list[dict]] = {name: [] for name in policies}
    work = [(world, seed, k, name, config, team) for name in policies for k in range(episodes)]
    if jobs > 1:
        import multiprocessing
        with multiprocessing.get_context("fork").Pool(jobs) as pool:
            for res in pool.imap(_one, work, chunksize=1):
                results[res["policy"]].append(res)
                if progress:
                    progress.step(res["policy"])
    else:
        for job in work:
            res = _one(job)
            results[res["policy"]].append(res)
            if progress:
                progress.step(res["policy"])
    return results


def summarize(rows: list[dict]) -> dict:
    paths = np.array([r["path_m"] for r in rows])
    firsts = [r["first_find_m"] for r in rows if r.get("first_find_m") is not None]
    ok = [r for r in rows if r["success"]]
    decisions = sum(r["decisions"] for r in rows)
    ms_total = sum(r["ms_mean"] * r["decisions"] for r in rows)
    return {
        "episodes": len(rows),
        "success_rate": len(ok) / len(rows) if rows else math.nan,
        "fires_found_rate": (sum(r.get("fires_found", 0) for r in rows) / sum(len(r["fires"]) for r in rows)
                             if rows else math.nan),
        "path_mean_m": float(paths.mean()) if rows else math.nan,
        "path_median_m": float(np.median(paths)) if rows else math.nan,
        "path_p90_m": float(np.percentile(paths, 90)) if rows else math.nan,
        "first_find_mean_m": float(np.mean(firsts)) if firsts else math.nan,
        "error_mean_m": float(np.nanmean([r["error_m"] for r in rows])) if rows else math.nan,
        "false_declarations": sum(r["false_declaration"] for r in rows),
        "forced_declarations": sum(r["forced"] for r in rows),
        "ms_per_decision_mean": ms_total / decisions if decisions else 0.0,
        "ms_per_decision_max": max((r["ms_max"] for r in rows), default=0.0),
    }


T_975 = {k: v for k, v in ((1, 12.71), (2, 4.30), (3, 3.18), (4, 2.78), (5, 2.57), (10, 2.23), (20, 2.09),
                            (30, 2.04), (60, 2.00), (120, 1.98))}  # Student's t, two-sided 95 %


def t_975(dof: int) -> float:
    """Student's t quantile for a two-sided 95 % interval (the nearest tabulated dof at or below)."""
    if dof >= 120:
        return 1.96
    return T_975[max(k for k in T_975 if k <= max(dof, 1))]


def paired_path_differences(results: dict[str, list[dict]], base: str) -> dict[str, dict]:
    """Per other policy: the mean of (its path - base's path) over the same episodes, with a 95 %
    confidence interval from the paired differences (Student's t): the episodes are the same worlds
    for every policy, so pairing removes what the worlds have in common."""
    by_episode = {r["episode"]: r["path_m"] for r in results[base]}
    out = {}
    for name, rows in results.items():
        if name == base:
            continue
        diffs = np.array([r["path_m"] - by_episode[r["episode"]] for r in rows if r["episode"] in by_episode])
        if diffs.size < 2:
            continue
        mean, sd = float(diffs.mean()), float(diffs.std(ddof=1))
        half = t_975(diffs.size - 1) * sd / math.sqrt(diffs.size)
        out[name] = {"episodes": int(diffs.size), "mean_m": mean, "ci95_low_m": mean - half, "ci95_high_m": mean + half}
    return out


def differences_table(diffs: dict[str, dict], base: str) -> str:
    lines = [f"path minus {base}'s on the same episodes, mean [95 % CI]:"]
    for name, d in diffs.items():
        lines.append(f"  {name:<10} {d['mean_m']:>+8.0f} m  [{d['ci95_low_m']:+.0f}, {d['ci95_high_m']:+.0f}]")
    return "\n".join(lines)


def table(summary: dict[str, dict]) -> str:
    head = (f"{'policy':<10} {'success':>7} {'found':>6} {'mean m':>8} {'1st m':>6} {'median m':>8} {'p90 m':>8} {'err m':>6} "
            f"{'false':>5} {'forced':>6} {'ms/dec':>7} {'max ms':>7}")
    lines = [head, "-" * len(head)]
    for name, s in summary.items():
        lines.append(f"{name:<10} {s['success_rate']:>7.3f} {s['fires_found_rate']:>6.3f} {s['path_mean_m']:>8.0f} "
                     f"{s.get('first_find_mean_m', math.nan):>6.0f} "
                     f"{s['path_median_m']:>8.0f} "
                     f"{s['path_p90_m']:>8.0f} {s['error_mean_m']:>6.1f} {s['false_declarations']:>5d} "
                     f"{s['forced_declarations']:>6d} {s['ms_per_decision_mean']:>7.2f} "
                     f"{s['ms_per_decision_max']:>7.1f}")
    return "\n".join(lines)


def plot(results: dict[str, list[dict]], path: Path, title: str) -> None:
    names = list(results)
    data = [[r["path_m"] for r in results[n]] for n in names]
    with png(path, (max(6.0, 1.3 * len(names) + 2), 4.5)) as (fig, ax):
        ax.boxplot(data, showmeans=True, whis=(5, 95))
        ax.set_xticks(range(1, len(names) + 1))
        ax.set_xticklabels([f"{n}\n{100 * np.mean([r['success'] for r in results[n]]):.1f}% ok" for n in names])
        ax.set_ylabel("path length to declaration [m]")
        ax.set_yscale("log")
        ax.set_title(title + "\nbox: quartiles, whiskers: 5-95 %, triangle: mean", fontsize=10)
        ax.grid(axis="y", alpha=0.3)


def told_wind(args, scenario) -> tuple | None:
    """The wind the search is told: the scenario's with --told-wind, calm with --ignore-wind, else
    None (the search estimates it, as it must against an ArduCopter that reports zero wind)."""
    if args.told_wind:
        return tuple(scenario.sim.wind.velocity_ned()[:2])
    return (0.0, 0.0) if args.ignore_wind else None


def evaluate(args) -> int:
    from firefly.sim.scenario import ScenarioError, load_scenario
    if args.flight is not None and args.start != "corner":
        raise EvaluateError("--flight: flown episodes start at home, the area's corner; use --start corner")
    if args.flight is not None and args.ignore_wind:
        raise EvaluateError("--ignore-wind: a flown search estimates the wind, or reads the vehicle's WIND with "
                            "--told-wind; it cannot be flown taking the air as calm")
    if args.flight is not None and args.flight > args.episodes:
        raise EvaluateError(f"--flight {args.flight}: at most --episodes ({args.episodes}) episodes can be flown")
    if args.flight is not None and args.survey_alt is not None:
        raise EvaluateError("--survey-alt: flown episodes survey at the scenario's height")
    vehicles = args.vehicles
    team = (vehicles, args.start) if vehicles > 1 else None
    if team is None and args.start == "spread":
        raise EvaluateError("--start spread: one vehicle per corner needs --vehicles above 1")
    if team is not None and args.start == "centre":
        raise EvaluateError("--start centre: a team starts at the corner or spread over the corners")
    if team is not None and args.sensor != "point":
        raise EvaluateError("--sensor camera: team episodes carry the point sensor only")
    if team is not None and (args.fires > 1 or (args.max_fires or 1) > 1):
        raise EvaluateError("--fires/--max-fires: a team searches for one fire")
    policies = parse_policies(args.policies or (DEFAULT_TEAM_POLICIES if team else DEFAULT_POLICIES), team is not None)
    try:
        scenario = load_scenario(args.scenario)
        if args.flight is not None:
            from ..flight.autopilot_process import check_scenario
            check_scenario(args.scenario)  # the vehicle's tables too, before the episodes run
    except ScenarioError as exc:
        raise EvaluateError(str(exc)) from None
    try:
        world = override_world(scenario.world, args.kernel, args.noise, args.survey_alt)
    except ValueError as exc:
        raise EvaluateError(str(exc)) from None
    seed = scenario.seed if args.seed is None else args.seed
    try:
        config = EpisodeConfig(start="corner" if team else args.start, threshold=args.threshold, budget_m=args.budget,
                               fixed_fire=args.fixed_fire, speed_m_s=args.speed, subcells=args.subcells,
                               confirm_m=None if args.no_confirm else args.confirm, outlier_rate=args.outlier_rate,
                               wind_ne_m_s=told_wind(args, scenario), air_ne_m_s=scenario.sim.wind.velocity_ned()[:2],
                               fires=args.fires, max_fires=(args.max_fires or 1) if team else args.max_fires,
                               fire_spacing_m=args.fire_spacing, further_prior=args.further_prior,
                               clear_threshold=args.clear, sensor=args.sensor)
        episode_world(world, seed, 0, config)  # a world that cannot be drawn fails here, in one line
    except ValueError as exc:
        raise EvaluateError(f"--fire-spacing/--fires: {exc}" if args.fire_spacing else str(exc)) from None
    jobs = args.jobs or 1
    progress = EpisodeProgress(len(policies) * args.episodes)
    t0 = time.monotonic()
    results = run(world, policies, args.episodes, seed, config, jobs, progress, team)
    progress.close()
    summary = {name: summarize(rows) for name, rows in results.items()}
    title = (f"{args.scenario.name}: kernel {world.kernel}, noise {world.noise_k:g} K, survey at {world.survey_alt_m:g} m, "
             + (f"{vehicles} vehicles, " if team else "") + f"{args.sensor} sensor, {args.start} start, "
             f"{args.episodes} episodes, seed {seed}" + (f", {args.fires} fires each" if args.fires > 1 else "")
             + (f" {args.fire_spacing:g} m apart" if args.fire_spacing else "")
             + (", not told how many fires" if config.max_fires is None
                else f", looking for up to {config.max_fires}" if config.max_fires > 1 else ""))
    print(title)
    print(table(summary))
    diffs = paired_path_differences(results, policies[0]) if len(policies) > 1 else {}
    if diffs:
        print(differences_table(diffs, policies[0]))
    confirm = "off" if config.confirm_m is None else f"within {config.confirm_m:g} m"
    print(f"({time.monotonic() - t0:.0f} s, {jobs} job{'s' if jobs > 1 else ''}; declare at 3x3 mass >= "
          f"{config.threshold:g}, confirmation {confirm}, budget {config.budget_m:g} m; success = declared cell "
          f"within one cell of a fire; false = confident but wrong; forced = declared without a confident belief)")
    flights = fly(args, world, seed, config, policies[0], results[policies[0]]) if args.flight else None
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        payload = {"scenario": str(args.scenario), "seed": seed, "episodes": args.episodes, "start": args.start,
                   "kernel": world.kernel, "noise_k": world.noise_k, "config": dataclasses.asdict(config),
                   "jobs": jobs, "cpus": os.cpu_count(), "summary": summary,
                   "paired_path_differences": {"base": policies[0], "policies": diffs}, "results": results}
        if flights is not None:
            payload["flights"] = flights
        args.json.write_text(json.dumps(payload, indent=1))
        print(f"results: {args.json}")
    if args.plot:
        plot(results, args.plot, title)
        print(f"plot: {args.plot}")
    return 0


def fly(args, world, seed: int, config: EpisodeConfig, policy: str, decided: list[dict]) -> dict:
    """The first K episodes flown through the real autopilot with the first policy listed."""
    import tomllib
    from . import flown_episodes
    base = tomllib.loads(args.scenario.read_text())  # checked by load_scenario and the autopilot
    print(f"flying episodes 0..{args.flight - 1} with {policy}"
          + (f" ({args.vehicles} vehicles)" if args.vehicles > 1 else "") + " through the autopilot at speedup "
          f"{args.flight_speedup:g}", flush=True)
    flown = []
    for k in range(args.flight):
        plot = args.flight_plots / f"flight_{k}.png" if args.flight_plots else None
        flown.append(flown_episodes.fly_episode(base, world, seed, k, policy, config, args.flight_speedup, plot,
                                                args.vehicles, told_wind=args.told_wind))
        r = flown[-1]
        state = (f"path {r['path_m']:.0f} m, error {r['error_m']:.1f} m, {r['survey_wall_s']:.1f} s wall"
                 if r["flown"] else f"not flown: {r['why']}")
        print(f"flight {k + 1}/{args.flight}: {state}", file=sys.stderr, flush=True)
    print(flown_episodes.table(flown, decided))
    summary = flown_episodes.summarize(flown)
    print(f"flown: success {summary['success_rate']:.2f}, mean path {summary['path_mean_m']:.0f} m, "
          f"landed at home {summary['landed_home_rate']:.2f} ({summary['flown']}/{summary['episodes']} flown; "
          f"ok = declared cell within one cell of the fire, home m = landed distance from home"
          + (", the farthest vehicle's; path = the slowest vehicle's" if args.vehicles > 1 else "") + ")")
    return {"policy": policy, "speedup": args.flight_speedup, "summary": summary, "episodes": flown}

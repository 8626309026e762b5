"""`groundstation evaluate --flight K`: the first K decision-level episodes flown end to end.

Each episode's world (its fire, strength and ambient, from episodes.py) is written as a
scenario file, a real `autopilot` process is started on it at the given speedup, and
`groundstation explore` flies the policy over MAVLink exactly as `make run` does, its search
controller configured as the decision-level episodes' (`--threshold`, `--confirm`, `--no-confirm`,
`--budget`, `--subcells`, `--speed` as the survey speed, and `--sensor`: with the camera the vehicle
is fitted with the thermal camera and the companion reads its stills through MAVLink). The flown result sits beside the
decision-level result of the same episode, so one can see whether the figures of the cheap
simulation hold when a vehicle with real dynamics, a real link and a 10 Hz sensor flies it. The
flight's sensor noise comes from the autopilot's own seeded stream, so the two runs see the same
fire but not the same noise samples.
"""
from __future__ import annotations

import json
import math
import tempfile
from pathlib import Path

from firefly.sim.fire import WORLD_KEYS, FireWorld

from ..flight.autopilot_process import AutopilotExited, run_flight, run_team_flight
from ..flight.explore import camera_options, explore
from ..flight.team_explore import explore_team
from ..flight.vehicle_link import LinkError
from .episodes import EpisodeConfig, episode_world, fires_found, judge_all


def scenario_text(base: dict, seed: int, world: FireWorld) -> str:
    """The scenario file (sim/scenario.py's format) of one episode: the original scenario's
    tables (home, airframe, wind, noise, faults, ...) with the episode's seed, world and fires. A
    [script] is left out: the companion flies the vehicle."""
    tables = {k: v for k, v in base.items() if k not in ("seed", "world", "fire", "script")}
    tables["seed"] = seed
    # a plume leaned by the wind (plume_rise_m_s) is written as that, not also as the lean it makes
    made_by_wind = ("wind_tilt", "wind_to_deg") if world.plume_rise_m_s > 0 else ()
    tables["world"] = {name: getattr(world, name) for name in sorted(WORLD_KEYS) if name not in made_by_wind}
    tables["fire"] = [{"n_m": f.n_m, "e_m": f.e_m, "strength_k": f.strength_k, "growth_k_per_s": f.growth_k_per_s}
                      for f in world.fires]
    return toml_text(tables)


def toml_text(tables: dict) -> str:
    """A TOML document of scalars, tables and arrays of tables (JSON's literals are TOML's too)."""
    lines = [f"{k} = {json.dumps(v)}" for k, v in tables.items() if not isinstance(v, (dict, list))]
    for name, table in tables.items():
        if isinstance(table, dict):
            lines += ["", f"[{name}]", *(f"{k} = {json.dumps(v)}" for k, v in table.items())]
    for name, array in tables.items():
        if isinstance(array, list):
            for table in array:
                lines += ["", f"[[{name}]]", *(f"{k} = {json.dumps(v)}" for k, v in table.items())]
    return "\n".join(lines) + "\n"


def fly_episode(base: dict, world: FireWorld, seed: int, index: int, policy: str, config: EpisodeConfig,
                speedup: float, plot: Path | None, vehicles: int = 1, told_wind: bool = False) -> dict:
    """Episode `index` of `world` flown on the scenario `base` (its TOML tables), by the search
    controller with the episodes' own settings (threshold, confirmation, budget, sub-cells, speed);
    with vehicles > 1 by that many vehicles of one autopilot process and the team controller. The
    search estimates the wind from the vehicle's lean, or with told_wind reads the vehicle's WIND
    (zero unless the scenario's [params] turn on drag fusion, as ArduCopter's)."""
    world = episode_world(world, seed, index, config)
    row = {"episode": index, "policy": policy, "fire": [(f.n_m, f.e_m, f.strength_k) for f in world.fires]}
    quiet = lambda text: None  # noqa: E731
    with tempfile.TemporaryDirectory(prefix="firefly-flight-") as tmp:
        path = Path(tmp) / f"episode_{index}.toml"
        path.write_text(scenario_text(base, seed + index, world))
        try:
            if vehicles > 1:
                result = run_team_flight(lambda urls: explore_team(urls, world, policy, plot, True, config, say=quiet),
                                         None, speedup, path, say=quiet, count=vehicles)
            else:
                result = run_flight(lambda url: explore(url, world, policy, plot, truth=True, config=config, say=quiet,
                                                        told_wind=told_wind, sensor=config.sensor),
                                    None, speedup, path, say=quiet, extra=camera_options(config.sensor))
        except (LinkError, AutopilotExited) as exc:
            return row | {"flown": False, "why": str(exc)}
    if vehicles > 1:
        return row | team_row(world, result)
    declared = [(f["n_m"], f["e_m"]) for f in result["fires"]]
    error, within, _ = judge_all(world, declared)
    return row | {"flown": True, "declared": (result["declared_n_m"], result["declared_e_m"]),
                  "declarations": declared, "fires_found": fires_found(world, declared),
                  "path_m": result["path_m"], "error_m": error, "success": within,
                  "forced": result["forced"], "landed_from_home_m": result["landed_from_home_m"],
                  "survey_vehicle_s": result["survey_vehicle_s"], "survey_wall_s": result["survey_wall_s"],
                  "wind_estimate_ne_m_s": result.get("wind_estimate_ne_m_s"), "plot": result.get("plot"),
                  "first_find_path_m": result.get("first_find_path_m"), "sensor": config.sensor,
                  "decision_ms_mean": result["decision_ms_mean"], "decision_ms_max": result["decision_ms_max"],
                  **{k: v for k, v in result.items() if k.startswith("frame")}}


def team_row(world: FireWorld, result: dict) -> dict:
    """A team flight's row: its path is the slowest vehicle's, and it landed at home only if every
    vehicle did (a vehicle that left the search did not)."""
    declared = (result["declared_n_m"], result["declared_e_m"])
    error, within, _ = judge_all(world, [declared])
    landed = [math.inf if d is None else d for d in result["landed_from_home_m"]]
    return {"flown": True, "declared": declared, "declarations": [declared], "fires_found": int(bool(within)),
            "path_m": result["path_m"], "paths_m": result["paths_m"], "team_path_m": result["team_path_m"],
            "error_m": error, "success": within, "forced": result["forced"], "landed_from_home_m": max(landed),
            "landed_each_m": result["landed_from_home_m"], "dropped": result["dropped"],
            "survey_vehicle_s": result["survey_vehicle_s"], "survey_wall_s": result["survey_wall_s"],
            "plot": result.get("plot")}


def table(flown: list[dict], decided: list[dict]) -> str:
    by_episode = {r["episode"]: r for r in decided}
    head = (f"{'episode':>7} {'fire N,E':>13} | {'decided: path m':>15} {'err m':>6} {'ok':>3} | "
            f"{'flown: path m':>13} {'err m':>6} {'ok':>3} {'home m':>6} {'vehicle s':>9} {'wall s':>6}")
    lines = [head, "-" * len(head)]
    for r in flown:
        d = by_episode.get(r["episode"], {})
        fire = f"{r['fire'][0][0]:.0f},{r['fire'][0][1]:.0f}" if r["fire"] else "-"
        left = (f"{r['episode']:>7} {fire:>13} | {d.get('path_m', math.nan):>15.0f} "
                f"{d.get('error_m', math.nan):>6.1f} {'yes' if d.get('success') else 'no':>3} | ")
        if not r["flown"]:
            lines.append(left + f"not flown: {r['why']}")
            continue
        lines.append(left + f"{r['path_m']:>13.0f} {r['error_m']:>6.1f} {'yes' if r['success'] else 'no':>3} "
                            f"{r['landed_from_home_m']:>6.1f} {r['survey_vehicle_s']:>9.0f} {r['survey_wall_s']:>6.1f}")
    return "\n".join(lines)


def summarize(flown: list[dict]) -> dict:
    done = [r for r in flown if r["flown"]]
    return {
        "episodes": len(flown),
        "flown": len(done),
        "success_rate": sum(r["success"] for r in done) / len(flown) if flown else math.nan,
        "path_mean_m": sum(r["path_m"] for r in done) / len(done) if done else math.nan,
        "landed_home_rate": sum(r["landed_from_home_m"] < 5.0 for r in done) / len(flown) if flown else math.nan,
        "vehicle_s_mean": sum(r["survey_vehicle_s"] for r in done) / len(done) if done else math.nan,
        "wall_s_mean": sum(r["survey_wall_s"] for r in done) / len(done) if done else math.nan,
        **({"frames_mean": sum(r["frames"] for r in done) / len(done)} if done and "frames" in done[0] else {}),
    }

"""Decision-level team episodes: k vehicles search one episode's world together (strategy/team.py).

The world, the sensor and the motion are those of the one-vehicle episodes (episodes.py): each
vehicle flies straight at the survey speed toward its target and reads once per sample interval
(and on arriving), at its own survey height. All vehicles move at once; the time to declaration is
the longest of the vehicles' own clocks (the slowest vehicle's path over the speed), and the team's
distance is the sum of their paths. Starts: "corner" puts every vehicle at the area's corner (0, 0)
(they fly at separated heights), "spread" one at each corner in turn. With one vehicle and the
joint policy an episode is exactly the one-vehicle gig episode.
"""
from __future__ import annotations

import math
import time

import numpy as np

from firefly.sim.fire import FireWorld, TemperatureSensor

from ..strategy.belief import Geometry
from ..strategy.stopping import Declaration
from ..strategy.team import TeamController, TeamPolicy, survey_heights
from .episodes import EpisodeConfig, episode_world, judge_all, policy_rng

TEAM_STARTS = ("corner", "spread")


def team_starts(geometry: Geometry, k: int, start: str) -> list[tuple[float, float]]:
    a = geometry.area_m
    if start == "corner":
        return [(0.0, 0.0)] * k
    corners = [(0.0, 0.0), (0.0, a), (a, 0.0), (a, a)]
    return [corners[i % 4] for i in range(k)]


def team_wind(config: EpisodeConfig) -> tuple:
    """The wind a team is told: it does not estimate one yet, so unless told otherwise it is told
    the wind that blows (a vehicle fusing drag would report it)."""
    return config.air_ne_m_s if config.wind_ne_m_s is None else config.wind_ne_m_s


def run_team_episode(world: FireWorld, seed: int, index: int, policy: TeamPolicy, k: int,
                     config: EpisodeConfig = EpisodeConfig(), start: str = "corner",
                     fail: tuple | None = None) -> dict:
    """One team episode; `fail` = (vehicle, after_s): that vehicle drops out after_s into the search."""
    ep_world = episode_world(world, seed, index, config)
    geometry = Geometry.from_world(ep_world)
    sensor = TemperatureSensor(ep_world, seed=(seed * 1_000_003 + index) & 0xFFFFFFFF)
    heights = survey_heights(geometry, k)
    pos = team_starts(geometry, k, start)
    team = TeamController(geometry, policy, config, pos, policy_rng(seed, index), time.perf_counter,
                          wind_ne_m_s=team_wind(config))
    step_m = config.observation_spacing_m
    clock = [0.0] * k
    paths = [0.0] * k
    arrived = [False] * k
    while True:
        for i in range(k):
            if team.active[i]:
                team.observe(i, pos[i][0], pos[i][1], sensor.read(pos[i][0], pos[i][1], heights[i], clock[i]),
                             heights[i])
        if fail is not None and team.active[fail[0]] and max(clock) >= fail[1]:
            team.drop(fail[0])
        move = team.step(pos, paths, arrived)
        if isinstance(move, Declaration):
            break
        for i, goto in enumerate(move):
            if goto is None:
                continue
            dn, de = goto.target[0] - pos[i][0], goto.target[1] - pos[i][1]
            d = math.hypot(dn, de)
            arrived[i] = d <= step_m
            if arrived[i]:
                pos[i] = goto.target
                paths[i] += d
                clock[i] += d / config.speed_m_s if d > 0 else config.sample_s
            else:
                pos[i] = (pos[i][0] + dn * step_m / d, pos[i][1] + de * step_m / d)
                paths[i] += step_m
                clock[i] += config.sample_s
    error, success, on_fire = judge_all(ep_world, [move.position])
    ms = [1000.0 * x for x in team.decision_s]
    return {"policy": policy.name, "vehicles": k, "start": start, "episode": index, "seed": seed,
            "kernel": ep_world.kernel, "fires": [(f.n_m, f.e_m, f.strength_k) for f in ep_world.fires],
            "time_s": max(clock), "team_path_m": sum(paths), "paths_m": paths,
            "path_m": max(paths),  # the slowest vehicle's: what the time to declaration is made of
            "fires_found": int(bool(success)), "declared": move.position,
            "declared_cell": move.index, "error_m": error, "success": bool(success), "forced": move.forced,
            "declared_by": team.finished_by, "false_declaration": bool(move.reason == "confident" and not on_fire[0]),
            "decisions": team.decisions, "ms_mean": float(np.mean(ms)) if ms else 0.0,
            "ms_max": float(np.max(ms)) if ms else 0.0, "dropped": [i for i in range(k) if not team.active[i]]}

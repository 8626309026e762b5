"""Running one task wherever a worker is: a pure function of (campaign, task), so a local pool
process and a Ray worker on another machine run exactly the same code. A flown episode starts its
own autopilot on free ports of the machine it runs on."""
from __future__ import annotations

import time

from .spec import Campaign, Task


class EpisodeFailed(RuntimeError):
    """The episode could not be run (a flight that never flew): retried, then recorded as failed."""


def run_task(campaign: Campaign, task: Task) -> dict:
    """The episode's result (the same fields `evaluate` reports) and its wall time."""
    from ..evaluation.episodes import run_episode
    from ..evaluation.evaluate import warm_up
    from ..strategy.policies import make_policy
    tables, world, config = campaign.setup(task.condition)
    t0 = time.monotonic()
    if task.condition.team is not None:
        from ..evaluation.team_episodes import run_team_episode
        from ..strategy.team import make_team_policy
        warm_up()
        vehicles, start = task.condition.team
        result = run_team_episode(world, campaign.seed, task.episode, make_team_policy(task.policy), vehicles,
                                  config, start)
    elif not task.flown:
        warm_up()
        result = run_episode(world, campaign.seed, task.episode, make_policy(task.policy), config).to_dict()
    else:
        from ..evaluation.flown_episodes import fly_episode
        quiet_mavsdk()
        result = fly_episode(tables, world, campaign.seed, task.episode, task.policy, config, campaign.speedup, None)
        if not result["flown"]:
            raise EpisodeFailed(result["why"])
    return {"result": result, "wall_s": time.monotonic() - t0}


_quiet = False


def quiet_mavsdk() -> None:
    """Once per worker process: MAVSDK's own log lines would bury the progress bar."""
    global _quiet
    if not _quiet:
        from ..flight.mavsdk_logs import quiet_mavsdk_logs
        quiet_mavsdk_logs()
        _quiet = True

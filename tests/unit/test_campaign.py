"""Campaigns without flying: the file checked in one line per mistake, the results file that
resumes and refuses another campaign's, and the local pool's retries when a worker dies."""
from __future__ import annotations

import json
import re
import os
import signal
from pathlib import Path

import pytest

from firefly.groundstation.campaign.pool import run_local
from firefly.groundstation.campaign.spec import CampaignError, load_campaign
from firefly.groundstation.campaign.store import ResultStore

REPO = Path(__file__).resolve().parents[2]
SCENARIO = REPO / "scenarios" / "default.toml"
GOOD = f"""
[campaign]
scenario = "{SCENARIO}"
policies = ["greedy", "lawnmower"]
episodes = 3
flown = 1
seed = 4
[sweep.world]
noise_k = [1.0, 3.0]
[sweep.search]
threshold = [0.9, 0.99]
"""


def campaign_file(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "c.toml"
    path.write_text(text)
    return path


def test_a_campaign_is_every_combination_of_its_sweep(tmp_path):
    c = load_campaign(campaign_file(tmp_path, GOOD))
    assert [cond.label for cond in c.conditions()] == [
        "noise_k=1.0, threshold=0.9", "noise_k=1.0, threshold=0.99", "noise_k=3.0, threshold=0.9",
        "noise_k=3.0, threshold=0.99"]
    tasks = c.tasks()
    assert len(tasks) == 4 * 2 * (3 + 1) and len({t.id for t in tasks}) == len(tasks)
    assert sum(t.flown for t in tasks) == 8 and c.name == "c" and c.seed == 4
    _, world, config = c.setup(c.conditions()[3])
    assert world.noise_k == 3.0 and config.threshold == 0.99
    # The fingerprint follows what decides outcomes, not the file's name.
    other = load_campaign(campaign_file(tmp_path, GOOD.replace("episodes = 3", "episodes = 4")))
    assert other.fingerprint != c.fingerprint
    assert load_campaign(campaign_file(tmp_path, GOOD)).fingerprint == c.fingerprint


@pytest.mark.parametrize("change, says", [
    (("[campaign]", "[campaign]\nepisodez = 3"), "[campaign]: unknown key 'episodez'"),
    (("episodes = 3", "episodes = 0"), "[campaign] episodes: expected a whole number >= 1"),
    (("flown = 1", "flown = 9"), "[campaign] flown: at most episodes (3) can be flown"),
    (('"greedy", "lawnmower"', '"greedy", "nosuch"'), "[campaign] policies: unknown policy 'nosuch'"),
    (("noise_k = [1.0, 3.0]", "noise_k = []"), "[sweep.world] noise_k: an empty list sweeps nothing"),
    (("noise_k = [1.0, 3.0]", "noize_k = [1.0]"), "[sweep.world]: unknown key 'noize_k'"),
    (("noise_k = [1.0, 3.0]", "noise_k = 1.0"), "[sweep.world] noise_k: expected a list"),
    (("[sweep.world]", "[sweep.weather]"), "[sweep]: unknown table 'weather'"),
    (("noise_k = [1.0, 3.0]", "noise_k = [-1.0]"), "noise_k=-1.0"),
    (("threshold = [0.9, 0.99]", 'start = ["centre"]'), "[sweep.search] start: flown episodes start at home"),
    (("seed = 4", "seed = 4\n[other]"), "unknown table [other]"),
])
def test_a_bad_campaign_file_is_one_line_naming_table_and_key(tmp_path, change, says):
    path = campaign_file(tmp_path, GOOD.replace(*change))
    with pytest.raises(CampaignError) as caught:
        load_campaign(path)
    text = str(caught.value)
    assert says in text and "\n" not in text and str(path) in text


def test_a_missing_scenario_or_file_is_named(tmp_path):
    with pytest.raises(CampaignError, match="no such file"):
        load_campaign(tmp_path / "none.toml")
    with pytest.raises(CampaignError, match=r"\[campaign\] scenario"):
        load_campaign(campaign_file(tmp_path, GOOD.replace(str(SCENARIO), str(tmp_path / "nowhere.toml"))))


def test_results_resume_and_refuse_another_campaigns_file(tmp_path):
    c = load_campaign(campaign_file(tmp_path, GOOD))
    tasks = c.tasks()
    path = tmp_path / "results.jsonl"
    store = ResultStore(path, c, resume=False)
    store.add(tasks[0], True, {"result": {"path_m": 1.0}, "wall_s": 0.1}, 1)
    store.add(tasks[1], False, "EpisodeFailed: no flight", 2)
    store.close()
    with open(path, "a") as f:
        f.write('{"id": "half a li')  # a kill in the middle of a line
    with pytest.raises(CampaignError, match="already holds results: --resume"):
        ResultStore(path, c, resume=False)
    again = ResultStore(path, c, resume=True)
    assert set(again.records) == {tasks[0].id, tasks[1].id}
    assert again.records[tasks[1].id]["status"] == "failed" and again.records[tasks[1].id]["attempts"] == 2
    again.close()
    assert path.read_text().endswith("\n"), "the cut line is dropped"
    first = json.loads(path.read_text().splitlines()[1])
    assert first["condition"] == {"world.noise_k": 1.0, "search.threshold": 0.9} and first["seed"] == 4
    assert {"policy", "episode", "flown", "version"} <= set(first)
    other = load_campaign(campaign_file(tmp_path, GOOD.replace("episodes = 3", "episodes = 5")))
    with pytest.raises(CampaignError, match="holds campaign 'c' .*not this one"):
        ResultStore(path, other, resume=True)
    a_file = tmp_path / "a-file"
    a_file.write_text("not a directory")
    with pytest.raises(CampaignError, match=re.escape(f"--out: {a_file} is a file, not a directory")):
        ResultStore(a_file / "results.jsonl", c, resume=False)


def _dies_once(payload):
    """A task that kills its own worker the first time it runs (a marker file says it has)."""
    marker, value = payload
    if value == "die" and not Path(marker).exists():
        Path(marker).write_text("died once")
        os.kill(os.getpid(), signal.SIGKILL)
    if value == "always fails":
        raise RuntimeError("this task cannot succeed")
    if value == "always dies":
        os.kill(os.getpid(), signal.SIGKILL)
    return value


def test_the_pool_reruns_what_a_dead_worker_held_and_records_twice_failed_tasks(tmp_path):
    marker = str(tmp_path / "marker")
    jobs = [(k, (marker, v)) for k, v in enumerate(["a", "die", "b", "always fails", "c", "always dies", "d"])]
    done = {}
    run_local(jobs, _dies_once, lambda key, ok, value, attempts: done.setdefault(key, []).append((ok, value, attempts)),
              workers=2)
    assert sorted(done) == list(range(7)) and all(len(v) == 1 for v in done.values()), "each task once"
    assert done[1] == [(True, "die", 2)], "the killed worker's task ran again, on a fresh worker"
    assert [done[k][0][1] for k in (0, 2, 4, 6)] == ["a", "b", "c", "d"]
    ok, error, attempts = done[3][0]
    assert not ok and attempts == 2 and error.startswith("RuntimeError: this task cannot succeed")
    ok, error, attempts = done[5][0]
    assert not ok and attempts == 2 and "worker running it died (exit code -9)" in error


TEAM = f"""
[campaign]
scenario = "{SCENARIO}"
policies = ["joint", "strips"]
episodes = 2
[sweep.team]
vehicles = [1, 3]
start = ["spread"]
"""


def test_a_team_sweep_runs_team_policies_decided_only(tmp_path):
    c = load_campaign(campaign_file(tmp_path, TEAM))
    assert [cond.team for cond in c.conditions()] == [(1, "spread"), (3, "spread")]
    from firefly.groundstation.campaign.tasks import run_task
    task = next(t for t in c.tasks() if t.condition.team == (3, "spread") and t.policy == "joint")
    result = run_task(c, task)["result"]
    assert result["vehicles"] == 3 and len(result["paths_m"]) == 3 and result["success"]
    for change, says in [(('"joint", "strips"', '"gig"'), "unknown team policy 'gig'"),
                         (("episodes = 2", "episodes = 2\nflown = 1"), "team episodes are decided only"),
                         (("vehicles = [1, 3]", "vehicles = [0]"), "[sweep.team] vehicles: expected whole numbers"),
                         (('start = ["spread"]', 'start = ["middle"]'), "[sweep.team] start"),
                         (('vehicles = [1, 3]\nstart = ["spread"]', ''), "[sweep.team]: sweeps nothing"),
                         (('[sweep.team]', '[sweep.search]\nstart = ["corner"]\n[sweep.team]'),
                          "[sweep.search] start: a team's starts are [sweep.team] start")]:
        with pytest.raises(CampaignError, match=re.escape(says)):
            load_campaign(campaign_file(tmp_path, TEAM.replace(*change)))

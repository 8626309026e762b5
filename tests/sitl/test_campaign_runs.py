"""Campaigns end to end: the `groundstation campaign` command on the local pool and on a local
Ray, flying real autopilots; a worker killed mid-campaign and a whole campaign interrupted, then
resumed, end with every episode recorded exactly once."""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from firefly.groundstation.campaign.spec import load_campaign

pytestmark = [pytest.mark.sitl, pytest.mark.serial]  # two campaign workers keep both cores busy
REPO = Path(__file__).resolve().parents[2]
CAMPAIGN_WALL_S = 600
SMALL_WORLD = REPO / "tests" / "sitl" / "data" / "small_world.toml"


def campaign_command(campaign: Path, out: Path, *args: str) -> list[str]:
    return [sys.executable, "-m", "firefly.groundstation", "campaign", str(campaign), "--out", str(out), *args]


def records(out: Path) -> list[dict]:
    """The task records of a results file (its header line left out)."""
    path = out / "results.jsonl"
    if not path.exists():
        return []
    lines = path.read_text().splitlines()
    return [json.loads(line) for line in lines[1:] if line.endswith("}")]


def check_complete(campaign_file: Path, out: Path) -> list[dict]:
    """Every task of the campaign recorded exactly once, and all of them succeeded."""
    campaign = load_campaign(campaign_file)
    rows = records(out)
    ids = [r["id"] for r in rows]
    assert len(ids) == len(set(ids)), "a task is recorded twice"
    assert set(ids) == {t.id for t in campaign.tasks()}, "a task is missing"
    failed = [r for r in rows if r["status"] != "ok"]
    assert not failed, failed[:3]
    return rows


def test_the_example_campaign_is_two_conditions_two_policies_fifty_decided_five_flown():
    campaign = load_campaign(REPO / "campaigns" / "noise.toml")
    tasks = list(campaign.tasks())
    assert len(tasks) == 2 * 2 * (50 + 5) and sum(t.flown for t in tasks) == 2 * 2 * 5


def example_campaign_scaled(tmp_path: Path, episodes: int, flown: int) -> Path:
    """campaigns/noise.toml with fewer episodes per cell: the same grid, policies and world."""
    text = (REPO / "campaigns" / "noise.toml").read_text()
    scaled = text.replace("episodes = 50", f"episodes = {episodes}").replace("flown = 5", f"flown = {flown}")
    scaled = scaled.replace('"../scenarios/default.toml"', f'"{REPO / "scenarios" / "default.toml"}"')
    assert scaled.count(f"episodes = {episodes}") == 1 and scaled.count(f"flown = {flown}") == 1
    path = tmp_path / "noise.toml"
    path.write_text(scaled)
    return path


# The example's grid, fewer episodes per cell (the whole example is 3-6 minutes of make test's
# 30), on the local pool only: Ray's campaigns are flown end to end, real autopilots and
# records, by the killed-worker test.
def test_two_conditions_two_policies_decided_and_flown_per_cell(tmp_path):
    campaign = example_campaign_scaled(tmp_path, episodes=6, flown=2)
    out = tmp_path / "out"
    done = subprocess.run(campaign_command(campaign, out, "--jobs", "2"), cwd=REPO,
                          capture_output=True, text=True, timeout=CAMPAIGN_WALL_S)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    rows = check_complete(campaign, out)
    assert len(rows) == 2 * 2 * (6 + 2)
    flown = [r for r in rows if r["flown"]]
    assert len(flown) == 8 and all(r["result"]["flown"] for r in flown)
    assert sum(r["result"]["success"] for r in flown) >= 6, "flown searches mostly find the fire"
    report = (out / "report.md").read_text()
    assert report.count("| greedy |") == 2 and report.count("| lawnmower |") == 2
    assert (out / "world_noise_k.png").stat().st_size > 10_000
    cells = json.loads((out / "report.json").read_text())["cells"]
    assert [c["episodes"] for c in cells] == [6] * 4 and [c["flown_episodes"] for c in cells] == [2] * 4


SMALL = """
[campaign]
scenario = "{scenario}"
policies = ["greedy"]
episodes = {episodes}
flown = {flown}
speedup = 20
seed = 3
[sweep.world]
noise_k = [1.0, 2.0]
"""


def small_campaign(tmp_path: Path, episodes: int, flown: int) -> Path:
    """On the explore tests' 200 m world: its episodes, decided or flown, take a quarter of the
    default world's time, and killing, retrying and resuming do not depend on the world."""
    path = tmp_path / "small.toml"
    path.write_text(SMALL.format(scenario=SMALL_WORLD, episodes=episodes, flown=flown))
    return path


def start(campaign: Path, out: Path, *args: str) -> subprocess.Popen:
    return subprocess.Popen(campaign_command(campaign, out, "--jobs", "2", *args), cwd=REPO,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


def children(pid: int) -> list[int]:
    found = []
    for proc in Path("/proc").iterdir():
        if proc.name.isdigit():
            try:
                fields = (proc / "stat").read_text().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[1]) == pid and fields[0] != "Z":
                found.append(int(proc.name))
    return found


def wait_for(condition, timeout: float, what: str, process: subprocess.Popen):
    deadline = time.monotonic() + timeout
    while not (value := condition()):
        assert process.poll() is None, f"the campaign ended before {what}"
        assert time.monotonic() < deadline, f"timed out after {timeout:g} s waiting for {what}"
        time.sleep(0.05)
    return value


def cmdline(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
    except OSError:
        return ""


def flying_workers(campaign_pid: int, ray: bool) -> list[int]:
    """Workers flying an autopilot: the pool's workers are the campaign's children; Ray's are
    processes titled ray::work (Ray names a worker after the task it runs)."""
    if ray:
        workers = [int(p.name) for p in Path("/proc").iterdir()
                   if p.name.isdigit() and cmdline(int(p.name)).startswith("ray::work")]
    else:
        workers = children(campaign_pid)
    return [w for w in workers if any(flies(c) for c in children(w))]


def flies(pid: int) -> bool:
    """An autopilot started cold, or a warm-start server (groundstation/flight/warm_start.py) with
    a vehicle forked from it (whose command line is the server's)."""
    line = cmdline(pid)
    return "-m firefly.autopilot" in line or ("flight.warm_start" in line and bool(children(pid)))


@pytest.mark.parametrize("backend", [(), ("--ray",)], ids=["local-pool", "local-ray"])
def test_a_worker_killed_mid_flight_is_retried_and_every_episode_is_recorded_once(tmp_path, backend):
    campaign = small_campaign(tmp_path, episodes=10, flown=2)
    out = tmp_path / "out"
    proc = start(campaign, out, *backend)
    try:
        # Decided episodes come first; once they are all in, the workers are flying.
        wait_for(lambda: len(records(out)) >= 20, 120, "the decided episodes", proc)
        worker = wait_for(lambda: flying_workers(proc.pid, bool(backend)), 60, "a worker flying an autopilot",
                          proc)[0]
        os.kill(worker, signal.SIGKILL)
        output, _ = proc.communicate(timeout=CAMPAIGN_WALL_S)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 0, output[-2000:]
    rows = check_complete(campaign, out)
    if not backend:  # the pool knows which task the dead worker held (Ray retries without saying so)
        retried = [r for r in rows if r["attempts"] == 2]
        assert len(retried) == 1 and retried[0]["flown"], "the killed worker's flight ran again"


def test_an_interrupted_campaign_resumes_to_every_episode_exactly_once(tmp_path):
    # 34 tasks: decided ones take under a second of a worker each on the small world, so the
    # interrupt after ten leaves some 20 to resume (40 episodes took two minutes of make test
    # for no more coverage)
    campaign = small_campaign(tmp_path, episodes=16, flown=1)
    out = tmp_path / "out"
    proc = start(campaign, out)
    try:
        wait_for(lambda: len(records(out)) >= 10, 120, "ten episodes", proc)
        proc.send_signal(signal.SIGINT)
        output, _ = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130 and "run again with --resume" in output, output[-2000:]
    before = len(records(out))
    assert 10 <= before < 34
    again = subprocess.run(campaign_command(campaign, out, "--jobs", "2", "--resume"), cwd=REPO,
                           capture_output=True, text=True, timeout=CAMPAIGN_WALL_S)
    assert again.returncode == 0, again.stdout[-2000:] + again.stderr[-2000:]
    assert f"({before} already recorded)" in again.stdout
    check_complete(campaign, out)
    # A results file of another campaign is refused, in one line.
    (tmp_path / "other").mkdir()
    other = small_campaign(tmp_path / "other", episodes=5, flown=0)
    refused = subprocess.run(campaign_command(other, out, "--resume"), cwd=REPO, capture_output=True, text=True,
                             timeout=60)
    assert refused.returncode == 2 and "not this one" in refused.stderr and "Traceback" not in refused.stderr


def test_an_unreachable_ray_address_is_one_line(tmp_path):
    campaign = small_campaign(tmp_path, episodes=1, flown=0)
    done = subprocess.run(campaign_command(campaign, tmp_path / "out", "--ray-address", "127.0.0.1:9"), cwd=REPO,
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 2
    assert done.stderr.strip().startswith("groundstation: error: --ray-address 127.0.0.1:9: cannot reach it")
    assert "Traceback" not in done.stderr and len(done.stderr.strip().splitlines()) == 1

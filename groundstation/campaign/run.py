"""`groundstation campaign FILE`: run what is missing from the results file, then report.

    groundstation campaign campaigns/noise.toml                 # local process pool, one per core
    groundstation campaign campaigns/noise.toml --ray           # a local Ray
    groundstation campaign campaigns/noise.toml --ray-address HEAD:6379 --resume
"""
from __future__ import annotations

import math
import os
import sys
import time
from pathlib import Path

from ..progress import Progress
from .spec import CampaignError, load_campaign
from .store import ResultStore
from .tasks import run_task


def work(payload) -> dict:
    """What a worker runs (a module-level function, so Ray sends it by name)."""
    campaign, task = payload
    return run_task(campaign, task)


class CampaignProgress:
    """Tasks done of the total, the rate and the time to go, on one line (a bar on a terminal)."""

    def __init__(self, total: int, already: int):
        self.progress = Progress(total)
        self.total, self.done, self.failed = total, already, 0
        self.started_with, self.t0 = already, time.monotonic()

    def step(self, ok: bool) -> None:
        self.done += 1
        self.failed += not ok
        ran = self.done - self.started_with
        elapsed = time.monotonic() - self.t0
        rate = ran / elapsed if elapsed > 0 else 0.0
        eta = (self.total - self.done) / rate if rate > 0 else math.inf
        self.progress.show(self.done, f"campaign: {self.done}/{self.total} episodes, {rate:.2f}/s, "
                                      f"~{eta:.0f} s to go" + (f", {self.failed} failed" if self.failed else ""),
                           milestone=10 * self.done // self.total)

    def close(self) -> None:
        self.progress.close()


def run(args) -> int:
    campaign = load_campaign(Path(args.campaign))
    out_dir = Path(args.out) if args.out else Path("out") / "campaign" / campaign.name
    store = ResultStore(out_dir / "results.jsonl", campaign, args.resume)
    tasks = campaign.tasks()
    missing = [t for t in tasks if t.id not in store.records]
    workers = args.jobs or os.cpu_count() or 1
    backend = ("Ray at " + args.ray_address) if args.ray_address else "a local Ray" if args.ray else \
        f"{min(workers, max(1, len(missing)))} local worker{'s' if workers > 1 else ''}"
    print(f"campaign {campaign.name}: {len(campaign.conditions())} condition(s) x {len(campaign.policies)} "
          f"policies, {len(tasks)} tasks ({len(tasks) - len(missing)} already recorded), on {backend}; "
          f"results: {store.path}", flush=True)
    by_id = {t.id: t for t in missing}
    progress = CampaignProgress(len(tasks), len(tasks) - len(missing))

    def on_done(key, ok, value, attempts) -> None:
        store.add(by_id[key], ok, value, attempts)
        progress.step(ok)

    jobs = [(t.id, (campaign, t)) for t in missing]
    t0 = time.monotonic()
    try:
        if jobs and (args.ray or args.ray_address):
            from .ray_backend import run_ray
            run_ray(jobs, work, on_done, address=args.ray_address, workers=args.jobs)
        elif jobs:
            from .pool import run_local
            run_local(jobs, work, on_done, workers)
    except KeyboardInterrupt:
        progress.close()
        store.close()
        print(f"interrupted: {len(store.records)} of {len(tasks)} tasks recorded in {store.path}; "
              "run again with --resume to finish", file=sys.stderr)
        return 130
    progress.close()
    store.close()
    wall = time.monotonic() - t0
    failed = sum(r["status"] == "failed" for r in store.records.values())
    if jobs:
        print(f"ran {len(jobs)} tasks in {wall:.1f} s ({len(jobs) / wall:.2f}/s)"
              + (f"; {failed} failed after a retry" if failed else ""), flush=True)
    from .report import write
    written = write(campaign, store.records, out_dir, len(tasks))
    print((out_dir / "report.md").read_text())
    print("wrote " + ", ".join(str(p) for p in written))
    return 0

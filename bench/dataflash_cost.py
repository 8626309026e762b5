"""What the dataflash log costs (docs/logs.md quotes these figures). Not part of `make bench`.

- headless: the bench's headless flight (take-off, a 20 m square, land) ticked every 10 ms as the
  loop ticks it, with the recorder writing real files, against the same without a recorder;
  alternated, medians.
- with a client: `autopilot --speedup inf` with one client (bench/telemetry.py), logging with
  LOG_DISARMED 1 (the vehicle sits disarmed) against LOG_BACKEND_TYPE 0; alternated, medians.
- per tick: the recorder's tick, averaged over a hover.

Run from the repository root: PYTHONPATH=. python bench/dataflash_cost.py [--runs 5]
"""
from __future__ import annotations

import argparse
import shutil
import tempfile
import time
from pathlib import Path

from firefly.autopilot.dataflash.recorder import Recorder
from firefly.autopilot.io.dataflash_files import LogFiles
from firefly.autopilot.vehicle import Vehicle, VehicleConfig
from report import summary  # bench/report.py, beside this script
from telemetry import ROOT, rtf_with_client_run

TICK_S = 0.01
CLIENT_LOGS = ROOT / "bench" / "tmp" / "telemetry" / "instance-0" / "logs"  # the client runs' logs


def headless_run(logging: bool) -> float:
    v = Vehicle(VehicleConfig())
    tmp = Path(tempfile.mkdtemp(prefix="firefly-df-"))
    files = LogFiles(tmp / "logs", v.params)
    rec = Recorder(v, files) if logging else None
    if rec is not None:
        v.text_listener = rec.text

    def until(t_s: float) -> None:
        while v.time_s < t_s - 1e-9:
            v.run_until(v.time_s + TICK_S)
            if rec is not None:
                rec.tick()

    t0 = time.perf_counter()
    v.set_mode(4)
    v.arm()
    v.takeoff(10.0)
    until(v.time_s + 8.0)
    for n, e in ((20, 0), (20, 20), (0, 20), (0, 0)):
        v.guided_goto(n, e, -10.0)
        until(v.time_s + 8.0)
    v.set_mode(9)
    until(v.time_s + 15.0)
    files.stop()
    wall = time.perf_counter() - t0
    shutil.rmtree(tmp)
    return v.time_s / wall


def tick_cost_us(ticks: int = 20_000) -> float:
    v = Vehicle(VehicleConfig())
    tmp = Path(tempfile.mkdtemp(prefix="firefly-df-"))
    files = LogFiles(tmp / "logs", v.params)
    rec = Recorder(v, files)
    v.set_mode(4)
    v.arm()
    v.takeoff(5.0)
    v.run_until(10.0)
    spent = 0.0
    for _ in range(ticks):
        v.run_until(v.time_s + TICK_S)
        t0 = time.perf_counter()
        rec.tick()
        spent += time.perf_counter() - t0
    files.stop()
    size = sum(p.stat().st_size for p in (tmp / "logs").glob("*.BIN"))
    shutil.rmtree(tmp)
    print(f"  log size: {size / (ticks * TICK_S) / 1024:.1f} KiB per sim second")
    return spent / ticks * 1e6


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=5)
    args = ap.parse_args()
    on, off = [], []
    for _ in range(args.runs):
        off.append(headless_run(False))
        on.append(headless_run(True))
    print(f"headless, ticked at 100 Hz: logging {summary(on)}; none {summary(off)}")
    print(f"recorder tick: {tick_cost_us():.1f} us")
    on, off = [], []
    for _ in range(args.runs):
        off.append(rtf_with_client_run(5.0, {"LOG_BACKEND_TYPE": 0}))
        on.append(rtf_with_client_run(5.0, {"LOG_DISARMED": 1}))
        shutil.rmtree(CLIENT_LOGS, ignore_errors=True)
    print(f"with a client, flat out: logging {summary(on)}; none {summary(off)}")


if __name__ == "__main__":
    main()

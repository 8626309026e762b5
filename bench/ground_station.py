"""A ground station's load, Firefly against ArduCopter SITL in the same run.

A client that sends a GCS HEARTBEAT every wall second and asks for every stream at 4 Hz (as
MAVProxy does), reading time_boot_ms from raw frames (telemetry.client_rtf): Firefly at
`--speedup inf` with that client and with one that asks for nothing, and, when the reference
vehicle is built on the machine (REF_DIR names build-arducopter-sitl's OUT_DIR), ArduCopter SITL
at `--speedup 1000` with the same client. Runs alternate vehicle by vehicle so that a machine's
load falls on all of them alike; the ratio is Firefly's median over ArduCopter's.
"""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

from report import summary
from telemetry import ROOT, client_rtf, rtf_with_client_run

REQUEST_HZ = 4
REF_SPEEDUP = 1000
REF_INSTANCE = 15  # a working folder of its own beside the parity recorder's instances
RUNNER = Path(os.environ.get("ARDUCOPTER_RUNNER", ROOT.parent / "shared" / "reference" / "run-arducopter-sitl"))


def reference_dir() -> Path | None:
    ref = os.environ.get("REF_DIR")
    if not ref:
        return None
    out = Path(ref)
    if not (out / "ardupilot" / "build" / "sitl" / "bin" / "arducopter").exists() or not RUNNER.exists():
        print(f"REF_DIR={ref}: no built ArduCopter SITL or no runner there; measuring Firefly alone",
              file=sys.stderr)
        return None
    return out


def arducopter_run(out_dir: Path, window_s: float) -> float:
    shutil.rmtree(out_dir / f"run-{REF_INSTANCE}", ignore_errors=True)  # a fresh boot, as Firefly's --wipe

    def launch(port: int) -> subprocess.Popen:
        return subprocess.Popen([str(RUNNER), str(out_dir), str(REF_INSTANCE), str(port), str(REF_SPEEDUP)],
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    # ArduCopter's start (parameters, the EKF's first seconds) runs slower than its flight: the
    # window opens once it has been sending for 3 wall seconds
    return client_rtf(launch, window_s, REQUEST_HZ, settle_s=3.0)


def measure(runs: int, window_s: float = 5.0, progress=print) -> dict:
    ref = reference_dir()
    streams, quiet, arducopter = [], [], []
    for i in range(runs):
        if ref is not None:
            arducopter.append(arducopter_run(ref, window_s))
            progress(f"ground station load, run {i + 1}/{runs}: ArduCopter all streams {arducopter[-1]:.0f}x")
        streams.append(rtf_with_client_run(window_s, request_hz=REQUEST_HZ))
        quiet.append(rtf_with_client_run(window_s))
        progress(f"ground station load, run {i + 1}/{runs}: Firefly all streams {streams[-1]:.0f}x, "
                 f"no request {quiet[-1]:.0f}x")
    out = {"request_hz": REQUEST_HZ, "firefly_all_streams": summary(streams), "firefly_no_request": summary(quiet)}
    if arducopter:
        out["arducopter_all_streams"] = summary(arducopter) | {"speedup": REF_SPEEDUP}
        out["ratio"] = out["firefly_all_streams"]["median"] / out["arducopter_all_streams"]["median"]
    return out

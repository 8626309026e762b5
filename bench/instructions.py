"""Instructions the headless pattern costs, counted by valgrind's callgrind: a speed figure that a
busy machine does not blur (wall-clock figures on two shared cores move by 20 % run to run; this
one by about 1 %), so two commits can be compared on any host.

The count is a run of the pattern minus a run that only imports and builds the vehicle, with
PYTHONHASHSEED fixed (string hashing otherwise changes dict layouts, and the count, run to run).
"""
from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BUILD = ("import sys; sys.path.insert(0, 'bench'); from firefly.autopilot.vehicle import Vehicle, VehicleConfig; "
         "from run import headless_pattern; v = Vehicle(VehicleConfig(compiled=True))")
COLLECTED = re.compile(r"Collected : (\d+)")


def _count(code: str) -> int:
    env = dict(os.environ, PYTHONHASHSEED="0")
    out = subprocess.run(["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null", sys.executable, "-c", code],
                         cwd=ROOT, env=env, capture_output=True, text=True, check=True)
    found = COLLECTED.search(out.stderr)
    if found is None:
        raise RuntimeError("callgrind printed no instruction count")
    return int(found.group(1))


def headless_pattern_instructions() -> dict | None:
    """{'instructions_M': ..., 'per_sim_s_M': ...}, or None where valgrind is not installed."""
    if shutil.which("valgrind") is None:
        return None
    flown = _count(BUILD + "; headless_pattern(v); print(v.time_s)")
    built = _count(BUILD)
    sys.path.insert(0, str(ROOT / "bench"))
    from firefly.autopilot.vehicle import Vehicle, VehicleConfig
    from run import headless_pattern
    v = Vehicle(VehicleConfig(compiled=True))
    headless_pattern(v)
    instructions = flown - built
    return {"instructions_M": round(instructions / 1e6, 1), "per_sim_s_M": round(instructions / 1e6 / v.time_s, 2),
            "sim_s": round(v.time_s, 1)}


if __name__ == "__main__":
    print(headless_pattern_instructions())

"""Record the reference: run every probe (or the areas named) against ArduCopter SITL.

    python -m tests.parity.record OUT_DIR [AREA ...]

OUT_DIR is where the reference scripts built ArduCopter (build-arducopter-sitl OUT_DIR); the
runner is ../shared/reference/run-arducopter-sitl unless ARDUCOPTER_RUNNER says otherwise.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from .probes import AREAS
from .recording import save
from .targets import ArduCopterTarget


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m tests.parity.record", description=__doc__.split("\n")[0])
    parser.add_argument("out_dir", type=Path, help="build-arducopter-sitl's OUT_DIR")
    parser.add_argument("areas", nargs="*", help=f"areas to record (default all: {', '.join(AREAS)})")
    parser.add_argument("--instance", type=int, default=0)
    parser.add_argument("--speedup", type=int, default=10)
    args = parser.parse_args(argv)
    unknown = [a for a in args.areas if a not in AREAS]
    if unknown:
        parser.error(f"unknown area {unknown[0]!r}; areas: {', '.join(AREAS)}")
    binary = args.out_dir / "ardupilot/build/sitl/bin/arducopter"
    if not binary.exists():
        parser.error(f"{binary}: not built; run build-arducopter-sitl {args.out_dir} first")
    for area in args.areas or AREAS:
        started = time.monotonic()
        print(f"recording {area} ...", flush=True)
        traces = AREAS[area].run(ArduCopterTarget(args.out_dir, args.instance, args.speedup))
        path = save(area, traces)
        print(f"  {sum(len(t.values) for t in traces.values())} facts in {len(traces)} probes -> {path} "
              f"({time.monotonic() - started:.0f} s)", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

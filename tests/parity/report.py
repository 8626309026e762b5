"""`make parity`: run every probe against Firefly, compare with the recorded ArduCopter, print the
score per area and write PARITY.md (every remaining difference with its reason).

    python -m tests.parity.report [--out PARITY.md] [AREA ...]
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from .compare_run import AreaResult, run_area
from .probes import AREAS
from .recording import ARDUPILOT_COMMIT, load


def _short(value, width: int = 60) -> str:
    text = json.dumps(value)
    return text if len(text) <= width else text[: width - 1] + "…"


def markdown(results: list[AreaResult], elapsed_s: float) -> str:
    total = sum(len(r.checks) for r in results)
    matching = sum(r.matching for r in results)
    lines = [
        "# Parity with ArduCopter",
        "",
        f"Every probe in `tests/parity/probes/` run against Firefly and compared, fact by fact, with the "
        f"recording of the same probe against ArduCopter SITL (commit {ARDUPILOT_COMMIT[:8]}, "
        f"ArduCopter 4.7.0-dev). Written by `make parity` in {elapsed_s:.0f} s.",
        "",
        "| area | checks | matching | score | known differences | unexplained |",
        "|---|---:|---:|---:|---:|---:|",
    ]
    for r in results:
        lines.append(f"| {r.area} | {len(r.checks)} | {r.matching} | {100 * r.matching / max(len(r.checks), 1):.1f} % "
                     f"| {len(r.explained)} | {len(r.unexplained)} |")
    no_params = [r for r in results if r.area != "params"]
    np_total, np_match = sum(len(r.checks) for r in no_params), sum(r.matching for r in no_params)
    lines += [f"| **all** | {total} | {matching} | **{100 * matching / max(total, 1):.1f} %** | "
              f"{sum(len(r.explained) for r in results)} | {sum(len(r.unexplained) for r in results)} |",
              "", f"Without the parameter list (one check per parameter): {np_match} / {np_total} = "
              f"{100 * np_match / max(np_total, 1):.1f} %.", ""]
    for r in results:
        if not r.explained and not r.unexplained:
            continue
        lines += [f"## {r.area}", ""]
        if r.unexplained:
            lines += ["Unexplained (a regression or a new gap):", ""]
            lines += [f"- `{c.name}`: ArduCopter {_short(c.want)}, Firefly {_short(c.got)}" for c in r.unexplained]
            lines.append("")
        by_reason: dict[str, list] = {}
        for c in r.checks:
            why = r.explained.get(r.check_id(c))
            if why:
                by_reason.setdefault(why, []).append(c)
        for why, checks in by_reason.items():
            lines.append(f"- **{why}** ({len(checks)} check{'s' * (len(checks) > 1)})")
            for c in checks[:6]:
                lines.append(f"  - `{c.name}`: ArduCopter {_short(c.want)}, Firefly {_short(c.got)}")
            if len(checks) > 6:
                lines.append(f"  - … and {len(checks) - 6} more")
        lines.append("")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m tests.parity.report", description=__doc__.split("\n")[0])
    parser.add_argument("areas", nargs="*")
    parser.add_argument("--out", type=Path, default=Path("PARITY.md"))
    args = parser.parse_args(argv)
    unknown = [a for a in args.areas if a not in AREAS]
    if unknown:
        parser.error(f"unknown area {unknown[0]!r}; areas: {', '.join(AREAS)}")
    started, results = time.monotonic(), []
    for area in args.areas or AREAS:
        load(area)  # a missing or stale recording says so before any vehicle starts
        t0 = time.monotonic()
        print(f"{area:10s} ...", end="", flush=True)
        r = run_area(area)
        results.append(r)
        print(f" {r.matching}/{len(r.checks)} = {100 * r.matching / max(len(r.checks), 1):.1f} %"
              f" ({len(r.explained)} known, {len(r.unexplained)} unexplained, {time.monotonic() - t0:.0f} s)")
    total, matching = sum(len(r.checks) for r in results), sum(r.matching for r in results)
    print(f"{'all':10s}     {matching}/{total} = {100 * matching / max(total, 1):.1f} %")
    args.out.write_text(markdown(results, time.monotonic() - started) + "\n")
    print(f"wrote {args.out}")
    return 1 if any(r.unexplained for r in results) else 0


if __name__ == "__main__":
    sys.exit(main())

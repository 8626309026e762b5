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

from .compare_run import AreaResult, run_area_confirmed
from .probes import AREAS
from .recording import ARDUPILOT_COMMIT, load
from .surface.score import KINDS, kind_of, load_surface, share, statuses, write_not_yet


def _short(value, width: int = 60) -> str:
    text = json.dumps(value)
    return text if len(text) <= width else text[: width - 1] + "…"


def surface_section(results: list[AreaResult]) -> list[str]:
    """The lead table: of ArduCopter's surface, per kind, how much Firefly reproduces."""
    table = statuses(results)
    lines = [
        "# Parity with ArduCopter",
        "",
        "## Of what ArduCopter does, how much Firefly does the same",
        "",
        f"ArduCopter's surface, enumerated from its sources at commit {ARDUPILOT_COMMIT[:8]} "
        "(`tests/parity/surface/arducopter.json`, by `python -m tests.parity.surface.extract`): every "
        "command its GCS handles, every mode number, every message it handles, every mission command its "
        "AUTO flies, the SIM faults a test sets (`sim_faults.toml`) and every parameter. An entry is "
        "*matching* when every fact its probes recorded on ArduCopter is reproduced, *deliberate* when "
        "what differs is listed with a reason in `tests/parity/differences.toml`, *not yet* otherwise "
        "(an entry no probe covers yet counts as not yet).",
        "",
        "| kind | ArduCopter has | in scope | matching | deliberate | not yet | Firefly reproduces |",
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    totals = [0, 0, 0, 0, 0]
    for kind, title in KINDS.items():
        column = table.get(kind, {})
        in_scope, matching, deliberate, missing = share(column)
        for i, n in enumerate((len(column), in_scope, matching, deliberate, missing)):
            totals[i] += n
        lines.append(f"| {title} | {len(column)} | {in_scope} | {matching} | {deliberate} | {missing} | "
                     f"**{100 * matching / max(in_scope, 1):.1f} %** |")
    every, in_scope, matching, deliberate, missing = totals
    lines += [f"| **all** | {every} | {in_scope} | {matching} | {deliberate} | {missing} | "
              f"**{100 * matching / max(in_scope, 1):.1f} %** |", ""]
    probed = [share(table.get(k, {})) for k in KINDS if k != "parameters"]
    probed_in, probed_matching = sum(p[0] for p in probed), sum(p[1] for p in probed)
    lines += ["Without the parameters (one entry each, most of them plain defaults): "
              f"{probed_matching} of {probed_in} = {100 * probed_matching / max(probed_in, 1):.1f} %.",
              "", "Out of scope (nothing a user of a SITL quadcopter can reach):", ""]
    out: dict[str, list[str]] = {}
    for kind, entries in load_surface().items():
        for entry in entries:
            if not entry.in_scope:
                out.setdefault(f"{kind}: {entry.why}", []).append(entry.name)
    lines += [f"- {why}: {', '.join(f'`{n}`' for n in names)}" for why, names in out.items()]
    lines += ["", "Not yet reproduced, per kind (the work of the issues that follow):", ""]
    for kind in KINDS:
        if kind == "parameters":
            continue
        names = sorted(n for n, s in table.get(kind, {}).items() if s in ("not yet", "not probed"))
        if names:
            lines.append(f"- {kind} ({len(names)}): " + ", ".join(f"`{n}`" for n in names))
    missing_params = sorted(n for n, s in table.get("parameters", {}).items() if s in ("not yet", "not probed"))
    if missing_params:
        lines.append(f"- parameters ({len(missing_params)}): see the params area below")
    if lines[-1] == "":  # nothing listed
        lines.append("None: every entry in scope is matched or listed as a deliberate difference.")
    return lines + [""]


def markdown(results: list[AreaResult], elapsed_s: float) -> str:
    total = sum(len(r.checks) for r in results)
    matching = sum(r.matching for r in results)
    lines = surface_section(results) + [
        "## Per area: every recorded fact",
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
        if not r.explained and not r.unexplained and not r.not_yet:
            continue
        lines += [f"### {r.area}", ""]
        if r.unexplained:
            lines += ["Unexplained (a regression or a new gap):", ""]
            lines += [f"- `{c.name}`: ArduCopter {_short(c.want)}, Firefly {_short(c.got)}" for c in r.unexplained]
            lines.append("")
        gaps = [c for c in r.checks if r.check_id(c) in r.not_yet]
        if gaps:
            lines += [f"Not yet reproduced ({len(gaps)} checks, entries listed in `surface/not_yet.toml`):", ""]
            lines += [f"- `{c.name}`: ArduCopter {_short(c.want)}, Firefly {_short(c.got)}" for c in gaps[:80]]
            if len(gaps) > 80:
                lines.append(f"- … and {len(gaps) - 80} more")
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
    parser.add_argument("--write-not-yet", action="store_true",
                        help="rewrite surface/not_yet.toml for the kinds of the areas run")
    args = parser.parse_args(argv)
    unknown = [a for a in args.areas if a not in AREAS]
    if unknown:
        parser.error(f"unknown area {unknown[0]!r}; areas: {', '.join(AREAS)}")
    started, results = time.monotonic(), []
    for area in args.areas or AREAS:
        load(area)  # a missing or stale recording says so before any vehicle starts
        t0 = time.monotonic()
        print(f"{area:10s} ...", end="", flush=True)
        r = run_area_confirmed(area)
        results.append(r)
        print(f" {r.matching}/{len(r.checks)} = {100 * r.matching / max(len(r.checks), 1):.1f} %"
              f" ({len(r.explained)} known, {len(r.unexplained)} unexplained, {time.monotonic() - t0:.0f} s)")
    total, matching = sum(len(r.checks) for r in results), sum(r.matching for r in results)
    print(f"{'all':10s}     {matching}/{total} = {100 * matching / max(total, 1):.1f} %")
    args.out.write_text(markdown(results, time.monotonic() - started) + "\n")
    print(f"wrote {args.out}")
    if args.write_not_yet:
        write_not_yet(statuses(results), {kind_of(r.area) for r in results} - {None})
        print("wrote tests/parity/surface/not_yet.toml")
    return 1 if any(r.unexplained for r in results) else 0


if __name__ == "__main__":
    sys.exit(main())

"""Markdown tables from `groundstation evaluate --json` files, as EVALUATION.md shows them:

    python -m firefly.groundstation.evaluation.report out/eval/default_R.json [more.json ...]

Per file: the summary per policy and the paired path differences against the first policy.
"""
from __future__ import annotations

import json
import sys
from pathlib import Path


def summary_table(doc: dict) -> list[str]:
    several = any(r.get("fires") and len(r["fires"]) > 1 for rows in doc.get("results", {}).values() for r in rows)
    lines = ["| policy | success |" + (" fires found |" if several else "") +
             " mean path m | path to 1st find m | median m | p90 m | mean error m | false | forced | ms/decision (mean) |",
             "|---|---|" + ("---|" if several else "") + "---|---|---|---|---|---|---|---|"]
    for name, s in doc["summary"].items():
        found = f" {s['fires_found_rate']:.3f} |" if several else ""
        first = s.get("first_find_mean_m", float("nan"))
        lines.append(f"| {name} | {s['success_rate']:.3f} |{found} {s['path_mean_m']:.0f} | {first:.0f} | "
                     f"{s['path_median_m']:.0f} | "
                     f"{s['path_p90_m']:.0f} | {s['error_mean_m']:.1f} | {s['false_declarations']} | "
                     f"{s['forced_declarations']} | {s['ms_per_decision_mean']:.1f} |")
    return lines


def differences_table(doc: dict) -> list[str]:
    paired = doc.get("paired_path_differences") or {}
    policies = paired.get("policies") or {}
    if not policies:
        return []
    base = paired["base"]
    lines = [f"Path minus {base}'s on the same episodes (mean, 95 % confidence interval of the paired differences):", "",
             "| policy | mean difference m | 95 % CI m |", "|---|---|---|"]
    for name, d in policies.items():
        lines.append(f"| {name} | {d['mean_m']:+.0f} | {d['ci95_low_m']:+.0f} to {d['ci95_high_m']:+.0f} |")
    return lines


def section(path: Path) -> str:
    doc = json.loads(path.read_text())
    config = doc.get("config", {})
    fires, spacing, wanted = config.get("fires", 1), config.get("fire_spacing_m"), config.get("max_fires", 1)
    told = ("" if wanted == 1 and fires == 1 else ", the search not told how many" if wanted is None
            else f", the search looking for up to {wanted}")
    head = (f"`{doc['scenario']}`, kernel {doc['kernel']}, noise {doc['noise_k']:g} K, {doc['start']} start, "
            f"{doc['episodes']} episodes, seed {doc['seed']}"
            + (f", {fires} fires per episode" if fires > 1 else "") + (f" {spacing:g} m apart" if spacing else "")
            + told)
    parts = [head, ""] + summary_table(doc)
    diffs = differences_table(doc)
    if diffs:
        parts += [""] + diffs
    return "\n".join(parts)


def main(argv: list[str] | None = None) -> int:
    paths = [Path(p) for p in (sys.argv[1:] if argv is None else argv)]
    if not paths:
        print("usage: python -m firefly.groundstation.evaluation.report FILE.json [...]", file=sys.stderr)
        return 2
    for path in paths:
        try:
            print(section(path) + "\n")
        except (OSError, ValueError, KeyError) as exc:
            print(f"{path}: not an evaluate --json file ({type(exc).__name__}: {exc})", file=sys.stderr)
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())

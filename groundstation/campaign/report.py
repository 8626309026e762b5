"""What a campaign found: a table per condition and policy (Markdown and JSON), and a PNG per
swept dimension (success and mean path against its values, one line per policy)."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from ..evaluation import flown_episodes
from ..evaluation.evaluate import summarize
from ..plots import png
from .spec import Campaign


def cells(campaign: Campaign, records: dict[str, dict]) -> list[dict]:
    """One summary per (condition, policy), in the campaign's order."""
    out = []
    for condition in campaign.conditions():
        for policy in campaign.policies:
            mine = [r for r in records.values() if r["policy"] == policy and r["condition"] == dict(condition.values)]
            decided = [r["result"] for r in mine if not r["flown"] and r["status"] == "ok"]
            flown = [r["result"] for r in mine if r["flown"] and r["status"] == "ok"]
            cell = {"condition": dict(condition.values), "label": condition.label, "policy": policy,
                    "episodes": len(decided), "flown_episodes": len(flown),
                    "failed": sum(r["status"] == "failed" for r in mine),
                    "errors": sorted({r["error"] for r in mine if r["status"] == "failed"})[:3]}
            if decided:
                cell["decided"] = summarize(decided)
                if "time_s" in decided[0]:  # time to declaration (one vehicle's episodes have it too now)
                    cell["decided"]["time_mean_s"] = float(np.mean([r["time_s"] for r in decided]))
                if "team_path_m" in decided[0]:  # team episodes: the team's distance
                    cell["decided"]["team_path_mean_m"] = float(np.mean([r["team_path_m"] for r in decided]))
            if flown:
                cell["flown"] = flown_episodes.summarize(flown)
                same = {r["episode"]: r["path_m"] for r in decided}
                paths = [same[r["episode"]] for r in flown if r["episode"] in same]
                cell["decided_path_mean_m_of_flown_episodes"] = float(np.mean(paths)) if paths else math.nan
            out.append(cell)
    return out


def _f(value, digits: int = 0) -> str:
    return "–" if value is None or (isinstance(value, float) and math.isnan(value)) else f"{value:.{digits}f}"


def markdown(campaign: Campaign, summary: list[dict], done: int, total: int) -> str:
    lines = [f"# Campaign {campaign.name}", "",
             f"{campaign.path} on {campaign.scenario_path.name}, seed {campaign.seed}: {campaign.episodes} "
             f"decision-level episodes per cell, the first {campaign.flown} also flown at speedup "
             f"{campaign.speedup:g}. {done} of {total} tasks recorded. Success: every declared cell within one "
             "cell of a fire. Path in metres (a team's: its slowest vehicle's); ms: decision time per decision.", "",
             "| condition | policy | episodes | failed | success | mean path | median | p90 | false decl. | ms/decision "
             "| time to declaration s | team: distance m "
             "| flown | flown success | flown mean path | decided mean path, same episodes |",
             "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for c in summary:
        d, f = c.get("decided", {}), c.get("flown", {})
        lines.append(f"| {c['label']} | {c['policy']} | {c['episodes']} | {c['failed']} | "
                     f"{_f(d.get('success_rate'), 3)} | {_f(d.get('path_mean_m'))} | {_f(d.get('path_median_m'))} | "
                     f"{_f(d.get('path_p90_m'))} | {d.get('false_declarations', '–')} | "
                     f"{_f(d.get('ms_per_decision_mean'), 1)} | {_f(d.get('time_mean_s'), 1)} | "
                     f"{_f(d.get('team_path_mean_m'))} | {c['flown_episodes']} | {_f(f.get('success_rate'), 3)} | "
                     f"{_f(f.get('path_mean_m'))} | {_f(c.get('decided_path_mean_m_of_flown_episodes'))} |")
    failed = [c for c in summary if c["errors"]]
    if failed:
        lines += ["", "Failed tasks (after a retry), first errors per cell:", ""]
        lines += [f"- {c['label']}, {c['policy']}: {'; '.join(c['errors'])}" for c in failed]
    return "\n".join(lines) + "\n"


def plot_dimension(campaign: Campaign, records: dict[str, dict], dimension: str, values: tuple, path: Path) -> None:
    """Success and mean decided path against one swept dimension, pooled over the others."""
    x = list(range(len(values)))
    with png(path, (10.0, 4.2), ncols=2) as (fig, (ax_ok, ax_path)):
        for policy in campaign.policies:
            ok, mean = [], []
            for value in values:
                rows = [r["result"] for r in records.values() if r["policy"] == policy and not r["flown"]
                        and r["status"] == "ok" and r["condition"].get(dimension) == value]
                ok.append(np.mean([r["success"] for r in rows]) if rows else math.nan)
                mean.append(np.mean([r["path_m"] for r in rows]) if rows else math.nan)
            ax_ok.plot(x, ok, "o-", label=policy)
            ax_path.plot(x, mean, "o-", label=policy)
        name = dimension.split(".", 1)[1]
        for ax, ylabel in ((ax_ok, "success rate"), (ax_path, "mean path [m]")):
            ax.set_xticks(x)
            ax.set_xticklabels([str(v) for v in values])
            ax.set_xlabel(name)
            ax.set_ylabel(ylabel)
            ax.grid(alpha=0.3)
        ax_ok.set_ylim(-0.02, 1.02)
        ax_ok.legend()
        fig.suptitle(f"{campaign.name}: decision-level episodes against {name} (pooled over the other dimensions)",
                     fontsize=10)


def write(campaign: Campaign, records: dict[str, dict], out_dir: Path, total: int) -> list[Path]:
    summary = cells(campaign, records)
    md, js = out_dir / "report.md", out_dir / "report.json"
    md.write_text(markdown(campaign, summary, len(records), total))
    js.write_text(json.dumps({"campaign": campaign.name, "file": str(campaign.path),
                              "fingerprint": campaign.fingerprint, "seed": campaign.seed,
                              "episodes": campaign.episodes, "flown": campaign.flown, "speedup": campaign.speedup,
                              "tasks": total, "recorded": len(records), "cells": summary}, indent=1))
    written = [md, js]
    for dimension, values in campaign.sweep:
        if len(values) > 1:
            path = out_dir / f"{dimension.replace('.', '_')}.png"
            plot_dimension(campaign, records, dimension, values, path)
            written.append(path)
    return written

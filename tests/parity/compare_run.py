"""Run an area's probes against Firefly and compare them with the recording, fact by fact; sort
every mismatch into a known, explained difference (differences.toml) or an unexplained one."""
from __future__ import annotations

import fnmatch
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from .facts import Check, compare
from .probes import AREAS
from .recording import load
from .surface.score import entry_of, kind_of, not_yet
from .targets import FireflyTarget

DIFFERENCES = Path(__file__).parent / "differences.toml"


def known_differences() -> list[dict]:
    """[[difference]] entries: `checks` (glob patterns over area/probe/fact) and `why`; with
    `sometimes = true`, a difference seen in some runs only (its why says how often), which is
    not stale when a run matches."""
    doc = tomllib.loads(DIFFERENCES.read_text())
    entries = doc.get("difference", [])
    for i, entry in enumerate(entries):
        if not entry.get("checks") or not entry.get("why"):
            raise ValueError(f"{DIFFERENCES.name}: difference {i + 1} needs `checks` and `why`")
    return entries


@dataclass
class AreaResult:
    area: str
    checks: list[Check] = field(default_factory=list)
    explained: dict[str, str] = field(default_factory=dict)   # check id -> why
    stale: list[str] = field(default_factory=list)            # listed patterns that matched no failure
    not_yet: set[str] = field(default_factory=set)            # check ids of surface entries not reproduced yet

    @property
    def matching(self) -> int:
        return sum(c.ok for c in self.checks)

    @property
    def unexplained(self) -> list[Check]:
        return [c for c in self.checks if not c.ok and self.check_id(c) not in self.explained
                and self.check_id(c) not in self.not_yet]

    def check_id(self, check: Check) -> str:
        return f"{self.area}/{check.name}"


def judge(area: str, checks: list[Check], differences: list[dict],
          gaps: dict[str, set[str]] | None = None) -> AreaResult:
    """Sort the mismatches: explained by differences.toml, a surface entry listed as not yet
    reproduced (gaps: kind -> entries, surface/not_yet.toml), or unexplained."""
    result = AreaResult(area, checks)
    kind = kind_of(area)
    listed = (gaps or {}).get(kind, set()) if kind else set()
    result.not_yet = {result.check_id(c) for c in checks if not c.ok and entry_of(area, c.name) in listed}
    for entry in differences:
        patterns = [p for p in entry["checks"] if p.split("/", 1)[0] in (area, "*")]
        if not patterns:
            continue
        used = False
        for check in checks:
            cid = result.check_id(check)
            if not check.ok and any(fnmatch.fnmatchcase(cid, p) for p in patterns):
                result.explained[cid] = entry["why"]
                used = True
        if not used and not entry.get("sometimes", False):  # ("sometimes": it differs in some runs only)
            result.stale.extend(patterns)
    return result


def run_area_confirmed(area: str) -> AreaResult:
    """run_area, and where something differs unexplained (or a listed difference is gone), once
    more: a check fails only if it failed in both runs. A probe's windows are cut where its client
    reads the streams; at speedup 20 a client 50 ms late is a vehicle second late, and a fact at a
    window's edge (an item reached, a MISSION_CURRENT change) can land in the next window. Firefly
    itself is deterministic: a regression differs in every run."""
    first = run_area(area)
    if not first.unexplained and not first.stale:
        return first
    second = {c.name: c for c in run_area(area).checks}
    merged = [c if c.ok or not (again := second.get(c.name)) or not again.ok else again for c in first.checks]
    return judge(area, merged, known_differences(), not_yet())


def run_area(area: str, target=None) -> AreaResult:
    recorded = load(area)["probes"]
    module = AREAS[area]
    # A probe whose client plays part of the world (FOLLOW's lead) may ask for a slower vehicle
    traces = module.run(target or FireflyTarget(getattr(module, "FIREFLY_SPEEDUP", "20")))
    checks = []
    for probe, facts in recorded.items():
        trace = traces.get(probe)
        if trace is None:
            checks.extend(Check(area, f"{probe}/{name}", want, "<probe not run>", False)
                          for name, want in facts.items())
        else:
            checks.extend(compare(area, probe, facts, trace))
    return judge(area, checks, known_differences(), not_yet())

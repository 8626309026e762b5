"""Firefly's score on ArduCopter's surface: every command, mode number, message, mission command,
SIM fault and parameter ArduCopter has (arducopter.json, read from its sources), each one entry.

An in-scope entry is *matching* when every fact its probes recorded on ArduCopter is reproduced,
*deliberate* when each one that is not is listed with its reason in differences.toml, and *not
yet* otherwise — including an entry no probe covers, and one Firefly answers UNSUPPORTED where
ArduCopter acts. The denominator is ArduCopter's, never Firefly's.

not_yet.toml lists the entries known not to match yet, so that `make test` fails on a regression
(an entry that matched and no longer does) but not on the gaps later issues close.
"""
from __future__ import annotations

import json
import tomllib
from dataclasses import dataclass
from pathlib import Path

SURFACE_DIR = Path(__file__).parent
NOT_YET = SURFACE_DIR / "not_yet.toml"
KINDS = {  # kind -> what a reader calls it
    "commands": "commands (COMMAND_LONG / COMMAND_INT)",
    "modes": "mode numbers",
    "messages": "messages it handles",
    "mission_commands": "mission commands in AUTO",
    "sim_faults": "SIM faults a test sets",
    "parameters": "parameters",
}
PARAMS_AREA = "params"  # the parameter list: one check per parameter, the entry is the fact


@dataclass(frozen=True)
class Entry:
    kind: str
    name: str
    in_scope: bool = True
    why: str = ""  # why it is out of scope


def _out_of_scope() -> dict[tuple[str, str], str]:
    doc = tomllib.loads((SURFACE_DIR / "scope.toml").read_text())
    return {(block["kind"], name): block["why"] for block in doc.get("out", []) for name in block["names"]}


def load_surface() -> dict[str, list[Entry]]:
    """ArduCopter's surface per kind, each entry in or out of scope."""
    from ..recording import load  # the parameter list is the recorded one: ArduCopter's own, fetched

    doc = json.loads((SURFACE_DIR / "arducopter.json").read_text())
    out = _out_of_scope()
    surface = {kind: [Entry(kind, e["name"], (kind, e["name"]) not in out, out.get((kind, e["name"]), ""))
                      for e in doc[kind]]
               for kind in ("commands", "modes", "messages", "mission_commands")}
    faults_file = SURFACE_DIR / "sim_faults.toml"
    faults = tomllib.loads(faults_file.read_text()).get("fault", []) if faults_file.exists() else []
    surface["sim_faults"] = [Entry("sim_faults", f["name"], f.get("scope", "in") != "out", f.get("why", ""))
                             for f in faults]
    surface["parameters"] = [Entry("parameters", name) for name in load(PARAMS_AREA)["probes"]["list"]]
    return surface


def entry_of(area: str, check_name: str) -> str:
    """The surface entry a check belongs to: the probe's name, or for the parameter list the fact's."""
    probe, _, fact = check_name.partition("/")
    return fact if area == PARAMS_AREA else probe


def kind_of(area: str) -> str | None:
    from ..probes import AREAS

    return "parameters" if area == PARAMS_AREA else getattr(AREAS[area], "KIND", None)


def not_yet() -> dict[str, set[str]]:
    """Entries known not to match yet, per kind."""
    if not NOT_YET.exists():
        return {}
    return {kind: set(names) for kind, names in tomllib.loads(NOT_YET.read_text()).items()}


def write_not_yet(statuses: dict[str, dict[str, str]], kinds_run: set[str]) -> None:
    """Rewrite not_yet.toml: the kinds whose areas ran from what they found, the others as listed."""
    listed = not_yet()
    lines = ["# ArduCopter's surface entries Firefly does not reproduce yet, per kind: written by",
             "# `make parity` (python -m tests.parity.report --write-not-yet) from the statuses it found.",
             "# `make test` tolerates a mismatch here and fails on one in any other entry (a regression).",
             ""]
    for kind in KINDS:
        if kind in kinds_run:
            names = sorted(n for n, s in statuses.get(kind, {}).items() if s in ("not yet", "not probed"))
        else:
            names = sorted(listed.get(kind, ()))
        lines.append(f"{kind} = [")
        lines += [f'  "{name}",' for name in names]
        lines.append("]")
    NOT_YET.write_text("\n".join(lines) + "\n")


def statuses(results: list, surface: dict[str, list[Entry]] | None = None) -> dict[str, dict[str, str]]:
    """kind -> entry -> matching | deliberate | not yet | not probed | out of scope, from the
    areas' results (compare_run.AreaResult) over ArduCopter's surface (load_surface())."""
    found: dict[tuple[str, str], list[str]] = {}  # (kind, entry) -> each check's verdict
    for result in results:
        kind = kind_of(result.area)
        if kind is None:
            continue
        for check in result.checks:
            verdict = "ok" if check.ok else ("deliberate" if result.check_id(check) in result.explained else "no")
            found.setdefault((kind, entry_of(result.area, check.name)), []).append(verdict)
    table: dict[str, dict[str, str]] = {}
    for kind, entries in (load_surface() if surface is None else surface).items():
        column = table[kind] = {}
        for entry in entries:
            verdicts = found.get((kind, entry.name))
            if not entry.in_scope:
                column[entry.name] = "out of scope"
            elif not verdicts:
                column[entry.name] = "not probed"
            elif "no" in verdicts:
                column[entry.name] = "not yet"
            else:
                column[entry.name] = "deliberate" if "deliberate" in verdicts else "matching"
    return table


def share(column: dict[str, str]) -> tuple[int, int, int, int]:
    """(in scope, matching, deliberate, not yet) of one kind."""
    in_scope = [s for s in column.values() if s != "out of scope"]
    matching, deliberate = in_scope.count("matching"), in_scope.count("deliberate")
    return len(in_scope), matching, deliberate, len(in_scope) - matching - deliberate

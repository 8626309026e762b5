"""How groundstation/ holds together: the companion never imports the autopilot, the strategy stays
pure decision code, and its shared progress display behaves on a terminal and in a log."""
from __future__ import annotations

import ast
import io
import sys
from pathlib import Path

import pytest

from firefly.groundstation.progress import Progress

GROUNDSTATION = Path(__file__).resolve().parents[2] / "groundstation"


def imported_modules(path: Path) -> set[str]:
    """Absolute names of the modules a source file imports (relative imports resolved), without
    the installed package's `firefly.` prefix."""
    package = ".".join(path.relative_to(GROUNDSTATION.parent).with_suffix("").parts[:-1])
    names = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = package.rsplit(".", node.level - 1)[0] if node.level > 1 else package
            module = node.module if node.level == 0 else ".".join(filter(None, [base, node.module]))
            names.add(module)
            names.update(f"{module}.{alias.name}" for alias in node.names)
    return {name.removeprefix("firefly.") for name in names}  # named by folder, as in a checkout


SOURCES = sorted(GROUNDSTATION.rglob("*.py"))


def test_the_scan_sees_every_kind_of_import():
    explore = imported_modules(GROUNDSTATION / "flight" / "explore.py")
    assert {"asyncio", "sim.fire", "groundstation.strategy.controller", "groundstation.flight.survey",
            "groundstation.truth"} <= explore


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(GROUNDSTATION)))
def test_the_companion_imports_nothing_from_the_autopilot(path):
    found = {m for m in imported_modules(path) if m == "autopilot" or m.startswith("autopilot.")}
    assert not found, f"{path} imports {sorted(found)}: the companion knows the vehicle only over MAVLink"


@pytest.mark.parametrize("path", sorted((GROUNDSTATION / "strategy").glob("*.py")), ids=lambda p: p.name)
def test_the_strategy_is_pure_decision_code(path):
    # numerics (numpy, scipy's least squares) but nothing that does I/O or talks to a vehicle
    allowed_roots = {"__future__", "dataclasses", "itertools", "math", "statistics", "typing", "numpy", "scipy",
                     "sim", "groundstation"}
    modules = imported_modules(path)
    assert {m.split(".")[0] for m in modules} <= allowed_roots
    assert not {m for m in modules if m.startswith(("groundstation.flight", "groundstation.evaluation"))}
    assert not {m for m in modules if m.startswith("sim.") and not m.startswith("sim.fire")}


class Terminal(io.StringIO):
    def isatty(self):
        return True


def test_progress_in_a_log_writes_a_line_per_milestone():
    log = io.StringIO()
    progress = Progress(4, log)
    for done, milestone in [(1, "a"), (2, "a"), (3, "b"), (4, "c")]:
        progress.show(done, f"{done}/4", milestone)
    progress.close()
    assert log.getvalue() == "1/4\n3/4\n4/4\n"


def test_progress_on_a_terminal_redraws_one_bar_and_ends_its_line():
    screen = Terminal()
    progress = Progress(4, screen)
    progress.show(1, "1/4")
    progress.show(4, "4/4")  # the end is always drawn
    progress.close()
    text = screen.getvalue()
    assert text.startswith("\r[") and text.count("\r") == 2 and text.endswith("4/4 \n")
    assert "[" + "#" * 24 + "]" in text


def test_progress_without_a_stream_draws_on_the_stderr_of_when_it_is_made(monkeypatch):
    """The default stream is sys.stderr as it is then (a terminal here), bar and all."""
    screen = Terminal()
    monkeypatch.setattr(sys, "stderr", screen)
    progress = Progress(2)
    progress.show(2, "2/2")
    progress.close()
    assert screen.getvalue().startswith("\r[")

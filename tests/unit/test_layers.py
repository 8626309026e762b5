"""The layers talk one way: sim/ imports neither the autopilot, the companion nor MAVLink; the
autopilot never imports the companion; inside the autopilot, flight modes and the vehicle's
parts never import the MAVLink layer or the I/O edge.

autopilot/testing (the pytest plugin) is not part of the vehicle: it runs in the test's process,
starts the vehicle's process and hands the test MAVSDK and pymavlink clients of it. So it alone
may import MAVSDK, it reaches the vehicle only through that process (never its parts), and no
part of the vehicle imports it."""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def absolute_imports(path: Path) -> set[str]:
    """Every module a file imports, relative imports resolved against its package, named by folder
    (an installed `firefly.autopilot.modes` is the checkout's autopilot/modes)."""
    package = path.relative_to(ROOT).with_suffix("").parts[:-1]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = package[:len(package) - node.level + 1] if node.level else ()
            module = ".".join((*base, node.module or ""))
            found.add(module.rstrip("."))
    return {name.removeprefix("firefly.") for name in found}  # the layers by their folders' names


TEST_HARNESS = "autopilot/testing"


def imports_under(folder: str) -> dict[str, set[str]]:
    """Each file's imports; the test harness counts only when it is the folder asked for."""
    return {str(p.relative_to(ROOT)): absolute_imports(p) for p in (ROOT / folder).rglob("*.py")
            if folder == TEST_HARNESS or not str(p.relative_to(ROOT)).startswith(TEST_HARNESS)}


@pytest.mark.parametrize("folder, forbidden", [
    ("sim", ("autopilot", "groundstation", "pymavlink", "mavsdk")),
    ("autopilot", ("groundstation", "mavsdk", "autopilot.testing")),
    (TEST_HARNESS, ("groundstation", "autopilot.vehicle", "autopilot.mavlink", "autopilot.control",
                    "autopilot.cli", "autopilot.io.runner", "autopilot.safety")),
    ("autopilot/modes", ("autopilot.mavlink", "autopilot.io", "autopilot.vehicle", "pymavlink")),
    ("autopilot/safety", ("autopilot.mavlink", "autopilot.io", "pymavlink")),
    ("autopilot/control", ("autopilot.mavlink", "autopilot.io", "autopilot.modes", "pymavlink")),
    ("autopilot/mission", ("autopilot.mavlink", "pymavlink")),
])
def test_imports_point_one_way(folder, forbidden):
    wrong = {f"{path} imports {module}" for path, modules in imports_under(folder).items()
             for module in modules if module.split(".")[0] in forbidden or module.startswith(forbidden)}
    assert not wrong, sorted(wrong)


# The companion's own layers, lowest first: each may import only those before it. The search's
# decisions (strategy) and the plans know nothing of flying; judging against the truth sits on the
# strategy, as does reading a camera's frame into it (camera_view); flying (flight) uses those; evaluation runs episodes, flown or not; a campaign runs
# evaluations; the command line drives them all.
GROUNDSTATION_LAYERS = (("strategy", "plans", "plots", "progress"), ("truth", "camera_view"), ("flight", "terrain_tiles"),
                        ("evaluation",), ("campaign",), ("cli",), ("__main__",))


def groundstation_package(module: str) -> str | None:
    """`groundstation.flight.explore` -> "flight"; None outside the companion."""
    parts = module.split(".")
    return parts[1] if parts[0] == "groundstation" and len(parts) > 1 else None


def test_groundstation_layers_import_downward_only():
    rank = {package: i for i, layer in enumerate(GROUNDSTATION_LAYERS) for package in layer}
    wrong, unplaced = set(), set()
    for path, modules in imports_under("groundstation").items():
        own = groundstation_package(".".join(Path(path).with_suffix("").parts))
        if own is None or own == "__init__":
            continue
        if own not in rank:
            unplaced.add(own)
            continue
        for module in modules:
            other = groundstation_package(module)
            if other is None or other == own:
                continue
            if other not in rank:
                unplaced.add(other)
            elif rank[other] >= rank[own]:
                wrong.add(f"{path} imports {module}")
    assert not unplaced, f"packages not in GROUNDSTATION_LAYERS: {sorted(unplaced)}"
    assert not wrong, sorted(wrong)


def test_the_check_sees_relative_imports():
    modules = absolute_imports(ROOT / "autopilot" / "modes" / "auto.py")
    assert "autopilot.mission.commands" in modules and "autopilot.modes.base" in modules

"""ArduCopter's surface as committed (tests/parity/surface): well-formed, consistent, current."""
from __future__ import annotations

import json
import subprocess
import tomllib
from pathlib import Path

import pytest
from pymavlink.dialects.v20 import ardupilotmega as mavlink

from tests.parity.recording import ARDUPILOT_COMMIT
from tests.parity.surface import extract

SURFACE = Path(extract.__file__).resolve().parent
DATA = json.loads((SURFACE / "arducopter.json").read_text())
SCOPE = tomllib.loads((SURFACE / "scope.toml").read_text())
KINDS = ("commands", "messages", "modes", "mission_commands")


def test_recorded_at_the_reference_commit():
    assert DATA["ardupilot_commit"] == ARDUPILOT_COMMIT
    assert DATA["generated_by"] == extract.GENERATED_BY


@pytest.mark.parametrize("kind", ["commands", "mission_commands"])
def test_commands_resolve_to_their_ids(kind):
    for entry in DATA[kind]:
        value = getattr(mavlink, entry["name"], None)
        if entry.get("in_pymavlink") is False:  # id taken from ArduPilot's own MAVLink XML
            assert value is None or value not in mavlink.enums["MAV_CMD"], entry
            continue
        assert value == entry["id"], entry
        assert mavlink.enums["MAV_CMD"][value].name == entry["name"]


def test_messages_resolve_to_their_ids():
    for entry in DATA["messages"]:
        value = getattr(mavlink, f"MAVLINK_MSG_ID_{entry['name']}", None)
        if entry.get("in_pymavlink") is False:
            assert value is None or value not in mavlink.mavlink_map, entry
            continue
        assert value == entry["id"], entry
        assert mavlink.mavlink_map[value].msgname == entry["name"]


def test_entries_are_unique_sorted_and_sourced():
    for kind in KINDS:
        names = [e["name"] for e in DATA[kind]]
        assert len(names) == len(set(names)), kind
        key = "number" if kind == "modes" else "id"
        ids = [e[key] for e in DATA[kind]]
        assert len(ids) == len(set(ids)), kind
        assert ids == sorted(ids), kind
        assert all(e["source"] for e in DATA[kind]), kind
    sim = [p["name"] for p in DATA["sim_parameters"]]
    assert sim == sorted(set(sim)) and all(n.startswith("SIM_") for n in sim)


def test_command_paths():
    for entry in DATA["commands"]:
        assert entry["paths"] in (["long", "int"], ["int"]), entry


def test_mission_command_roles():
    for entry in DATA["mission_commands"]:
        assert entry["role"] in ("nav", "do", "condition"), entry


def test_counts_are_sane_and_stated():
    counts = DATA["counts"]
    for kind in (*KINDS, "sim_parameters"):
        assert counts[kind] == len(DATA[kind]), kind
    assert len(DATA["commands"]) >= 60
    assert len(DATA["messages"]) >= 80
    assert len(DATA["mission_commands"]) >= 25
    assert len(DATA["sim_parameters"]) >= 300
    numbers = [m["number"] for m in DATA["modes"]]
    assert len(numbers) >= 25
    assert {0, 3, 4, 5, 6, 9} <= set(numbers)  # STABILIZE, AUTO, GUIDED, LOITER, RTL, LAND


def test_scope_names_exist_and_say_why():
    assert set(SCOPE) == {"out"}
    seen = set()
    for block in SCOPE["out"]:
        assert set(block) == {"kind", "names", "why"}, block
        assert block["kind"] in KINDS, block
        assert block["why"].strip(), block
        assert block["names"], block
        known = {e["name"] for e in DATA[block["kind"]]}
        for name in block["names"]:
            assert name in known, (block["kind"], name)
            assert (block["kind"], name) not in seen, name
            seen.add((block["kind"], name))


def test_scope_leaves_out_little():
    out = {kind: sum(len(b["names"]) for b in SCOPE["out"] if b["kind"] == kind) for kind in KINDS}
    for kind in KINDS:
        assert out[kind] <= len(DATA[kind]) // 5, kind


def _mirror() -> Path | None:
    """A repository holding the reference commit, when ArduPilot's MAVLink XML is also here
    (the extractor takes the ids pymavlink lacks from it)."""
    if not any((c / extract.XML_DIRS[0]).is_dir() for c in extract.SOURCE_CANDIDATES):
        return None
    for candidate in extract.SOURCE_CANDIDATES:
        if candidate.exists():
            done = subprocess.run(["git", "-C", str(candidate), "cat-file", "-e",
                                   f"{ARDUPILOT_COMMIT}^{{commit}}"], capture_output=True)
            if done.returncode == 0:
                return candidate
    return None


@pytest.mark.skipif(_mirror() is None, reason="no ArduPilot repository here (CI has none)")
def test_extraction_reproduces_the_committed_file():
    source = _mirror()
    assert source is not None
    doc = extract.extract(extract.Tree(source, ARDUPILOT_COMMIT))
    assert extract.render(doc) == (SURFACE / "arducopter.json").read_text()

"""`groundstation mission` flies .plan and .waypoints files against the real autopilot, and bad
files get one line naming where the problem is."""
from __future__ import annotations

import json
import subprocess
import sys

import pytest

from .conftest import REPO

pytestmark = pytest.mark.sitl
EXAMPLES = REPO / "examples"


def run_groundstation(*args, timeout=120):
    return subprocess.run([sys.executable, "-m", "firefly.groundstation", *args], cwd=REPO, capture_output=True,
                          text=True, timeout=timeout)


@pytest.mark.parametrize("name", ["square.plan", "square.waypoints"])
def test_mission_file_is_flown_to_the_end(autopilot, tmp_path, name):
    plot = tmp_path / "track.png"
    result = run_groundstation("mission", str(EXAMPLES / name), "--url", autopilot.mavsdk_url,
                               "--plot", str(plot))
    assert result.returncode == 0, result.stderr[-2000:]
    assert "uploaded 6 items" in result.stdout
    assert "item 6/6" in result.stdout
    summary = next(line for line in result.stdout.splitlines() if line.startswith("summary:"))
    landed = float(summary.split("landed_from_home_m ")[1].split(",")[0])
    assert landed < 2.0
    assert plot.stat().st_size > 10_000 and plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("name, items", [("survey.plan", 24), ("splines.waypoints", 11)])
def test_a_ground_station_plan_is_flown_with_its_own_autopilot_and_the_camera_watched(tmp_path, name, items):
    """Plans made by the ground stations' rules (examples/plans/): a QGC survey, and a Mission
    Planner mission whose landing after DO_LAND_START ends it (the vehicle then resets to item 1),
    flown end to end by an autopilot the command starts, the camera listener on an output of its own."""
    plot = tmp_path / "plan.png"
    result = run_groundstation("mission", str(EXAMPLES / "plans" / name), "--speedup", "20",
                               "--plot", str(plot), timeout=240)
    assert result.returncode == 0, result.stderr[-2000:]
    assert f"uploaded {items} items" in result.stdout and f"item {items}/{items}" in result.stdout
    summary = next(line for line in result.stdout.splitlines() if line.startswith("summary:"))
    fields = dict(part.rsplit(" ", 1) for part in summary.removeprefix("summary: ").split(", "))
    assert float(fields["landed_from_home_m"]) < 2.0
    assert float(fields["flown_m"]) > 0.9 * float(fields["planned_m"])  # all of it, turnarounds included
    # the survey's photos every 8 m along its transects, as ArduCopter took 37 (mission_plans)
    assert int(fields["camera_triggers"]) == (37 if name == "survey.plan" else 0)
    assert plot.stat().st_size > 10_000


def test_a_mission_the_vehicle_refuses_is_one_line(autopilot):
    """QGC's structure scan: DO_SET_ROI_WPNEXT_OFFSET is refused at upload, as ArduCopter 4.7 does."""
    result = run_groundstation("mission", str(EXAMPLES / "plans" / "structure.plan"), "--url", autopilot.mavsdk_url)
    assert result.returncode == 1
    lines = result.stderr.strip().splitlines()
    assert lines == ["groundstation: the vehicle refused the mission: UNSUPPORTED"], result.stderr[-2000:]


@pytest.mark.parametrize("content, mentions", [
    ("QGC WPL 110\n0\t1\t0\t16\t0\t0\t0\t0\t-35.36\t149.16\t584\t1\n1\t0\t3\t16\t0\t0\t0\n", ":3: expected 12 fields"),
    ("QGC WPL 110\n0\t1\t0\t16\t0\t0\t0\t0\t-35.36\t149.16\t584\t1\n1\t0\t3\t16\t0\t0\t0\t0\t95\t149\t10\t1\n", "latitude"),
    ("QGC WPL 100\n", ":1: expected the header"),
    ("not a mission", "neither"),
    (json.dumps({"fileType": "Plan", "mission": {"items": [{"type": "ComplexItem"}]}}), "items[0]"),
    (json.dumps({"fileType": "Plan", "mission": {"items": [{"type": "ComplexItem", "complexItemType": "survey",
                                                            "TransectStyleComplexItem": {"Items": []}}]}}),
     "items[0].TransectStyleComplexItem.Items"),
    (json.dumps({"fileType": "Plan", "mission": {"items": [{"type": "SimpleItem", "command": 16,
                                                            "frame": 3, "params": [0, 0, 0]}]}}), "params"),
    ("{\n  \"fileType\": \"Plan\",\n  oops\n}", ":3: not valid JSON"),
])
def test_bad_mission_file_gets_one_line(tmp_path, content, mentions):
    path = tmp_path / "bad.mission"
    path.write_text(content)
    result = run_groundstation("mission", str(path), "--url", "udpin://127.0.0.1:1", timeout=30)
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in result.stderr, result.stderr
    assert mentions in lines[0] and "bad.mission" in lines[0]

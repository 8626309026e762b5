"""The ground stations' planning rules (groundstation/plans/) and the loader of what they save."""
from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from firefly.groundstation.flight.mission_files import MissionFileError, load_mission
from firefly.groundstation.plans import examples
from firefly.groundstation.plans.corridor import Corridor
from firefly.groundstation.plans.geo import LocalFrame, offset_polygon, offset_polyline
from firefly.groundstation.plans.items import (DO_LAND_START, DO_SET_CAM_TRIGG_DIST, DO_SET_ROI_NONE,
                                               DO_SET_ROI_WPNEXT_OFFSET, NAV_SPLINE_WAYPOINT, NAV_WAYPOINT)
from firefly.groundstation.plans.transects import ENTRY, EXIT, TURNAROUND
from firefly.groundstation.plans.waypoints_file import waypoints_text

REPO = Path(__file__).resolve().parents[2]
HOME = examples.AROUND_HOME


def ne(item) -> tuple[float, float]:
    return HOME.to_ne(item.lat_deg, item.lon_deg)


def test_local_frame_round_trips_to_a_millimetre():
    frame = LocalFrame(-35.0, 149.0)
    lat, lon = frame.to_latlon(123.4, -56.7)
    assert all(abs(a - b) < 1e-3 for a, b in zip(frame.to_ne(lat, lon), (123.4, -56.7)))


def test_a_polyline_moves_left_of_travel_and_its_corner_stays_square():
    moved = offset_polyline([(0.0, 0.0), (10.0, 0.0), (10.0, 10.0)], 2.0)  # north, then east
    assert [tuple(round(v, 6) for v in p) for p in moved] == [(0.0, -2.0), (12.0, -2.0), (12.0, 10.0)]


@pytest.mark.parametrize("ring", [[(0, 0), (10, 0), (10, 10), (0, 10)], [(0, 0), (0, 10), (10, 10), (10, 0)]])
def test_a_polygon_grows_outwards_whichever_way_round(ring):
    grown = offset_polygon([tuple(map(float, p)) for p in ring], 5.0)
    assert sorted((round(n, 6), round(e, 6)) for n, e in grown) == [(-5, -5), (-5, 15), (15, -5), (15, 15)]


def test_survey_transects_are_side_spacing_apart_inside_the_field_with_turnarounds():
    transects = examples.SURVEY.transects()
    frame = examples.SURVEY.frame
    easts = [t[1].ne[1] for t in transects]
    assert len(transects) == 4 and all(abs(b - a - 15.0) < 1e-6 for a, b in zip(easts, easts[1:]))
    field = [frame.to_ne(*v) for v in examples.SURVEY.polygon]
    south, north = min(p[0] for p in field), max(p[0] for p in field)
    for k, t in enumerate(transects):
        assert [p.kind for p in t] == [TURNAROUND, ENTRY, EXIT, TURNAROUND]
        entry, exit_ = t[1].ne[0], t[2].ne[0]
        assert (entry, exit_) == pytest.approx((south, north) if k % 2 == 0 else (north, south))  # a lawnmower
        assert math.dist(t[0].ne, t[1].ne) == pytest.approx(10.0) and math.dist(t[2].ne, t[3].ne) == pytest.approx(10.0)


def test_survey_camera_starts_at_the_first_point_and_each_entry_and_stops_at_the_last():
    items = examples.SURVEY.items()
    triggers = [(k, it.params[0]) for k, it in enumerate(items) if it.command == DO_SET_CAM_TRIGG_DIST]
    assert triggers[0] == (1, 8.0) and triggers[-1] == (len(items) - 1, 0.0)
    assert sum(1 for _, d in triggers if d == 8.0) == 1 + len(examples.SURVEY.transects())
    assert all(math.isnan(it.params[3]) for it in items if it.command == NAV_WAYPOINT)  # yaw left alone


def test_corridor_has_one_transect_per_spacing_half_a_spacing_inside_each_edge():
    scan = Corridor(polyline=(LocalFrame(-35.0, 149.0).to_latlon(0, 0), LocalFrame(-35.0, 149.0).to_latlon(50, 0)),
                    width_m=20.0, altitude=20.0, side_m=10.0, trigger_m=5.0, turnaround_m=0.0)
    transects = scan.transects()
    assert [round(t[0].ne[1], 6) for t in transects] == [-5.0, 5.0]
    assert [p.kind for p in transects[1]] == [ENTRY, EXIT] and transects[1][0].ne[0] == pytest.approx(50.0)


def test_structure_scan_circles_each_layer_pointing_at_the_structure():
    items = examples.STRUCTURE.items()
    layers = sorted({it.alt_m for it in items if it.command == NAV_WAYPOINT})
    assert layers == [5.0, 15.0, 20.0]  # the layers mid-way up 10 m bands; the entrance and exit at 20 m
    assert items[1].command == DO_SET_ROI_WPNEXT_OFFSET and items[1].alt_m == 90.0
    assert items[-2].command == DO_SET_ROI_NONE
    # QGC's count: per layer the ring's vertices, back to the first, trigger on and off; ROI on
    # and off; entrance and exit
    assert len(items) == (4 + 1 + 2) * 2 + 2 + 2
    ring = [ne(it) for it in items if it.command == NAV_WAYPOINT and it.alt_m == 5.0]
    assert ring[0] == pytest.approx(ring[-1], abs=1e-6)
    assert {(round(n), round(e)) for n, e in ring} == {(20, -60), (60, -60), (60, -20), (20, -20)}


@pytest.mark.parametrize("name, scan", [("survey.plan", examples.SURVEY), ("corridor.plan", examples.CORRIDOR),
                                        ("structure.plan", examples.STRUCTURE)])
def test_a_saved_plan_loads_as_the_items_the_rules_make(name, scan):
    plan = load_mission(REPO / "examples" / "plans" / name)
    assert repr(plan.items[1:-1]) == repr(scan.items())  # repr: NaN equals NaN
    assert plan.home == examples.HOME


def test_the_committed_example_plans_are_the_ones_the_rules_make(tmp_path):
    for path in examples.write_examples(tmp_path):
        assert path.read_bytes() == (REPO / "examples" / "plans" / path.name).read_bytes(), f"make plans: {path.name}"


def test_mission_planner_file_has_splines_and_a_landing_sequence():
    text = waypoints_text(examples.HOME, examples.SPLINES)
    rows = [line.split("\t") for line in text.splitlines()[1:]]
    assert text.startswith("QGC WPL 110\r\n") and all(len(r) == 12 for r in rows)
    commands = [int(r[3]) for r in rows]
    assert commands.count(NAV_SPLINE_WAYPOINT) == 4
    assert commands.index(DO_LAND_START) < len(commands) - 1 and commands[-1] == 21
    plan = load_mission(REPO / "examples" / "plans" / "splines.waypoints")
    assert [it.command for it in plan.items] == commands[1:]


def _plan_with(item: dict) -> str:
    return json.dumps({"fileType": "Plan", "mission": {"items": [item]}})


@pytest.mark.parametrize("item, mentions", [
    ({"type": "ComplexItem", "complexItemType": "survey"}, "items[0].TransectStyleComplexItem"),
    ({"type": "ComplexItem", "complexItemType": "survey", "TransectStyleComplexItem": {"Items": [{"command": 16}]}},
     "TransectStyleComplexItem.Items[0]"),
    ({"type": "ComplexItem", "complexItemType": "fw landing"}, "complexItemType"),
    ({**examples.STRUCTURE.qgc_json(), "Layers": "two"}, "items[0].Layers"),
    ({**examples.STRUCTURE.qgc_json(), "polygon": [[1, 2]]}, "items[0].polygon"),
    ({**examples.STRUCTURE.qgc_json(), "CameraCalc": {"DistanceToSurface": None}}, "CameraCalc.DistanceToSurface"),
])
def test_a_bad_complex_item_is_refused_naming_the_field(tmp_path, item, mentions):
    path = tmp_path / "bad.plan"
    path.write_text(_plan_with(item))
    with pytest.raises(MissionFileError, match=mentions.replace("[", r"\[").replace("]", r"\]")):
        load_mission(path)

"""Waypoint legs flown like ArduCopter's S-curve navigation: the real autopilot process flies the
recorded courses (AUTO missions, RTL's return) over pymavlink and its track is compared with the
reference's figures (tests/parity/recorded/, measured on ArduCopter SITL by the same code)."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.parity.rtl_return import fly as fly_rtl
from tests.parity.square import fly, reduce

RECORDED = json.loads((Path(__file__).parents[1] / "parity" / "recorded" / "wpnav_square.json").read_text())
TOLERANCE_M = 1.0
LEG_TIME_TOLERANCE_S = 1.0


@pytest.mark.parametrize("case", sorted(RECORDED["cases"]))
def test_waypoint_course_tracks_within_a_metre_of_arducopter(autopilot, case):
    spec = RECORDED["cases"][case]
    reference = spec["reference"]
    flown = reduce(fly(autopilot.pymavlink_url, spec["speed_cms"], spec["side_m"], spec["turn_deg"], timeout=300))
    assert len(flown["corners"]) == len(reference["corners"])
    for ours, theirs in zip(flown["corners"], reference["corners"]):
        assert ours["signed_m"] < 0.0, f"corner {ours['corner']} passed outside"
        assert abs(ours["signed_m"] - theirs["signed_m"]) <= TOLERANCE_M, (ours, theirs)
    for ours, theirs in zip(flown["legs"], reference["legs"], strict=True):
        assert abs(ours["cross_track_mid_m"] - theirs["cross_track_mid_m"]) <= TOLERANCE_M, (ours, theirs)
        assert abs(ours["cross_track_max_m"] - theirs["cross_track_max_m"]) <= TOLERANCE_M, (ours, theirs)
        assert abs(ours["time_s"] - theirs["time_s"]) <= LEG_TIME_TOLERANCE_S, (ours, theirs)
    assert abs(flown["path_m"] - reference["path_m"]) <= 0.03 * reference["planned_m"]


def test_rtl_climbs_then_returns_on_a_leg_like_arducopter(autopilot):
    recorded = json.loads((Path(__file__).parents[1] / "parity" / "recorded" / "rtl_return.json").read_text())
    reference = recorded["reference_figures"]
    flown = fly_rtl(autopilot.pymavlink_url)
    for name in ("climb_time_s", "time_to_2m_of_home_s", "time_to_0.3m_s"):
        assert abs(flown[name] - reference[name]) <= LEG_TIME_TOLERANCE_S, (name, flown, reference)
    for name in ("moved_home_when_climbed_m", "overshoot_past_home_m", "max_sideways_m", "max_alt_m"):
        assert abs(flown[name] - reference[name]) <= TOLERANCE_M, (name, flown, reference)

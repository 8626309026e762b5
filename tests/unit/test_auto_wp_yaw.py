"""WP_YAW_BEHAVIOR in AUTO's waypoint legs and its RTL item, flown by the real vehicle model in
process. ArduCopter 4.7 SITL's figures (tests/parity/recorded/mission_wpyaw.json): a leg east
faces 90° for 1, 2 and 3; the way home from there faces home for 1 and 3 and keeps 45° (the last
leg's heading) for 2, and 1 and 3 turn back to the armed heading over home before descending; 0
never turns."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.mission import MissionItem

from ._util import altitude, fly_until, hovering_vehicle
from .test_auto_items_navgeo import WAYPOINT, item_at

RTL = 20


def heading_deg(v) -> float:
    return math.degrees(v.attitude[2]) % 360.0


def off(a: float, b: float) -> float:
    return abs((a - b + 180.0) % 360.0 - 180.0)


def fly_east_then_home(behaviour: int) -> dict[str, float]:
    """Headings mid-way along a leg 20 m east, mid-way home in the RTL item and low in its
    descent."""
    v = hovering_vehicle()
    v.params.set("WP_YAW_BEHAVIOR", behaviour)
    armed = heading_deg(v)
    v.mission.replace(0, [item_at(v, WAYPOINT, 0, 20), MissionItem(RTL, 3, 0, 0, 0, 0, 0, 0, 0)])
    v.set_mode(3)
    assert fly_until(v, lambda x: x.body.e_m > 10.0, 20.0)
    leg = heading_deg(v)
    assert fly_until(v, lambda x: 1 in x.mission_progress.reached, 20.0)
    assert fly_until(v, lambda x: x.body.e_m < 10.0, 40.0)
    home = heading_deg(v)
    assert fly_until(v, lambda x: altitude(x) < 2.0, 90.0)
    return {"armed": armed, "leg": leg, "home": home, "descent": heading_deg(v)}


@pytest.mark.parametrize("behaviour", [1, 3])
def test_facing_the_way_also_home_then_back_to_the_armed_heading(behaviour):
    h = fly_east_then_home(behaviour)
    assert off(h["leg"], 90.0) < 5.0
    assert off(h["home"], 270.0) < 8.0
    assert off(h["descent"], h["armed"]) < 3.0


def test_two_faces_the_legs_but_holds_its_heading_in_the_rtl():
    h = fly_east_then_home(2)
    assert off(h["leg"], 90.0) < 5.0
    assert off(h["home"], 90.0) < 5.0 and off(h["descent"], 90.0) < 5.0


def test_zero_never_turns():
    h = fly_east_then_home(0)
    assert max(off(h[k], h["armed"]) for k in ("leg", "home", "descent")) < 3.0

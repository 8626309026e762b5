"""DO_SET_RESUME_REPEAT_DIST flown by the real vehicle model: a mission left part-way along a leg
and resumed flies back over the last metres first (mission/rewind.py). The figures are the
reference's (tests/parity/recorded/mission_resume.json): left 25 m east on a leg running east
from A, a 10 m rewind goes back to 15 m east, a 50 m one to A itself, none stays; each turns
back onto the leg short of its point (ArduCopter's least east: 17.3 m and 1.5 m)."""
from __future__ import annotations

import pytest

from firefly.autopilot.mission import MissionItem
from firefly.autopilot.mission.rewind import RETURNED, WaypointHistory

from ._util import fly_until, hovering_vehicle

REL, AUTO, LOITER = 3, 3, 5


def wp_at(v, n, e, alt=10.0, command=16):
    g = v.ned_to_global(n, e, 0.0)
    return MissionItem(command, REL, 0, 0, 0, 0, int(round(g.lat_deg * 1e7)), int(round(g.lon_deg * 1e7)), alt)


def resumed(repeat_m: int):
    """The mission A, B, C with the repeat distance, left at 25 m east on A-B for 4 s of LOITER and
    resumed: the least east flown after the resume, and the texts said."""
    v = hovering_vehicle()
    v.mission.replace(0, [MissionItem(215, REL, repeat_m), wp_at(v, 20, 0), wp_at(v, 20, 40), wp_at(v, 0, 40)])
    v.set_mode(AUTO)
    assert fly_until(v, lambda x: x.mission_progress.current_seq() == 3 and x.body.e_m >= 25.0, 60.0)
    v.drain_events()
    v.set_mode(LOITER)
    v.run_until(v.time_s + 4.0)
    v.set_mode(AUTO)
    least = [v.body.e_m]
    assert fly_until(v, lambda x: least.append(x.body.e_m) or 4 in x.mission_progress.reached, 60.0)
    return min(least), [t for _, t in v.drain_events()]


@pytest.mark.parametrize("repeat_m, least_east_m", [(10, 17.3), (50, 1.5)])
def test_a_resume_flies_back_its_repeat_distance_first(repeat_m, least_east_m):
    least, said = resumed(repeat_m)
    assert least == pytest.approx(least_east_m, abs=1.5)
    assert said.count("Mission: 2 WP") == 1 and RETURNED in said
    assert said.index("Mission: 2 WP") < said.index(RETURNED) < said.index("Mission: 4 WP")


def test_without_a_repeat_distance_the_leg_goes_on_from_where_it_was_left():
    least, said = resumed(0)
    assert least > 24.0 and "Mission: 2 WP" not in said and RETURNED not in said


def test_the_history_keeps_the_last_waypoints_with_a_location_and_forgets_on_clear():
    h = WaypointHistory()
    items = [MissionItem(16, REL, x=10 * k, y=1) for k in range(1, 10)]
    for k, it in enumerate(items):
        assert not h.loaded(k, it, 5)
    assert not h.loaded(99, MissionItem(16, REL), 5)  # no location: not kept
    assert h.indexes == [2, 3, 4, 5, 6, 7, 8]
    assert h.rewind(items, None, 5) is None  # no exit position
    h.clear()
    assert h.indexes == [None] * 7 and h.rewind(items, (0.0, 0.0), 5) is None

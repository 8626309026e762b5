"""AUTO's NAV_LOITER_TURNS, NAV_LOITER_TO_ALT and NAV_SPLINE_WAYPOINT, flown by the real vehicle
model in process; the figures are ArduCopter 4.7 SITL's (tests/parity/recorded/mission_navgeo.json)."""
from __future__ import annotations

import math

from firefly.autopilot.control.spline import SplineLeg
from firefly.autopilot.mission import MissionItem
from firefly.autopilot.mission.progress import MissionState
from firefly.autopilot.modes.auto_items.loiter_turns import radius_of, turns_of
from firefly.autopilot.results import Result

from ._util import altitude, fly_until, hovering_vehicle

REL = 3  # MAV_FRAME_GLOBAL_RELATIVE_ALT
TURNS, TO_ALT, SPLINE, WAYPOINT = 18, 31, 82, 16


def item_at(v, command, n=None, e=None, alt=10.0, p1=0.0, p3=0.0) -> MissionItem:
    if n is None:
        return MissionItem(command, REL, p1, 0, p3, 0, 0, 0, alt)
    g = v.ned_to_global(n, e, 0.0)
    return MissionItem(command, REL, p1, 0, p3, 0, int(round(g.lat_deg * 1e7)), int(round(g.lon_deg * 1e7)), alt)


def said(v) -> list[str]:
    return [text for _, text in v.events]


def track_while(v, predicate, timeout_s: float) -> list[tuple[float, float, float, float]]:
    """(time, north, east, heading) every 0.1 s while predicate holds."""
    samples = []
    end = v.time_s + timeout_s
    while predicate(v) and v.time_s < end:
        v.run_until(v.time_s + 0.1)
        samples.append((v.time_s, v.body.n_m, v.body.e_m, v.attitude[2]))
    return samples


def test_loiter_turns_params_as_ap_mission_stores_them():
    assert turns_of(2.7) == 2 and turns_of(300) == 255 and turns_of(0.5) == 0.5 and turns_of(-1) == 0
    assert turns_of(float("nan")) == 0
    assert radius_of(10.9) == 10 and radius_of(-5) == 5 and radius_of(1234) == 1230 and radius_of(5000) == 2550


def test_two_turns_clockwise_round_a_point_at_the_radius_and_the_rate():
    """ArduCopter: 2 turns of 10 m take 18.7 s and 18.0 s (CIRCLE_RATE 20 deg/s), 9.7 m flown."""
    v = hovering_vehicle()
    v.mission.replace(0, [item_at(v, TURNS, 15, 0, p1=2, p3=10), item_at(v, WAYPOINT, 0, 0)])
    assert v.set_mode(3) == Result.ACCEPTED
    assert fly_until(v, lambda x: "Mission: starting circle 1/2" in said(x), 30.0)
    start = v.time_s
    samples = track_while(v, lambda x: 1 not in x.mission_progress.reached, 60.0)
    assert 1 in v.mission_progress.reached
    assert 35.0 < v.time_s - start < 39.0  # two turns
    radii = [math.hypot(n - 15, e) for _, n, e, _ in samples]
    assert 9.0 < sum(radii) / len(radii) < 10.2
    # clockwise seen from above: the bearing from the centre grows
    angles = [math.atan2(e, n - 15) for _, n, e, _ in samples]
    turned = sum((b - a + math.pi) % (2 * math.pi) - math.pi for a, b in zip(angles, angles[1:]))
    assert 1.8 < turned / (2 * math.pi) < 2.05
    # nose at the centre
    _, n, e, yaw = samples[len(samples) // 2]
    to_centre = math.atan2(-e, 15 - n)
    assert abs((yaw - to_centre + math.pi) % (2 * math.pi) - math.pi) < math.radians(10)
    texts = said(v)
    assert texts.index("Mission: starting circle 2/2") < texts.index("Mission: starting circle 3/2")
    assert "Reached command #1" not in texts  # ArduCopter's verify_circle says none


def test_a_negative_radius_turns_counter_clockwise():
    v = hovering_vehicle()
    v.mission.replace(0, [item_at(v, TURNS, 0, 10, p1=1, p3=-5), item_at(v, WAYPOINT, 0, 0)])
    v.set_mode(3)
    assert fly_until(v, lambda x: any(t.startswith("Mission: starting circle 1/") for t in said(x)), 30.0)
    samples = track_while(v, lambda x: 1 not in x.mission_progress.reached, 40.0)
    angles = [math.atan2(e - 10, n) for _, n, e, _ in samples]
    turned = sum((b - a + math.pi) % (2 * math.pi) - math.pi for a, b in zip(angles, angles[1:]))
    assert -1.05 < turned / (2 * math.pi) < -0.85


def test_radius_zero_after_boot_turns_on_the_spot_and_zero_turns_end_at_the_edge():
    """ArduCopter's circle navigator starts with radius 0: a panorama of one turn in 18.5 s; then
    0 turns of 5 m: done on reaching the circle, 'starting circle 1/0'."""
    v = hovering_vehicle()
    v.mission.replace(0, [item_at(v, TURNS, p1=1), item_at(v, TURNS, 0, 20, p1=0, p3=5), item_at(v, WAYPOINT, 0, 0)])
    v.set_mode(3)
    start = v.time_s
    samples = track_while(v, lambda x: 1 not in x.mission_progress.reached, 30.0)
    assert 17.0 < v.time_s - start < 20.0
    assert max(math.hypot(n, e) for _, n, e, _ in samples) < 1.0
    yaws = [y for *_, y in samples]
    nose = sum((b - a + math.pi) % (2 * math.pi) - math.pi for a, b in zip(yaws, yaws[1:]))
    assert 0.9 < nose / (2 * math.pi) < 1.05
    assert fly_until(v, lambda x: 2 in x.mission_progress.reached, 30.0)
    assert abs(math.hypot(v.body.n_m, v.body.e_m - 20) - 5.0) < 1.5
    assert "Mission: starting circle 1/0" in said(v)


def test_loiter_to_alt_flies_there_then_climbs_and_reports_no_reached():
    """ArduCopter: the item is done with no MISSION_ITEM_REACHED and no text; 20 m reached."""
    v = hovering_vehicle()
    v.mission.replace(0, [item_at(v, TO_ALT, 20, 0, alt=20.0), item_at(v, TO_ALT, alt=6.0), item_at(v, WAYPOINT, 0, 0)])
    v.set_mode(3)
    assert fly_until(v, lambda x: x.mission_progress.current_seq() == 2, 30.0)
    assert abs(altitude(v) - 20.0) < 0.3 and math.hypot(v.body.n_m - 20, v.body.e_m) < 2.0
    assert fly_until(v, lambda x: x.mission_progress.current_seq() == 3, 30.0)
    assert abs(altitude(v) - 6.0) < 0.3 and math.hypot(v.body.n_m - 20, v.body.e_m) < 2.0
    assert fly_until(v, lambda x: x.mission_progress.state is MissionState.COMPLETE, 40.0)
    assert v.mission_progress.reached == [3]
    assert not any(t.startswith("Reached command #1") or t.startswith("Reached command #2") for t in said(v))


def test_splines_round_a_square_bulge_as_arducopters_and_each_is_reached():
    """ArduCopter: 20.2 s from the first spline to the waypoint after the third; 3.3, 5.6, 5.5 m
    off the square's sides; the middle one climbs to 14 m."""
    v = hovering_vehicle()
    v.mission.replace(0, [item_at(v, SPLINE, 20, 0), item_at(v, SPLINE, 20, 20, alt=14.0), item_at(v, SPLINE, 0, 20),
                          item_at(v, WAYPOINT, 0, 0)])
    v.set_mode(3)
    start = v.time_s
    samples = track_while(v, lambda x: x.mission_progress.current_seq() < 4, 40.0)
    assert 17.0 < v.time_s - start < 23.0
    bulge = max(max(-e, n - 20, e - 20) for _, n, e, _ in samples)
    assert 4.0 < bulge < 7.0
    assert fly_until(v, lambda x: x.mission_progress.state is MissionState.COMPLETE, 30.0)
    assert v.mission_progress.reached == [1, 2, 3, 4]
    assert [t for t in said(v) if t.startswith("Reached")] == [f"Reached command #{i}" for i in (1, 2, 3, 4)]


def test_a_spline_leg_with_no_length_or_limits_ends_rather_than_hangs():
    """Never down: a spline onto its own origin, or with zero speed limits, is over at once."""
    here = SplineLeg((0.0, 0.0, -10.0), (0.0, 0.0, -10.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), 10, 2.5, 1.5, 2.5, 1.0)
    assert here.reached
    stuck = SplineLeg((0.0, 0.0, 0.0), (10.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), 0, 0, 0, 0, 0)
    stuck.advance(0.01, 0.0)
    assert stuck.reached


def test_a_circle_rate_set_after_boot_does_not_reach_auto():
    """ArduCopter's AC_Circle copies CIRCLE_RATE's default when built: with CIRCLE_RATE set to 10
    after boot a turn of 10 m still takes 18.6 s (at 10 deg/s it would take 36)."""
    v = hovering_vehicle()
    v.params.set("CIRCLE_RATE", 10.0)
    v.mission.replace(0, [item_at(v, TURNS, 10, 0, p1=1, p3=10), item_at(v, WAYPOINT, 0, 0)])
    v.set_mode(3)
    assert fly_until(v, lambda x: "Mission: starting circle 1/1" in said(x), 30.0)
    start = v.time_s
    assert fly_until(v, lambda x: 1 in x.mission_progress.reached, 40.0)
    assert 17.5 < v.time_s - start < 20.0


def test_a_spline_with_a_hold_time_stops_at_its_point_and_waits_whole_seconds():
    """Param 1: the curve ends at rest on the point (no vector onwards) and 'Reached command'
    comes once the hold is over (ArduCopter counts whole seconds)."""
    v = hovering_vehicle()
    v.mission.replace(0, [item_at(v, SPLINE, 15, 0, p1=3.7), item_at(v, WAYPOINT, 0, 0)])
    v.set_mode(3)
    assert fly_until(v, lambda x: math.hypot(x.body.n_m - 15, x.body.e_m) < 1.0 and
                     math.hypot(x.body.vn_m_s, x.body.ve_m_s) < 0.2, 30.0)
    arrived = v.time_s
    assert fly_until(v, lambda x: 1 in x.mission_progress.reached, 10.0)
    assert 2.0 < v.time_s - arrived < 4.0
    assert math.hypot(v.body.n_m - 15, v.body.e_m) < 1.0

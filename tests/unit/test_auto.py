"""AUTO mode and MISSION_START as ArduCopter handles them."""
from __future__ import annotations

import math

from firefly.autopilot.mission import MissionItem
from firefly.autopilot.mission.progress import MissionState
from firefly.autopilot.results import Result

from ._util import altitude, fly_until, hovering_vehicle, ready_vehicle

REL = 3  # MAV_FRAME_GLOBAL_RELATIVE_ALT


def wp_at(v, n, e, alt=10.0, command=16, p1=0.0):
    g = v.ned_to_global(n, e, 0.0)
    return MissionItem(command, REL, p1, 0, 0, 0, int(round(g.lat_deg * 1e7)), int(round(g.lon_deg * 1e7)), alt)


def takeoff(alt=10.0):
    return MissionItem(22, REL, z=alt)


def test_mission_start_on_the_ground_needs_a_takeoff_first():
    v = ready_vehicle()
    v.mission.replace(0, [wp_at(v, 20, 0)])
    v.set_mode(4)
    assert v.arm() == Result.ACCEPTED
    assert v.mission_start() == Result.FAILED
    assert [t for _, t in v.events][-2:] == ["Auto: Missing Takeoff Cmd", "Mode change to AUTO failed: init failed"]
    assert v.mode.number == 4


def test_auto_on_the_ground_starts_the_mission_but_waits_for_mission_start_to_fly():
    v = ready_vehicle()
    v.mission.replace(0, [takeoff(), wp_at(v, 20, 0)])
    v.set_mode(4)
    v.arm()
    assert v.set_mode(3) == Result.ACCEPTED
    v.run_until(v.time_s + 3.0)
    assert v.landed and v.mission_progress.running and v.mission_progress.current_seq() == 1
    assert v.mission_start() == Result.ACCEPTED
    assert fly_until(v, lambda x: altitude(x) > 9.5, 20.0)
    # The leg's S-curve ends at rest on the waypoint: reached once it is over, within the radius.
    assert fly_until(v, lambda x: len(x.mission_progress.reached) >= 2, 20.0)
    assert abs(v.body.n_m - 20) < 2.0
    assert v.mission_progress.reached[:2] == [1, 2]


def test_a_waypoint_made_current_while_auto_waits_on_the_ground_is_flown_on_mission_start():
    """AUTO held on the ground (its leg ended); MISSION_SET_CURRENT to a waypoint, then
    MISSION_START: the leg starts from where the vehicle is (it had raised an internal error)."""
    v = ready_vehicle()
    v.mission.replace(0, [takeoff(), wp_at(v, 20, 0), wp_at(v, 20, 20)])
    v.set_mode(4)
    v.arm()
    assert v.set_mode(3) == Result.ACCEPTED
    v.run_until(v.time_s + 1.0)
    assert v.set_mission_current(2)
    v.run_until(v.time_s + 0.5)
    assert v.mission_start() == Result.ACCEPTED
    v.run_until(v.time_s + 5.0)
    assert not v.internal_errors and v.mode.number == 3 and v.armed


def test_mission_start_announces_the_first_item_twice_as_arducopter():
    """MISSION_START starts the mission, and AUTO's first tick resumes it (restarting the item)."""
    v = ready_vehicle()
    v.mission.replace(0, [takeoff(), wp_at(v, 20, 0)])
    v.set_mode(4)
    v.arm()
    v.drain_events()
    assert v.mission_start() == Result.ACCEPTED
    v.run_until(v.time_s + 0.1)
    assert [t for _, t in v.drain_events() if t.startswith("Mission")] == ["Mission: 1 Takeoff"] * 2


def test_after_landing_and_a_new_upload_auto_starts_the_new_mission_from_its_first_item():
    """Issue 12: disarming resets the mission; the new list is flown from item 1, not resumed."""
    v = hovering_vehicle()
    v.mission.replace(0, [wp_at(v, 10, 0), MissionItem(20, REL)])
    v.set_mode(3)
    assert fly_until(v, lambda x: not x.armed, 120.0)
    assert v.mission_progress.state is MissionState.COMPLETE and v.mission_progress.current_seq() == 0
    v.mission.replace(0, [takeoff(), wp_at(v, 0, 15), wp_at(v, 15, 15), MissionItem(20, REL)])
    v.set_mode(4)
    assert v.arm() == Result.ACCEPTED and v.takeoff(10) == Result.ACCEPTED
    assert fly_until(v, lambda x: altitude(x) > 9.5, 30.0)
    v.drain_events()
    assert v.set_mode(3) == Result.ACCEPTED
    v.run_until(v.time_s + 0.1)
    assert v.mission_progress.current_seq() in (1, 2)
    assert "Mission: 1 Takeoff" in [t for _, t in v.drain_events()]


def test_leaving_auto_and_a_new_upload_in_flight_resumes_at_the_same_index():
    v = hovering_vehicle()
    v.mission.replace(0, [wp_at(v, 5, 0), wp_at(v, 30, 0), wp_at(v, 30, 30)])
    v.set_mode(3)
    assert fly_until(v, lambda x: x.mission_progress.current_seq() == 2, 60.0)
    v.set_mode(4)
    assert v.mission_progress.state is MissionState.NOT_STARTED
    v.mission.replace(0, [wp_at(v, 0, 5), wp_at(v, 0, 20), wp_at(v, 20, 20), wp_at(v, 20, 0)])
    v.set_mode(3)
    v.run_until(v.time_s + 0.1)
    assert v.mission_progress.current_seq() == 2
    assert fly_until(v, lambda x: abs(x.body.e_m - 20) < 2 and abs(x.body.n_m) < 2, 60.0)


def test_mis_restart_1_restarts_the_mission_on_entering_auto():
    v = hovering_vehicle()
    v.params.set("MIS_RESTART", 1)
    v.mission.replace(0, [wp_at(v, 5, 0), wp_at(v, 30, 0), wp_at(v, 30, 30)])
    v.set_mode(3)
    assert fly_until(v, lambda x: x.mission_progress.current_seq() == 2, 60.0)
    v.set_mode(4)
    v.drain_events()
    v.set_mode(3)
    v.run_until(v.time_s + 0.01)
    assert v.mission_progress.current_seq() == 1 and v.drain_events()[0][1] == "Mission: 1 WP"


def test_auto_in_the_air_starts_at_once_without_takeoff_item():
    v = hovering_vehicle()
    v.mission.replace(0, [wp_at(v, 0, 25), wp_at(v, 25, 25)])
    assert v.set_mode(3) == Result.ACCEPTED
    assert fly_until(v, lambda x: v.mission_progress.state is MissionState.COMPLETE, 60.0)
    assert abs(v.body.n_m - 25) < 2.0 and abs(v.body.e_m - 25) < 2.0
    assert v.armed  # a mission that does not land ends in a hover


def test_vtol_takeoff_and_land_items_are_flown_as_the_plain_ones():
    """As ArduCopter's AUTO on a multicopter: "Mission: 1 VTOLTakeoff" climbs, VTOLLand lands."""
    v = hovering_vehicle()
    v.mission.replace(0, [MissionItem(84, REL, z=15.0), wp_at(v, 10, 0, alt=15.0), MissionItem(85, REL)])
    assert v.set_mode(3) == Result.ACCEPTED
    assert fly_until(v, lambda x: altitude(x) > 14.5, 30.0)
    assert fly_until(v, lambda x: not x.armed, 90.0)
    said = [text for _, text in v.events]
    assert "Mission: 1 VTOLTakeoff" in said and "Mission: 3 VTOLLand" in said
    assert not any(t.startswith("Skipping") for t in said)


def test_do_jump_repeats_and_unsupported_items_are_skipped():
    v = hovering_vehicle()
    items = [wp_at(v, 10, 0), wp_at(v, 0, 0), MissionItem(177, 2, p1=1, p2=2),
             MissionItem(31000, 2), wp_at(v, 0, 10)]
    v.mission.replace(0, items)
    v.set_mode(3)
    assert fly_until(v, lambda x: v.mission_progress.state is MissionState.COMPLETE, 120.0)
    assert v.mission_progress.reached.count(1) == 3 and v.mission_progress.reached.count(2) == 3  # first pass + two repeats
    assert [t for _, t in v.events if "Jump" in t] == ["Mission: 3 Jump 1/2", "Mission: 3 Jump 2/2"]
    assert any("Skipping invalid cmd #31000" in text for _, text in v.events)


def test_loiter_time_holds_for_its_time():
    v = hovering_vehicle()
    v.mission.replace(0, [wp_at(v, 0, 0, command=19, p1=8.0), wp_at(v, 10, 0)])
    v.set_mode(3)
    t0 = v.time_s
    assert fly_until(v, lambda x: 1 in x.mission_progress.reached, 30.0)
    assert v.time_s - t0 >= 8.0
    assert "Reached command #1" in [text for _, text in v.events]  # ArduCopter's verify_loiter_time says so


def test_mission_land_and_rtl_end_disarmed_at_the_spot():
    v = hovering_vehicle()
    v.mission.replace(0, [wp_at(v, 15, 0), MissionItem(20, 2)])
    v.set_mode(3)
    assert fly_until(v, lambda x: not x.armed, 120.0)
    assert abs(v.body.n_m) < 1.0 and abs(v.body.e_m) < 1.0
    assert v.mission_progress.state is MissionState.COMPLETE  # the RTL item done, then disarmed
    v2 = hovering_vehicle()
    v2.mission.replace(0, [MissionItem(21, REL, x=0, y=0, z=0)])
    v2.set_mode(3)
    assert fly_until(v2, lambda x: not x.armed, 60.0)
    # ArduCopter disarms in the land item; the reset mission runs on from its first item.
    v2.run_until(v2.time_s + 0.1)
    assert v2.mission_progress.running and v2.mission_progress.current_seq() == 1


def test_set_current_jumps_in_flight():
    v = hovering_vehicle()
    v.mission.replace(0, [wp_at(v, 40, 0), wp_at(v, 0, 30)])
    v.set_mode(3)
    v.run_until(v.time_s + 1.0)
    assert v.set_mission_current(2)
    assert fly_until(v, lambda x: abs(x.body.e_m - 30) < 2 and abs(x.body.n_m) < 2, 40.0)
    assert not v.set_mission_current(7)


def corner_speeds(hold_s: float) -> list[float]:
    """Horizontal speeds flown within 3 m of the corner of takeoff, (20, 0) with hold_s, (20, 20)."""
    v = hovering_vehicle()
    v.mission.replace(0, [takeoff(), wp_at(v, 20, 0, p1=hold_s), wp_at(v, 20, 20)])
    v.set_mode(3)
    speeds = []

    def near_corner_track(x):
        if math.hypot(x.body.n_m - 20, x.body.e_m) < 3.0:
            speeds.append(math.hypot(x.body.vn_m_s, x.body.ve_m_s))
        return len(x.mission_progress.reached) >= 3
    assert fly_until(v, near_corner_track, 60.0)
    return speeds


def test_a_waypoint_is_flown_through_into_the_next_leg_unless_it_has_a_hold_time():
    assert min(corner_speeds(0.0)) > 2.0   # blended: no stop at the corner
    assert min(corner_speeds(2.0)) < 0.3   # a hold time: it stops there first

def test_set_current_in_guided_is_where_auto_resumes():
    v = hovering_vehicle()
    v.mission.replace(0, [takeoff(), wp_at(v, 40, 0), wp_at(v, 0, 30)])
    assert v.set_mission_current(3) and v.mission_progress.state is MissionState.NOT_STARTED
    v.set_mode(3)
    v.run_until(v.time_s + 0.05)
    assert v.mission_progress.current_seq() == 3


def test_a_mission_ending_in_the_air_completes_and_auto_again_starts_over():
    v = hovering_vehicle()
    v.mission.replace(0, [takeoff(), wp_at(v, 8, 0)])
    v.set_mode(3)
    assert fly_until(v, lambda x: x.mission_progress.state is MissionState.COMPLETE, 60.0)
    assert v.armed and v.mission_progress.current_seq() == 2
    assert not any(t == "Mission complete" for _, t in v.events)  # ArduCopter says nothing
    v.set_mode(4)
    v.drain_events()
    v.set_mode(3)
    v.run_until(v.time_s + 0.01)
    assert v.mission_progress.running and [t for _, t in v.drain_events()] == ["Mission: 1 Takeoff"]


def _flying_the_first_waypoint(v):
    """AUTO over [wp 30 m north, wp 30 m north 30 east, wp 0 30 east, wp 0 0, RTL], the first
    waypoint being flown; the texts so far drained."""
    items = [wp_at(v, 30, 0), wp_at(v, 30, 30), wp_at(v, 0, 30), wp_at(v, 0, 0), MissionItem(20, REL)]
    v.mission.replace(0, items)
    assert v.set_mode(3) == Result.ACCEPTED
    v.run_until(v.time_s + 2.0)
    assert v.mission_progress.current_seq() == 1
    v.drain_events()
    return items


def _upload_item_by_item(v, items):
    """As an upload writes them: the count shortens the list, then one item per tick."""
    v.mission.truncate(0, len(items))
    for index, item in enumerate(items):
        v.mission.put(0, index, item)
        v.run_until(v.time_s + 0.01)
    v.mission.changed()
    v.run_until(v.time_s + 0.5)
    return [t for _, t in v.drain_events() if t.startswith("Auto mission changed")]


def test_an_upload_of_the_same_mission_during_auto_restarts_nothing():
    v = hovering_vehicle()
    items = _flying_the_first_waypoint(v)
    assert _upload_item_by_item(v, items) == []
    assert v.mission_progress.current_seq() == 1


def test_an_upload_changing_only_items_past_the_next_two_restarts_nothing():
    """ArduCopter's change detector looks at the current navigation item and the next two."""
    v = hovering_vehicle()
    items = _flying_the_first_waypoint(v)
    changed = items[:3] + [wp_at(v, -10, -10)] + items[4:]
    assert _upload_item_by_item(v, changed) == []


def test_an_upload_changing_the_next_waypoint_restarts_the_current_one_once():
    v = hovering_vehicle()
    items = _flying_the_first_waypoint(v)
    changed = items[:1] + [wp_at(v, 40, 40)] + items[2:]
    assert _upload_item_by_item(v, changed) == ["Auto mission changed, restarted command"]
    assert v.mission_progress.current_seq() == 1


def test_set_current_into_a_loop_of_do_items_without_navigation_ends():
    """Only "do" items and an unlimited DO_JUMP back to them: MISSION_SET_CURRENT while the mission
    is not running searched (and counted jumps, with a text each) for ever, until memory ran out."""
    v = ready_vehicle()
    v.mission.replace(0, [MissionItem(178, REL, 1, 5.0), MissionItem(177, REL, 1, -1)])
    assert v.set_mission_current(1) is False
    assert len(v.events) <= 64 and v.mission_progress.nav_index is None


def test_pause_stops_a_waypoint_leg_and_continue_flies_the_rest():
    """DO_PAUSE_CONTINUE in AUTO (the guided parity area compares it with ArduCopter's)."""
    v = hovering_vehicle()
    v.mission.replace(0, [wp_at(v, 120, 0)])
    assert v.set_mode(3) == Result.ACCEPTED
    assert fly_until(v, lambda x: x.body.vn_m_s > 7.0, 30.0)
    assert v.pause(True) == Result.ACCEPTED
    assert fly_until(v, lambda x: abs(x.body.vn_m_s) < 0.1, 10.0)
    stopped = v.body.n_m
    v.run_until(v.time_s + 3.0)
    assert abs(v.body.n_m - stopped) < 0.5 and stopped < 100.0
    assert v.pause(False) == Result.ACCEPTED
    assert fly_until(v, lambda x: v.mission_progress.state is MissionState.COMPLETE, 60.0)
    assert abs(v.body.n_m - 120.0) < 2.0
    assert v.pause(True) == Result.FAILED  # the leg is over: nothing to pause, as ArduCopter


def test_climb_speed_of_do_change_speed_holds_for_the_legs_after_it():
    v = hovering_vehicle()
    v.mission.replace(0, [wp_at(v, 0, 5, alt=10.0), wp_at(v, 0, 5, alt=30.0)])
    assert v.set_mode(3) == Result.ACCEPTED
    assert v.set_vertical_speed(1.0, None) == Result.ACCEPTED
    assert fly_until(v, lambda x: altitude(x) > 15.0, 60.0)
    assert 0.8 < -v.body.vd_m_s < 1.2

"""AUTO's timed and conditional items flown by the real vehicle model: NAV_DELAY, NAV_SCRIPT_TIME,
NAV_ATTITUDE_TIME, NAV_GUIDED_ENABLE, NAV_PAYLOAD_PLACE, CONDITION_DELAY / DISTANCE / YAW.
The figures they are held to were measured on ArduCopter SITL (tests/parity/recorded/
mission_navtime.json)."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.mission import MissionItem
from firefly.autopilot.modes.auto_items.guided_limits import GuidedLimits
from firefly.autopilot.modes.auto_items.nav_delay import ms_until_utc
from firefly.autopilot.results import Result

from ._util import altitude, fly_until, hovering_vehicle

REL = 3  # MAV_FRAME_GLOBAL_RELATIVE_ALT
NAV_DELAY, PAYLOAD_PLACE, GUIDED_ENABLE, SCRIPT_TIME, ATTITUDE_TIME = 93, 94, 92, 42702, 42703
COND_DELAY, COND_DISTANCE, COND_YAW = 112, 114, 115


def wp_at(v, n, e, alt=10.0, command=16, params=(0.0, 0.0, 0.0, 0.0)):
    g = v.ned_to_global(n, e, 0.0)
    return MissionItem(command, REL, *params, int(round(g.lat_deg * 1e7)), int(round(g.lon_deg * 1e7)), alt)


def item(command, *params, x=0):
    p = (list(params) + [0.0] * 4)[:4]
    return MissionItem(command, REL, *p, x, 0, 0.0)


def flown(v, middle):
    """AUTO on the mission waypoint A (20 m north), the item(s) under test, waypoint B (20 m
    north, 20 m east), from a hover at 10 m; the vehicle's texts so far drained."""
    v.mission.replace(0, [wp_at(v, 20, 0), *middle, wp_at(v, 20, 20)])
    v.drain_events()
    v.set_mode(3)
    return v


def reached_at(v, seq, timeout_s):
    assert fly_until(v, lambda x: seq in x.mission_progress.reached, timeout_s), f"item {seq} not reached"
    return v.time_s


def heading_deg(v) -> float:
    return math.degrees(v.attitude[2]) % 360.0


def texts(v) -> list[str]:
    return [t for _, t in v.drain_events()]


def test_nav_delay_holds_where_it_is_for_its_seconds():
    v = flown(hovering_vehicle(), [item(NAV_DELAY, 5, -1, -1, -1)])
    t_a = reached_at(v, 1, 30.0)
    here = (v.body.n_m, v.body.e_m)
    assert fly_until(v, lambda x: x.mission_progress.current_seq() == 2, 1.0)
    assert "Delaying 5 sec" in texts(v)
    assert not fly_until(v, lambda x: 2 in x.mission_progress.reached, 4.8)
    assert math.hypot(v.body.n_m - here[0], v.body.e_m - here[1]) < 0.5
    assert reached_at(v, 2, 1.0) - t_a == pytest.approx(5.0, abs=0.2)


# AP_RTC counts a field left out (-1) below the largest one given as -1 itself: minute 15 with no
# second is 14:59 past the hour, 9 o'clock with nothing else 08:59:59.
@pytest.mark.parametrize("hour, minute, second, want_s", [
    (-1, -1, 30, 20.0),       # the next :30 of a minute: 20 s on
    (-1, -1, 5, 55.0),        # :05 is past: the next minute's
    (-1, 15, -1, 5 * 60 - 11.0),
    (9, -1, -1, 86400 - 2 * 3600 - 11 * 60 - 11.0),  # past: tomorrow's
    (-1, -1, -1, 0.0),        # no field: no wait
])
def test_time_of_day_delays_as_ap_rtc(hour, minute, second, want_s):
    now_ms = ((11 * 60 + 10) * 60 + 10) * 1000  # 11:10:10.000 UTC
    assert ms_until_utc(now_ms, hour, minute, second) / 1000.0 == want_s


def test_nav_delay_to_a_second_of_the_minute_waits_on_the_utc_clock():
    v = hovering_vehicle()
    now_s = v.unix_time_us() / 1e6
    target = int(now_s + 40) % 60  # a second of the minute about 40 s ahead, the flight to A within it
    flown(v, [item(NAV_DELAY, -1, -1, -1, target)])
    reached_at(v, 1, 30.0)
    assert fly_until(v, lambda x: 2 in x.mission_progress.reached, 60.0)
    assert int(v.unix_time_us() / 1e6) % 60 == target


def test_condition_delay_holds_back_only_its_own_item_while_the_leg_goes_on():
    v = flown(hovering_vehicle(), [item(COND_DELAY, 4)])
    t_a = reached_at(v, 1, 30.0)
    t_met = reached_at(v, 2, 10.0)
    assert t_met - t_a == pytest.approx(4.0, abs=0.1)  # the reference: 4.0
    assert v.body.e_m > 5.0  # flying the leg to B meanwhile
    reached_at(v, 3, 30.0)
    assert v.mission_progress.reached[:3] == [1, 2, 3]
    assert "Skipping invalid cmd #112" not in texts(v)


def test_condition_distance_is_met_within_its_metres_of_the_next_point():
    v = flown(hovering_vehicle(), [item(COND_DISTANCE, 8)])
    reached_at(v, 1, 30.0)
    reached_at(v, 2, 20.0)
    to_b = math.hypot(20 - v.body.n_m, 20 - v.body.e_m)
    assert 7.0 < to_b < 8.0  # the reference, at its 10 Hz stream: 8.3


def test_condition_yaw_turns_to_an_absolute_heading_and_keeps_it_on_the_leg():
    v = flown(hovering_vehicle(), [item(COND_YAW, 180, 0, 0, 0)])
    t_a = reached_at(v, 1, 30.0)
    assert reached_at(v, 2, 10.0) - t_a == pytest.approx(2.5, abs=0.5)  # the reference: 2.5 s at 60 deg/s
    assert heading_deg(v) == pytest.approx(180.0, abs=2.0)
    reached_at(v, 3, 30.0)
    assert heading_deg(v) == pytest.approx(180.0, abs=3.0)  # not the leg's 90: the reference 181


def test_condition_yaw_relative_counter_clockwise_at_its_rate():
    v = flown(hovering_vehicle(), [item(COND_YAW, 90, 30, -1, 1)])
    t_a = reached_at(v, 1, 30.0)
    assert reached_at(v, 2, 10.0) - t_a == pytest.approx(3.2, abs=0.5)  # 90 at 30 deg/s; the reference: 3.2
    # from the heading steered to as A's corner turned the nose (about 45), 90 counter-clockwise:
    # the reference's 319
    assert heading_deg(v) == pytest.approx(318.0, abs=5.0)
    reached_at(v, 3, 30.0)
    assert heading_deg(v) == pytest.approx(315.0, abs=5.0)


def test_attitude_time_holds_its_attitude_and_climb_for_its_time():
    v = flown(hovering_vehicle(), [item(ATTITUDE_TIME, 4, 0, 0, 270, x=1)])
    t_a = reached_at(v, 1, 30.0)
    alt0 = altitude(v)
    t_done = reached_at(v, 2, 10.0)
    assert t_done - t_a == pytest.approx(4.0, abs=0.2)
    assert heading_deg(v) == pytest.approx(270.0, abs=3.0)
    assert 2.5 < altitude(v) - alt0 < 4.5  # 1 m/s; the reference climbed 3.5 m


def test_script_time_without_scripts_ends_at_its_timeout_and_waits_with_none():
    v = flown(hovering_vehicle(), [item(SCRIPT_TIME, 0, 4)])
    t_a = reached_at(v, 1, 30.0)
    assert reached_at(v, 2, 10.0) - t_a == pytest.approx(4.0, abs=0.2)
    v = flown(hovering_vehicle(), [item(SCRIPT_TIME, 0, 0)])
    reached_at(v, 1, 30.0)
    assert not fly_until(v, lambda x: 2 in x.mission_progress.reached, 20.0)
    assert v.mission_progress.current_seq() == 2


def test_guided_enable_on_waits_holding_and_off_goes_on_at_once():
    v = flown(hovering_vehicle(), [item(GUIDED_ENABLE, 1)])
    reached_at(v, 1, 30.0)
    here = (v.body.n_m, v.body.e_m, altitude(v))
    assert not fly_until(v, lambda x: 2 in x.mission_progress.reached, 15.0)
    assert v.mission_progress.current_seq() == 2 and v.mode.number == 3
    assert math.dist(here, (v.body.n_m, v.body.e_m, altitude(v))) < 0.5
    v = flown(hovering_vehicle(), [item(GUIDED_ENABLE, 0)])
    t_a = reached_at(v, 1, 30.0)
    assert reached_at(v, 2, 1.0) - t_a < 0.1


def test_payload_place_flies_to_its_point_sets_down_and_climbs_back():
    v = hovering_vehicle()
    flown(v, [wp_at(v, 30, 10, command=PAYLOAD_PLACE)])
    t_a = reached_at(v, 1, 30.0)
    lowest = [altitude(v)]
    assert fly_until(v, lambda x: lowest.append(altitude(x)) or 2 in x.mission_progress.reached, 60.0)
    assert v.time_s - t_a == pytest.approx(34.1, abs=5.0)  # the reference: 34.1 s
    assert min(lowest) < 0.2 and v.armed
    assert altitude(v) == pytest.approx(10.0, abs=0.3)
    assert math.hypot(v.body.n_m - 30, v.body.e_m - 10) < 1.0
    said = texts(v)
    assert "PayloadPlace: payload release thrust threshold: 0.315000" in said
    assert "PayloadPlace: landed" not in said  # the touchdown is seen before the land detector fires


def test_payload_place_stops_at_its_maximum_descent_and_climbs_back():
    v = flown(hovering_vehicle(), [item(PAYLOAD_PLACE, 4)])
    reached_at(v, 1, 30.0)
    lowest = [altitude(v)]
    assert fly_until(v, lambda x: lowest.append(altitude(x)) or 2 in x.mission_progress.reached, 40.0)
    assert min(lowest) == pytest.approx(5.8, abs=0.5)  # the reference: 5.8
    assert "PayloadPlace: Reached maximum descent" in texts(v)
    assert altitude(v) == pytest.approx(10.0, abs=0.3)


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf, 1e30])
def test_items_with_unusable_params_do_not_bring_the_vehicle_down(bad):
    v = hovering_vehicle()
    odd = [item(c, bad, bad, bad, bad) for c in (COND_YAW, NAV_DELAY, COND_DELAY, COND_DISTANCE, SCRIPT_TIME,
                                                  ATTITUDE_TIME, PAYLOAD_PLACE, GUIDED_ENABLE)]
    flown(v, [odd[0], odd[1], odd[2], odd[3], odd[4], odd[5], odd[6], odd[7]])
    v.run_until(v.time_s + 20.0)
    assert v.armed and not v.internal_errors and v.mode.number == 3


def test_a_navigation_item_after_condition_yaw_flies_its_own_heading():
    """ArduCopter's attitude hold steers its own yaw; a delay keeps the turn."""
    v = flown(hovering_vehicle(), [item(COND_YAW, 180), item(NAV_DELAY, 4), item(ATTITUDE_TIME, 4, 0, 0, 90)])
    reached_at(v, 2, 40.0)  # the turn, met during the delay
    reached_at(v, 3, 10.0)
    assert heading_deg(v) == pytest.approx(180.0, abs=3.0)
    reached_at(v, 4, 10.0)
    assert heading_deg(v) == pytest.approx(90.0, abs=3.0)


def test_guided_enable_ends_at_the_timeout_of_the_guided_limits_before_it():
    v = flown(hovering_vehicle(), [item(222, 5, 0, 0, 0), item(GUIDED_ENABLE, 1)])
    reached_at(v, 2, 30.0)  # the limits: a "do" item, reported as ArduCopter's AUTO does
    t0 = v.time_s
    assert reached_at(v, 3, 10.0) - t0 == pytest.approx(5.0, abs=0.2)


def test_guided_limits_on_height_and_distance_end_the_guided_item():
    v = hovering_vehicle()
    ctx = v.ctx
    start = (v.body.n_m, v.body.e_m)
    assert not GuidedLimits().broken(ctx, v.time_s, start)
    assert GuidedLimits(alt_range_m=(0.0, 5.0)).broken(ctx, v.time_s, start)
    assert GuidedLimits(alt_range_m=(15.0, 0.0)).broken(ctx, v.time_s, start)
    assert not GuidedLimits(alt_range_m=(5.0, 15.0), horiz_max_m=1.0).broken(ctx, v.time_s, start)
    assert GuidedLimits(horiz_max_m=1.0).broken(ctx, v.time_s, (start[0] + 2.0, start[1]))
    assert GuidedLimits(timeout_s=1.0).broken(ctx, v.time_s - 1.0, start)


def _companion_east(v) -> bool:
    """A companion's 2 m/s east, sent every tick while AUTO takes it; True once item 3 is reached."""
    if v.mode.in_guided_mode:
        v.guided_target(None, (0.0, 2.0, 0.0), None)
    return 3 in v.mission_progress.reached


@pytest.mark.parametrize("command", [GUIDED_ENABLE, SCRIPT_TIME])
def test_a_companion_steers_auto_during_its_guided_items_and_the_limits_end_them(command):
    """ArduCopter's AUTO is "in guided mode" during NAV_GUIDED_ENABLE and NAV_SCRIPT_TIME: a
    velocity target flies it; DO_GUIDED_LIMITS' 15 m ends the guided item, not the script's."""
    v = flown(hovering_vehicle(), [item(222, 0, 0, 0, 15), item(command, 1, 0)])
    assert not v.mode.in_guided_mode
    assert v.guided_target(None, (0.0, 2.0, 0.0), None) == Result.DENIED  # no guided item yet
    reached_at(v, 2, 30.0)
    assert fly_until(v, lambda x: x.mission_progress.current_seq() == 3, 2.0)
    start_e, t0 = v.body.e_m, v.time_s
    assert v.mode.in_guided_mode
    if command == GUIDED_ENABLE:
        assert fly_until(v, _companion_east, 20.0)
        assert v.body.e_m - start_e == pytest.approx(15.0, abs=1.0)
        assert v.time_s - t0 == pytest.approx(8.5, abs=1.5)  # 2 m/s, after speeding up
        assert not v.mode.in_guided_mode
    else:  # no script to end it, no limit: the companion flies it on
        assert not fly_until(v, _companion_east, 10.0)
        assert v.body.e_m - start_e > 15.0 and v.mode.in_guided_mode

"""Mission progress over the wire, as ArduCopter's SITL does it (issue 12, "Missions"): a landed
vehicle flies a newly uploaded mission from its first item; one that never disarmed resumes it
at the item it left. The parity area `missions` compares the same situations, fact by fact, with
the recorded ArduCopter (tests/parity/recorded/missions.json)."""
from __future__ import annotations

import pytest
from pymavlink import mavutil

from .pymav import Gcs, take_off, upload_mission

pytestmark = pytest.mark.sitl
mav = mavutil.mavlink
AUTO, GUIDED = 3, 4
TAKEOFF, WAYPOINT, RTL = mav.MAV_CMD_NAV_TAKEOFF, mav.MAV_CMD_NAV_WAYPOINT, mav.MAV_CMD_NAV_RETURN_TO_LAUNCH


@pytest.fixture
def gcs(autopilot):
    g = Gcs(autopilot.pymavlink_url)
    yield g
    g.close()


def home(gcs: Gcs) -> tuple:
    """Where the vehicle is, once it knows: before a location (a rebooted vehicle before its GPS
    fix) GLOBAL_POSITION_INT is all zeros, as ArduCopter's."""
    pos = gcs.recv("GLOBAL_POSITION_INT", 30, lambda m: m.lat != 0 or m.lon != 0)
    assert pos is not None, "no location"
    return pos.lat, pos.lon


def north_east(origin: tuple, n_m: float, e_m: float) -> tuple:
    """x, y (1e-7 degrees) n_m north and e_m east of origin; about 0.09 m per unit near 43.5 deg."""
    return origin[0] + int(n_m / 0.0111), origin[1] + int(e_m / 0.00805)


def mission_current(gcs: Gcs, condition, timeout: float = 60.0):
    msg = gcs.recv("MISSION_CURRENT", timeout, condition)
    assert msg is not None, "no matching MISSION_CURRENT"
    return msg


def texts_until(gcs: Gcs, last: str, timeout: float = 60.0) -> list:
    """STATUSTEXTs up to and including the first that reads `last`."""
    texts = []
    while True:
        msg = gcs.recv("STATUSTEXT", timeout)
        assert msg is not None, f"no {last!r} after {texts}"
        texts.append(msg.text)
        if msg.text == last:
            return texts


def test_a_new_mission_after_landing_is_flown_from_its_first_item(gcs):
    origin = home(gcs)
    upload_mission(gcs, [(TAKEOFF, 0, 0, 10.0), (WAYPOINT, *north_east(origin, 15, 0), 10.0), (RTL, 0, 0, 0.0)])
    assert gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, GUIDED) == mav.MAV_RESULT_ACCEPTED
    assert gcs.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1) == mav.MAV_RESULT_ACCEPTED
    assert gcs.command(mav.MAV_CMD_MISSION_START) == mav.MAV_RESULT_ACCEPTED
    flown = texts_until(gcs, "Disarming motors", 120)
    assert [t for t in flown if t.startswith(("Mission", "Reached"))] == [
        "Mission: 1 Takeoff", "Mission: 1 Takeoff", "Mission: 2 WP", "Reached command #2", "Mission: 3 RTL"]
    # Disarmed at the end: the mission is complete and reset (no current item), still in AUTO.
    done = mission_current(gcs, lambda m: m.seq == 0)
    assert (done.total, done.mission_state, done.mission_mode) == (3, mav.MISSION_STATE_COMPLETE, 1)

    upload_mission(gcs, [(TAKEOFF, 0, 0, 10.0), (WAYPOINT, *north_east(origin, 0, 15), 10.0),
                         (WAYPOINT, *north_east(origin, 15, 15), 10.0), (RTL, 0, 0, 0.0)])
    take_off(gcs, 10.0)
    assert gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, AUTO) == mav.MAV_RESULT_ACCEPTED
    started = texts_until(gcs, "Mission: 2 WP")
    assert [t for t in started if t.startswith("Mission")] == ["Mission: 1 Takeoff", "Mission: 2 WP"]
    running = mission_current(gcs, lambda m: m.seq == 2)
    assert (running.total, running.mission_state, running.mission_mode) == (4, mav.MISSION_STATE_ACTIVE, 1)


def test_a_mission_left_in_flight_resumes_at_its_item_in_a_new_list(gcs):
    origin = home(gcs)
    wp = [(WAYPOINT, *north_east(origin, n, e), 10.0) for n, e in ((12, 0), (12, 12), (0, 12))]
    upload_mission(gcs, [(TAKEOFF, 0, 0, 10.0), *wp, (RTL, 0, 0, 0.0)])
    take_off(gcs, 10.0)
    assert gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, AUTO) == mav.MAV_RESULT_ACCEPTED
    texts_until(gcs, "Mission: 3 WP")
    assert gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, GUIDED) == mav.MAV_RESULT_ACCEPTED
    left = mission_current(gcs, lambda m: m.mission_mode == 0)
    assert (left.seq, left.mission_state) == (3, mav.MISSION_STATE_NOT_STARTED)
    upload_mission(gcs, [(TAKEOFF, 0, 0, 10.0), *reversed(wp), (WAYPOINT, *north_east(origin, 5, 5), 10.0),
                         (RTL, 0, 0, 0.0)])
    assert gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, AUTO) == mav.MAV_RESULT_ACCEPTED
    assert texts_until(gcs, "Mission: 3 WP")[-1] == "Mission: 3 WP"
    resumed = mission_current(gcs, lambda m: m.mission_mode == 1 and m.mission_state == mav.MISSION_STATE_ACTIVE)
    assert (resumed.seq, resumed.total) == (3, 6)

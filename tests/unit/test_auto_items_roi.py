"""A region of interest (DO_SET_ROI_LOCATION, DO_SET_ROI, DO_SET_ROI_NONE): the nose points at it,
in AUTO as a mission item and in GUIDED as a command, until cleared. Figures: ArduCopter SITL
(tests/parity/recorded/surface_mission.json: a leg flown east with an ROI to the west reaches its
end at 270 degrees; surface_commands.json: an ROI 50 m to the right turns the nose 90 degrees)."""
from __future__ import annotations

import math

from firefly.autopilot.mission import MissionItem
from firefly.autopilot.results import Result

from ._util import fly_until, hovering_vehicle, ready_vehicle
from .test_auto import takeoff, wp_at

REL = 3


def heading_deg(v) -> float:
    return math.degrees(v.estimate.attitude[2]) % 360.0


def roi_item(v, n, e, command=195):
    g = v.ned_to_global(n, e, 0.0)
    return MissionItem(command, REL, x=int(round(g.lat_deg * 1e7)), y=int(round(g.lon_deg * 1e7)), z=0.0)


def test_a_leg_flown_east_faces_an_roi_to_the_west():
    v = ready_vehicle()
    v.mission.replace(0, [takeoff(), wp_at(v, 20, 0), roi_item(v, 20, -30), wp_at(v, 20, 20),
                          wp_at(v, 20, 40)])
    v.set_mode(4)
    assert v.arm() == Result.ACCEPTED
    v.mission_start()
    assert fly_until(v, lambda x: x.mission_progress.current_seq() == 5, 60.0)  # waypoint B reached
    assert abs(heading_deg(v) - 270.0) < 15.0
    assert v.body.e_m > 15.0  # it flew the leg east all the same


def test_roi_none_gives_the_heading_back_to_the_legs():
    v = ready_vehicle()
    v.mission.replace(0, [takeoff(), wp_at(v, 20, 0), roi_item(v, 20, -30), wp_at(v, 20, 20),
                          MissionItem(197, REL), wp_at(v, 20, 60)])
    v.set_mode(4)
    v.arm()
    v.mission_start()
    assert fly_until(v, lambda x: x.mission_progress.current_seq() == 6 and x.body.e_m > 35.0, 80.0)
    assert abs(heading_deg(v) - 90.0) < 15.0  # facing the way it flies again


def test_the_command_turns_guided_to_the_point_and_none_clears_it():
    v = hovering_vehicle()
    assert v.mode.number == 4
    start = heading_deg(v)
    n, e = v.body.n_m, v.body.e_m
    target = math.radians(start + 90.0)
    assert v.set_roi((n + 50 * math.cos(target), e + 50 * math.sin(target), 0.0)) == Result.ACCEPTED
    v.run_until(v.time_s + 6.0)
    assert abs((heading_deg(v) - start - 90.0 + 180.0) % 360.0 - 180.0) < 10.0
    assert v.set_roi(None) == Result.ACCEPTED
    turned = heading_deg(v)
    v.run_until(v.time_s + 3.0)
    assert abs((heading_deg(v) - turned + 180.0) % 360.0 - 180.0) < 5.0  # held where it was


def test_modes_that_steer_no_heading_accept_the_command_and_keep_theirs():
    v = hovering_vehicle()
    assert v.set_mode(5) == Result.ACCEPTED  # LOITER: the pilot's heading
    start = heading_deg(v)
    assert v.set_roi((v.body.n_m, v.body.e_m + 50.0, 0.0)) == Result.ACCEPTED
    v.run_until(v.time_s + 4.0)
    assert abs((heading_deg(v) - start + 180.0) % 360.0 - 180.0) < 5.0

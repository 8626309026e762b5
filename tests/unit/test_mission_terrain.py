"""A mission at heights above terrain on a vehicle with no terrain data (ArduCopter SITL with no
ground station serving tiles: tests/parity/recorded/mission_terrain.json): the upload is taken,
arming is refused "waiting for terrain data", and nothing flies."""
from __future__ import annotations

from firefly.autopilot.mission import MissionItem
from firefly.autopilot.modes import Guided
from firefly.autopilot.results import Result

from ._util import ready_vehicle

TERRAIN_ALT, TERRAIN_ALT_INT, REL = 10, 11, 3


def with_mission(frame: int, command: int = 16):
    v = ready_vehicle()
    v.mission.replace(0, [MissionItem(22, REL, 0, 0, 0, 0, 0, 0, 10.0),
                          MissionItem(command, frame, 0, 0, 0, 0, -353630000, 1491650000, 10.0)])
    assert v.set_mode(Guided.number) == Result.ACCEPTED
    return v


def said(v) -> list[str]:
    return [text for _, text in v.events]


def test_a_terrain_frame_waypoint_refuses_arming_without_terrain_data():
    for frame in (TERRAIN_ALT, TERRAIN_ALT_INT):
        v = with_mission(frame)
        assert v.arm() == Result.FAILED and not v.armed
        assert "Arm: waiting for terrain data" in said(v)


def test_terrain_disabled_is_said_so_and_a_relative_mission_arms():
    v = with_mission(TERRAIN_ALT)
    v.params.set("TERRAIN_ENABLE", 0)
    assert v.arm() == Result.FAILED and "Arm: terrain disabled" in said(v)
    assert with_mission(REL).arm() == Result.ACCEPTED


def test_a_terrain_frame_on_an_item_with_no_location_needs_no_terrain():
    # DO_CHANGE_SPEED keeps no location (AP_Mission::stored_in_location): its frame is not looked at
    assert with_mission(TERRAIN_ALT, command=178).arm() == Result.ACCEPTED

"""JUMP_TAG / DO_JUMP_TAG and the texts of AP_Mission's own do-items, flown in AUTO on the real
vehicle model (the figures are ArduCopter SITL's, tests/parity/recorded/surface_mission.json)."""
from __future__ import annotations

from firefly.autopilot.mission import MissionItem
from firefly.autopilot.results import Result

from ._util import fly_until, ready_vehicle
from .test_auto import takeoff, wp_at

REL = 3


def tag(number: int) -> MissionItem:
    return MissionItem(600, REL, p1=number)


def jump_to_tag(number: int, repeat: int) -> MissionItem:
    return MissionItem(601, REL, p1=number, p2=repeat)


def fly_mission(items, limit_s=90.0):
    v = ready_vehicle()
    v.mission.replace(0, items(v))
    v.set_mode(4)
    assert v.arm() == Result.ACCEPTED
    v.drain_events()
    assert v.mission_start() == Result.ACCEPTED
    reached: list[int] = []
    texts: list[str] = []

    def landed_or_done(x):
        reached.extend(x.mission_progress.drain_reached())
        texts.extend(t for _, t in x.drain_events())
        return not x.armed

    assert fly_until(v, landed_or_done, limit_s)
    return reached, texts


def test_do_jump_tag_flies_again_from_its_tag_as_arducopter():
    """Measured: reached 1, 3, 3, 5 and "Mission: 4 Jump 1/1" between the two "Tag 0"s."""
    reached, texts = fly_mission(lambda v: [takeoff(), tag(7), wp_at(v, 20, 0), jump_to_tag(7, 1),
                                            wp_at(v, 20, 20), MissionItem(21, REL)])
    assert reached[:4] == [1, 3, 3, 5]
    missions = [t for t in texts if t.startswith("Mission")]
    missions = missions[missions.index("Mission: 2 Tag 0") - 1:]  # MISSION_START and AUTO both start item 1
    assert missions[:7] == ["Mission: 1 Takeoff", "Mission: 2 Tag 0", "Mission: 3 WP", "Mission: 4 Jump 1/1",
                            "Mission: 2 Tag 0", "Mission: 3 WP", "Mission: 5 WP"]
    assert not any(t.startswith("Skipping") for t in texts)


def test_a_jump_to_a_tag_no_item_carries_ends_the_mission_there():
    """AP_Mission finds no item to go on with (its jump target is 0): the mission completes."""
    v = ready_vehicle()
    v.mission.replace(0, [takeoff(), wp_at(v, 10, 0), jump_to_tag(3, 1), wp_at(v, 20, 20)])
    v.set_mode(4)
    v.arm()
    v.mission_start()
    assert fly_until(v, lambda x: x.mission_progress.state.name == "COMPLETE", 40.0)
    assert abs(v.body.n_m - 10) < 2.0 and abs(v.body.e_m) < 2.0  # never went on to (20, 20)


def test_gripper_and_repeat_distance_say_what_arducopter_says():
    reached, texts = fly_mission(lambda v: [takeoff(), MissionItem(211, REL, p1=1, p2=0),
                                            MissionItem(211, REL, p1=1, p2=1), MissionItem(215, REL, p1=10),
                                            wp_at(v, 5, 0), MissionItem(21, REL)], limit_s=60.0)
    assert "Gripper Released" in texts
    for first, then in (("Mission: 2 Gripper", "Gripper Released"), ("Mission: 3 Gripper", "Gripper Grabbed"),
                        ("Mission: 4 SetRepeatDist", "Resume repeat dist set to 10 m")):
        assert texts[texts.index(first) + 1] == then
    assert 2 not in reached and 4 not in reached  # AP_Mission's own items are never reported reached

"""DO_FENCE_ENABLE as a mission item and as a command: the fences switch at run time, FENCE_ENABLE
is kept (figures and texts: ArduCopter SITL, tests/parity/recorded/surface_mission.json and
surface_commands.json)."""
from __future__ import annotations

from firefly.autopilot.mission import MissionItem
from firefly.autopilot.results import Result
from firefly.autopilot.safety.fence_switch import fence_names

from ._util import fly_until, ready_vehicle
from .test_auto import takeoff, wp_at

REL = 3


def test_fence_names_read_as_arducopters():
    assert fence_names(7) == "Max Alt, Circle and Polygon fences"
    assert fence_names(2) == "Circle fence"
    assert fence_names(9) == "Max Alt and Min Alt fences"


def test_the_mission_item_switches_every_configured_fence_on_and_says_so():
    v = ready_vehicle()
    v.mission.replace(0, [takeoff(), wp_at(v, 10, 0), MissionItem(207, REL, p1=1), wp_at(v, 10, 10)])
    v.set_mode(4)
    v.arm()
    v.drain_events()
    v.mission_start()
    assert not v.fence.enabled
    assert fly_until(v, lambda x: x.fence.enabled, 40.0)
    assert "Max Alt, Circle and Polygon fences enabled" in [t for _, t in v.drain_events()]
    assert v.params["FENCE_ENABLE"] == 0  # a run-time switch: the parameter is not written
    assert fly_until(v, lambda x: 3 in x.mission_progress.reached or x.mission_progress.state.name == "COMPLETE", 5.0)


def test_the_command_switches_fences_and_refuses_what_is_not_there():
    v = ready_vehicle()
    assert v.fence_enable(1, 0) == Result.ACCEPTED and v.fence.enabled_fences == 7
    assert v.fence_enable(2, 0) == Result.ACCEPTED and v.fence.enabled_fences == 7  # no floor was on
    assert v.fence_enable(0, 2) == Result.ACCEPTED and v.fence.enabled_fences == 5  # the circle alone off
    assert v.fence_enable(0, 0) == Result.ACCEPTED and not v.fence.enabled
    v.params.set("FENCE_TYPE", 4)  # a polygon fence and no polygon uploaded: nothing to switch on
    assert v.fence_enable(1, 4) == Result.FAILED and not v.fence.enabled
    assert v.fence_enable(7, 0) == Result.FAILED


def test_setting_fence_enable_switches_the_configured_fences_less_the_floor():
    v = ready_vehicle()
    v.params.set("FENCE_TYPE", 15)
    v.params.set("FENCE_ENABLE", 1)
    assert v.fence.enabled_fences == 7
    v.params.set("FENCE_ENABLE", 0)
    assert not v.fence.enabled

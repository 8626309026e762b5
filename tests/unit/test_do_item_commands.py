"""The mission's do-items sent as commands (mavlink/do_item_commands.py), through the session as
on the wire; results as ArduCopter SITL gave them (tests/parity/recorded/surface_commands.json)."""
from __future__ import annotations

from firefly.autopilot.mavlink.dialect import mavlink as mav
from firefly.autopilot.mission import MissionItem

from ._session_link import Link, link  # noqa: F401 - the fixture
from ._util import of_type
from .test_auto import takeoff, wp_at

REL = 3


def test_set_mission_current_without_a_mission_is_denied(link):  # noqa: F811
    ack, _ = link.command(mav.MAV_CMD_DO_SET_MISSION_CURRENT, 1, 0)
    assert ack.result == mav.MAV_RESULT_DENIED


def test_set_mission_current_makes_the_item_current_and_says_so(link):  # noqa: F811
    v = link.vehicle
    v.mission.replace(0, [takeoff(), wp_at(v, 10, 0), wp_at(v, 20, 0)])
    ack, out = link.command(mav.MAV_CMD_DO_SET_MISSION_CURRENT, 3, 0)
    assert ack.result == mav.MAV_RESULT_ACCEPTED
    assert v.mission_progress.current_seq() == 3
    assert [m.seq for m in of_type(out, "MISSION_CURRENT")] == [3]
    ack, _ = link.command(mav.MAV_CMD_DO_SET_MISSION_CURRENT, 4, 0)
    assert ack.result == mav.MAV_RESULT_DENIED
    ack, _ = link.command(mav.MAV_CMD_DO_SET_MISSION_CURRENT, float("nan"), 0)
    assert ack.result == mav.MAV_RESULT_DENIED


def test_jump_tag_goes_to_the_tag_or_fails(link):  # noqa: F811
    v = link.vehicle
    ack, _ = link.command(mav.MAV_CMD_DO_JUMP_TAG, 1)
    assert ack.result == mav.MAV_RESULT_FAILED  # no mission, no tag: as ArduCopter
    v.mission.replace(0, [takeoff(), wp_at(v, 10, 0), MissionItem(600, REL, p1=5), wp_at(v, 20, 0)])
    ack, out = link.command(mav.MAV_CMD_DO_JUMP_TAG, 5)
    assert ack.result == mav.MAV_RESULT_ACCEPTED
    assert v.mission_progress.current_seq() == 4  # the navigation item after the tag
    assert of_type(out, "MISSION_CURRENT")
    assert link.command(mav.MAV_CMD_DO_JUMP_TAG, 70000)[0].result == mav.MAV_RESULT_DENIED


def test_fence_enable_command_sets_the_sys_status_bit_and_streams_fence_status():
    link = Link()
    ack, _ = link.command(mav.MAV_CMD_DO_FENCE_ENABLE, 1)
    assert ack.result == mav.MAV_RESULT_ACCEPTED
    link.vehicle.run_until(link.vehicle.time_s + 2.0)
    out = link.poll()
    status = of_type(out, "SYS_STATUS")[-1]
    assert status.onboard_control_sensors_enabled & mav.MAV_SYS_STATUS_GEOFENCE
    link.session.receive(mav.MAVLink_request_data_stream_message(1, 1, mav.MAV_DATA_STREAM_EXTENDED_STATUS, 2, 1),
                         link.vehicle.time_s)
    link.vehicle.run_until(link.vehicle.time_s + 1.5)
    assert of_type(link.poll(), "FENCE_STATUS")

"""Never down: modes chosen before home, and a bug in the loop handled as an ArduPilot internal
error (counted, reported in SYS_STATUS / HEARTBEAT / a pre-arm failure, the vehicle landing)
instead of an exit; commands answered once, also when their handler fails, retries recognised
on the link clock."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.mavlink.commands import HANDLERS, Command, CommandService
from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.mavlink.session import Session
from firefly.autopilot.modes import Guided, Land, ModeNumber
from firefly.autopilot.results import Result
from firefly.autopilot.safety.internal_error import FLOW_OF_CONTROL
from firefly.autopilot.startup import StartupTimeline
from firefly.autopilot.vehicle import Vehicle, VehicleConfig

from ._util import client_codec, fly_until, hovering_vehicle, mav, wire

NOT_YET = [ModeNumber.RTL, ModeNumber.AUTO]


def booting_vehicle() -> Vehicle:
    """A vehicle booting as ArduCopter does: no GPS fix and no home for its first seconds."""
    v = Vehicle(VehicleConfig(startup=StartupTimeline()))
    v.run_until(1.0)
    assert v.home_ned is None
    return v


@pytest.mark.parametrize("mode", NOT_YET)
def test_a_mode_that_measures_from_home_is_entered_before_home_and_waits(mode):
    v = booting_vehicle()
    assert v.set_mode(mode) == Result.ACCEPTED  # ArduCopter lets a disarmed vehicle choose it
    assert v.mode.number == mode and not v.mode_flying
    v.run_until(5.0)  # still no home: the mode flies nothing, and nothing raises
    assert v.home_ned is None and not v.internal_errors
    assert fly_until(v, lambda x: x.home_ned is not None, 120.0)
    v.run_until(v.time_s + 1.0)
    assert v.mode_flying and not v.internal_errors and not v.armed


def test_land_before_home_is_flown_at_once_measuring_from_the_boot_ground():
    v = booting_vehicle()
    assert v.set_mode(ModeNumber.LAND) == Result.ACCEPTED and v.mode_flying
    v.run_until(3.0)
    assert not v.internal_errors and v.home_ned is None


def test_without_gps_arming_sets_no_home_and_land_brings_it_down():
    v = Vehicle(VehicleConfig(faults={"SIM_GPS_DISABLE": 1}))
    v.run_until(1.0)
    assert v.set_mode(ModeNumber.ALT_HOLD) == Result.ACCEPTED
    assert v.arm() == Result.ACCEPTED and v.home_ned is None  # as ArduCopter: home needs a fix
    assert v.set_home(None) == Result.FAILED
    end = v.time_s + 7.0  # the arming delay, the spool-up and the throttle's slew before it leaves the ground
    while v.time_s < end:  # climb on the throttle stick, held
        v.rc.hold_sticks(0.0, 0.0, 0.0, 0.9, v.time_s)
        v.run_until(v.time_s + 0.1)
    assert v.boot_ground_d - v.body.d_m > 2.0, "it climbed"
    assert v.set_mode(ModeNumber.LAND) == Result.ACCEPTED
    assert fly_until(v, lambda x: not x.armed, 60.0), "landed and disarmed without home"
    assert not v.internal_errors


def test_commands_before_home_are_answered_and_change_nothing_they_should_not():
    v = booting_vehicle()
    s = Session(v, new_codec(1))
    c = client_codec()
    for msg in (c.command_long_encode(1, 1, mav.MAV_CMD_NAV_LAND, 0, 0, 0, 0, 0, 0, 0, 0),
                c.command_long_encode(1, 1, mav.MAV_CMD_NAV_RETURN_TO_LAUNCH, 0, 0, 0, 0, 0, 0, 0, 0),
                c.command_int_encode(1, 1, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, mav.MAV_CMD_DO_REPOSITION, 0, 0,
                                     -1, 1, 0, 0, -353632610, 1491652300, 10.0),
                c.command_long_encode(1, 1, mav.MAV_CMD_MISSION_START, 0, 0, 0, 0, 0, 0, 0, 0)):
        acks = [m for m in s.receive(wire(msg), v.time_s) if m.get_type() == "COMMAND_ACK"]
        assert len(acks) == 1 and acks[0].command == msg.command
        v.run_until(v.time_s + 0.5)
    assert v.home_ned is None and not v.armed
    assert s.counters["handler_errors"] == 0 and not v.internal_errors


def break_update(monkeypatch, *modes) -> None:
    """Give each of `modes` an update() with a bug in it."""
    def broken(self, ctx, sp, dt):
        raise ZeroDivisionError("a bug")
    for mode in modes:
        monkeypatch.setattr(mode, "update", broken)


@pytest.mark.internal_errors
def test_a_mode_that_raises_in_flight_is_an_internal_error_and_the_vehicle_lands(monkeypatch):
    v = hovering_vehicle(10.0)
    break_update(monkeypatch, Guided)
    v.run_until(v.time_s + 0.05)
    errors = v.internal_errors
    assert errors.bits == FLOW_OF_CONTROL and errors.count >= 1 and "ZeroDivisionError" in errors.last
    assert v.mode.number == ModeNumber.LAND
    said = [text for _, text in v.drain_events()]
    assert f"Internal Errors 0x{FLOW_OF_CONTROL:x}" in said  # ArduPilot's words when the mask changes
    assert fly_until(v, lambda x: not x.armed, 60.0), "landed and disarmed"
    # As ArduPilot: reported until reboot, and no arming with it
    assert v.prearm_failure().startswith("Internal errors 0x100000")
    assert v.set_mode(Guided.number) == Result.ACCEPTED
    assert v.arm() == Result.FAILED
    s = Session(v, new_codec(1))
    status = s.build(mav.MAVLINK_MSG_ID_SYS_STATUS)
    assert (status.errors_count1, status.errors_count2, status.errors_count4) == (0, 0x10, errors.count & 0xFFFF)
    assert s.build(mav.MAVLINK_MSG_ID_HEARTBEAT).system_status == mav.MAV_STATE_CRITICAL


@pytest.mark.internal_errors
def test_when_land_itself_raises_the_vehicle_comes_down_level(monkeypatch):
    v = hovering_vehicle(10.0)
    break_update(monkeypatch, Guided, Land)
    fly_until(v, lambda x: x.landed, 60.0)
    assert v.landed and v.mode.number == ModeNumber.LAND
    assert all(math.isfinite(x) for x in v.body)
    assert fly_until(v, lambda x: not x.armed, 30.0), "disarmed once down"


@pytest.mark.internal_errors
def test_a_command_whose_handler_raises_is_still_answered_once(monkeypatch):
    v = hovering_vehicle(10.0)
    s = Session(v, new_codec(1))

    def broken(session, c):
        raise KeyError("bug")
    monkeypatch.setitem(HANDLERS, mav.MAV_CMD_CONDITION_YAW, broken)
    msg = client_codec().command_long_encode(1, 1, mav.MAV_CMD_CONDITION_YAW, 0, 90, 10, 1, 0, 0, 0, 0)
    acks = [m for m in s.receive(wire(msg), v.time_s) if m.get_type() == "COMMAND_ACK"]
    assert [(a.command, a.result) for a in acks] == [(mav.MAV_CMD_CONDITION_YAW, Result.FAILED)]
    assert s.counters["handler_errors"] == 1 and v.internal_errors.count == 1
    assert v.mode.number == Guided.number  # a failed handler is reported, it changes no mode


class Counting:
    """A session stand-in for CommandService: counts how often the handler ran."""

    def __init__(self):
        self.codec = client_codec()
        self.runs = 0

    def handler_failed(self, where, exc):
        raise AssertionError(f"{where}: {exc}")


def _count_runs(session, c):
    session.runs += 1
    return Result.ACCEPTED


def _takeoff(p7: float) -> Command:
    return Command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, math.nan, 0, 0, p7, 0, False, 0, (255, 190))


def test_a_confirmed_retry_is_recognised_at_any_speedup_and_with_nan(monkeypatch):
    monkeypatch.setitem(HANDLERS, mav.MAV_CMD_NAV_TAKEOFF, _count_runs)
    service, session = CommandService(), Counting()
    service.handle(session, _takeoff(10.0), now_s=5.0, link_s=100.0)
    # MAVSDK's resend 0.5 s of wall time later at speedup 20 (10 s of flight), its confirmation
    # counted up and its NaN yaw included: answered, not run again
    ack = service.handle(session, _takeoff(10.0)._replace(confirmation=1), now_s=15.0, link_s=100.5)
    assert session.runs == 1 and ack.result == Result.ACCEPTED
    service.handle(session, _takeoff(12.0)._replace(confirmation=1), now_s=15.1, link_s=100.6)  # another
    assert session.runs == 2


def test_an_unconfirmed_repeat_is_a_retry_only_when_close_in_wall_and_sim_time(monkeypatch):
    monkeypatch.setitem(HANDLERS, mav.MAV_CMD_NAV_TAKEOFF, _count_runs)
    service, session = CommandService(), Counting()
    service.handle(session, _takeoff(10.0), now_s=5.0, link_s=100.0)
    service.handle(session, _takeoff(10.0), now_s=5.5, link_s=100.5)  # a retry at speedup 1
    assert session.runs == 1
    service.handle(session, _takeoff(10.0), now_s=8.0, link_s=100.6)  # 2.5 s of flight later: again
    assert session.runs == 2
    service.handle(session, _takeoff(10.0), now_s=8.1, link_s=103.0)  # 2.4 s of wall time later: again
    assert session.runs == 3


@pytest.mark.parametrize("alt_m", [3_000_000.0, 1e30, math.inf, math.nan, -90_000.0])
def test_set_home_altitude_outside_what_a_location_holds_is_denied(alt_m):
    v = hovering_vehicle(5.0)
    s = Session(v, new_codec(1))
    home = v.home
    msg = client_codec().command_long_encode(1, 1, mav.MAV_CMD_DO_SET_HOME, 0, 0, 0, 0, 0,
                                             home.lat_deg, home.lon_deg, alt_m)
    acks = [m for m in s.receive(wire(msg), v.time_s) if m.get_type() == "COMMAND_ACK"]
    assert acks[0].result == Result.DENIED and v.home == home
    assert s.build(mav.MAVLINK_MSG_ID_HOME_POSITION) is not None


def test_a_message_that_cannot_pack_is_reported_and_the_rest_of_the_batch_goes():
    from firefly.autopilot.mavlink.link import Link
    from firefly.autopilot.mavlink.signing import LinkSigning
    codec = new_codec(1)
    link = Link(codec, LinkSigning(codec))
    seen = []
    link.on_unpackable = lambda exc, what: seen.append(what)
    bad = codec.message_interval_encode(70_000, 1000)  # message_id is 16 bits
    ack = codec.command_ack_encode(mav.MAV_CMD_GET_MESSAGE_INTERVAL, 0, 0, 0, 255, 190)
    frames = link.pack([bad, ack])
    assert len(frames) == 1 and seen == ["MESSAGE_INTERVAL"] and link.counters["unpackable"] == 1


@pytest.mark.parametrize("msg_id", [3e6, 65536, -1, math.nan])
def test_get_message_interval_of_an_id_that_message_cannot_hold_is_denied(msg_id):
    v = hovering_vehicle(5.0)
    s = Session(v, new_codec(1))
    msg = client_codec().command_long_encode(1, 1, mav.MAV_CMD_GET_MESSAGE_INTERVAL, 0, msg_id, 0, 0, 0, 0, 0, 0)
    out = s.receive(wire(msg), v.time_s)
    assert [(m.get_type(), m.result) for m in out] == [("COMMAND_ACK", Result.DENIED)]


def test_a_heading_of_any_size_is_wrapped_before_it_is_flown_or_reported():
    v = hovering_vehicle(5.0)
    assert v.guided_goto(v.body.n_m, v.body.e_m, v.body.d_m, yaw=1000.0) == Result.ACCEPTED
    v.run_until(v.time_s + 0.5)
    s = Session(v, new_codec(1))
    nav = s.build(mav.MAVLINK_MSG_ID_NAV_CONTROLLER_OUTPUT)
    assert -180 <= nav.nav_bearing <= 180
    assert nav.pack(new_codec(1))


def test_home_found_in_flight_takes_the_boot_grounds_height():
    v = Vehicle(VehicleConfig(faults={"SIM_GPS_DISABLE": 1}))
    v.run_until(1.0)
    v.set_mode(ModeNumber.ALT_HOLD)
    assert v.arm() == Result.ACCEPTED
    end = v.time_s + 7.0  # past the arming delay and the pilot takeoff's spool-up and throttle slew
    while v.time_s < end:
        v.rc.hold_sticks(0.0, 0.0, 0.0, 0.9, v.time_s)
        v.run_until(v.time_s + 0.1)
    assert v.home_ned is None and v.boot_ground_d - v.body.d_m > 2.0
    v.params.set("SIM_GPS_DISABLE", 0)
    assert fly_until(v, lambda x: x.home_ned is not None, 10.0)
    assert v.home_ned[2] == v.boot_ground_d  # not the height it was flying at


def test_mission_start_while_auto_waits_for_home_runs_nothing_until_then():
    from firefly.autopilot.mission import MissionItem
    v = booting_vehicle()
    v.mission.replace(0, [MissionItem(22, 3, z=10.0), MissionItem(16, 3, x=-353632610, y=1491652300, z=10.0)])
    v.drain_events()
    assert v.mission_start() == Result.ACCEPTED and not v.mode_flying
    v.run_until(3.0)
    assert not [t for _, t in v.drain_events() if t.startswith("Mission")]
    assert not v.mission_progress.running

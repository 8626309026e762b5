"""The MAVLink session, sans-IO: commands, addressing, parameters and FTP, in sim time."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.modes import Brake, Guided, Land, Loiter
from firefly.autopilot.mavlink.params_service import LIST_BURST, LIST_RATE_PER_S
from firefly.autopilot.params import SERVED
from firefly.autopilot.safety.arming import FORCE_DISARM_MAGIC

from ._session_link import SYSTEM_ID, Link, gcs, link  # noqa: F401 - link is a fixture
from ._util import GCS_COMPONENT, GCS_SYSTEM, command_long, mav, of_type, statustexts, wire


# ----- commands ----------------------------------------------------------------------------------
def test_command_long_gets_exactly_one_ack_addressed_to_the_sender(link):
    out = link.send(command_long(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1))
    assert [m.get_type() for m in out] == ["COMMAND_ACK"]
    ack = out[0]
    assert ack.command == mav.MAV_CMD_COMPONENT_ARM_DISARM
    assert (ack.target_system, ack.target_component) == (GCS_SYSTEM, GCS_COMPONENT)
    assert ack.result == mav.MAV_RESULT_ACCEPTED
    assert link.vehicle.armed


def test_unknown_command_is_unsupported(link):
    ack, _ = link.command(mav.MAV_CMD_USER_1)
    assert ack.result == mav.MAV_RESULT_UNSUPPORTED == 3
    assert link.session.counters["refused"] == 1


def test_commands_answered_as_arducopter_sitl_answers_them(link):
    """Measured on ArduCopter SITL (tests/parity/probes/surface_commands.py)."""
    ack, replies = link.command(mav.MAV_CMD_GET_HOME_POSITION)
    assert ack.result == mav.MAV_RESULT_ACCEPTED
    assert {"HOME_POSITION", "GPS_GLOBAL_ORIGIN"} <= {m.get_type() for m in replies}
    ack, _ = link.command(mav.MAV_CMD_DO_MOUNT_CONTROL, 10, 0, 0)  # no mount: FAILED, not UNSUPPORTED
    assert ack.result == mav.MAV_RESULT_FAILED
    ack, _ = link.command(mav.MAV_CMD_NAV_LOITER_UNLIM)  # LOITER, even disarmed
    assert ack.result == mav.MAV_RESULT_ACCEPTED and link.vehicle.mode_number == Loiter.number
    link.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, Guided.number)
    link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    ack, _ = link.command(mav.MAV_CMD_NAV_VTOL_TAKEOFF, 0, 0, 0, 0, 0, 0, 10)  # a plain takeoff on a copter
    assert ack.result == mav.MAV_RESULT_ACCEPTED


def test_prearm_checks_run_on_request_and_termination_stops_the_motors_in_flight():
    """Measured on ArduCopter SITL (tests/parity/probes/surface_commands.py)."""
    from ._util import hovering_vehicle

    link = Link(hovering_vehicle(10.0))
    ack, _ = link.command(mav.MAV_CMD_RUN_PREARM_CHECKS)
    assert ack.result == mav.MAV_RESULT_TEMPORARILY_REJECTED  # armed
    ack, _ = link.command(mav.MAV_CMD_DO_FLIGHTTERMINATION, 0)
    assert ack.result == mav.MAV_RESULT_FAILED and link.vehicle.armed
    ack, out = link.command(mav.MAV_CMD_DO_FLIGHTTERMINATION, 1)
    assert ack.result == mav.MAV_RESULT_ACCEPTED and not link.vehicle.armed
    assert "Disarming motors" in statustexts(out + link.poll())
    ack, _ = link.command(mav.MAV_CMD_RUN_PREARM_CHECKS)
    assert ack.result == mav.MAV_RESULT_ACCEPTED


def test_takeoff_while_disarmed_fails(link):
    link.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, Guided.number)
    ack, _ = link.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 10)
    assert ack.result == mav.MAV_RESULT_FAILED == 4
    assert not link.vehicle.armed


def test_arm_with_nan_param_is_denied(link):
    ack, _ = link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, math.nan)
    assert ack.result == mav.MAV_RESULT_DENIED
    assert not link.vehicle.armed
    ack, _ = link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1, math.inf)
    assert ack.result == mav.MAV_RESULT_DENIED
    assert not link.vehicle.armed


def test_do_set_mode_changes_the_mode(link):
    ack, _ = link.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, Loiter.number)
    assert ack.result == mav.MAV_RESULT_ACCEPTED
    assert link.vehicle.mode.number == Loiter.number
    ack, _ = link.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, 99)
    assert ack.result == mav.MAV_RESULT_FAILED
    assert link.vehicle.mode.number == Loiter.number
    ack, _ = link.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, 4.5)
    assert ack.result == mav.MAV_RESULT_DENIED
    assert link.vehicle.mode.number == Loiter.number


def test_set_mode_message_changes_the_mode_unanswered_as_arducopter_4_7(link):
    msg = wire(gcs().set_mode_encode(SYSTEM_ID, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, Guided.number))
    out = link.send(msg)
    assert [m.get_type() for m in out if m.get_type() == "COMMAND_ACK"] == []
    assert link.vehicle.mode.number == Guided.number


def test_set_mode_without_custom_mode_flag_changes_nothing(link):
    before = link.vehicle.mode
    out = link.send(wire(gcs().set_mode_encode(SYSTEM_ID, 0, Guided.number)))
    assert [m.get_type() for m in out if m.get_type() == "COMMAND_ACK"] == []
    assert link.vehicle.mode is before


def test_exact_retry_of_a_refused_arm_replays_the_result_without_acting_again(link):
    link.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, Land.number)
    link.vehicle.events.clear()
    t = link.vehicle.time_s
    ack1, _ = link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1, now=t)
    ack2, _ = link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1, now=t + 0.5, confirmation=1)
    assert ack1.result == ack2.result == mav.MAV_RESULT_FAILED
    assert [text for _, text in link.vehicle.events].count("Arm: LAND mode not armable") == 1


def test_exact_retry_of_an_accepted_arm_does_not_arm_again(link):
    t = link.vehicle.time_s
    ack1, _ = link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1, now=t)
    assert ack1.result == mav.MAV_RESULT_ACCEPTED and link.vehicle.armed
    link.vehicle.disarm("test")  # something else disarms it before the client's retry arrives
    ack2, _ = link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1, now=t + 0.5, confirmation=1)
    assert ack2.result == mav.MAV_RESULT_ACCEPTED
    assert not link.vehicle.armed  # replayed, not acted on
    # The same command long after the retry window (and without confirmation) is a new command.
    ack3, _ = link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1, now=t + 5.0)
    assert ack3.result == mav.MAV_RESULT_ACCEPTED
    assert link.vehicle.armed


def test_force_disarm_in_flight_needs_the_magic_number():
    from ._util import hovering_vehicle
    link = Link(hovering_vehicle(5.0))
    ack, _ = link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0)
    assert ack.result == mav.MAV_RESULT_FAILED and link.vehicle.armed
    ack, _ = link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0, FORCE_DISARM_MAGIC)
    assert ack.result == mav.MAV_RESULT_ACCEPTED and not link.vehicle.armed


def test_command_int_takeoff_path_matches_command_long(link):
    link.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, Guided.number)
    link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    msg = wire(gcs().command_int_encode(SYSTEM_ID, 1, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT,
                                        mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 0, 0, 8.0))
    out = link.send(msg)
    acks = of_type(out, "COMMAND_ACK")
    assert len(acks) == 1 and acks[0].result == mav.MAV_RESULT_ACCEPTED
    assert (acks[0].target_system, acks[0].target_component) == (GCS_SYSTEM, GCS_COMPONENT)
    link.vehicle.run_until(link.vehicle.time_s + 10.0)
    assert -link.vehicle.body.d_m == pytest.approx(8.0, abs=0.3)


# ----- addressing ---------------------------------------------------------------------------------
def test_messages_for_another_system_are_ignored(link):
    out = link.send(command_long(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1, target_system=2))
    assert out == []
    assert not link.vehicle.armed
    assert link.session.counters["ignored_other_system"] == 1
    out = link.send(wire(gcs().param_set_encode(2, 1, b"DISARM_DELAY", 3.0, mav.MAV_PARAM_TYPE_REAL32)))
    assert out == []
    assert link.vehicle.params["DISARM_DELAY"] == 10.0
    out = link.send(wire(gcs().set_mode_encode(2, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, Brake.number)))
    assert out == [] and link.vehicle.mode.number != Brake.number


def test_broadcast_target_zero_is_accepted(link):
    out = link.send(command_long(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1, target_system=0))
    assert out[0].result == mav.MAV_RESULT_ACCEPTED


def test_manual_control_for_another_system_is_ignored(link):
    before = list(link.vehicle.rc.overrides.values)
    link.send(wire(gcs().manual_control_encode(2, 1000, 500, 900, 0, 0)))
    assert link.vehicle.rc.overrides.values == before


def test_manual_control_for_this_system_sets_the_sticks(link):
    v = link.vehicle
    link.send(wire(gcs().manual_control_encode(SYSTEM_ID, 1000, -500, 750, 0, 0)))
    # As GCS_MAVLINK::manual_override: spread over RCn_MIN..MAX, x (forward) reversed onto channel 2
    assert v.rc.overrides.values[:4] == [1250, 1000, 1750, 1500]
    v.rc.read(v.time_s)
    p = v.pilot
    assert (p.pitch, p.roll, p.throttle) == pytest.approx((1.0, -230 / 480, 720 / 970))


def test_bad_data_is_counted_and_answered_with_nothing(link):
    bad = mav.MAVLink_bad_data(b"\xfd\x00\x00", "bad")
    assert link.session.receive(bad, 0.0) == []
    assert link.session.counters["bad_data"] == 1


# ----- parameters ---------------------------------------------------------------------------------
def _name(msg) -> str:
    pid = msg.param_id
    return (pid.decode() if isinstance(pid, bytes) else pid).rstrip("\0")


def _list_over_time(link, start: float, step: float = 0.01, limit: float = 10.0) -> tuple[list, list]:
    """(first answer, everything) of a PARAM_REQUEST_LIST at `start`, polled every `step` s."""
    first = of_type(link.send(wire(gcs().param_request_list_encode(SYSTEM_ID, 1)), start), "PARAM_VALUE")
    values, now = list(first), start
    while link.session.params.streaming and now < start + limit:
        now += step
        values.extend(of_type(link.poll(now), "PARAM_VALUE"))
    return first, values


def test_param_request_list_yields_every_parameter_once_with_consistent_indices(link):
    first, values = _list_over_time(link, link.vehicle.time_s)
    served = {spec.name: spec for spec in SERVED}
    assert len(values) == len(SERVED) >= 1300
    assert {m.param_count for m in values} == {len(SERVED)}
    assert [m.param_index for m in values] == list(range(len(SERVED)))
    assert [_name(m) for m in values] == [spec.name for spec in SERVED]
    for m in values:
        spec = served[_name(m)]
        # MIS_TOTAL is counted, not a default: the mission's length with home, 1 for no mission
        expected = 1.0 if spec.name == "MIS_TOTAL" else spec.default
        assert m.param_value == pytest.approx(expected, rel=1e-6)
        assert m.param_type == spec.mav_type == link.vehicle.params.mav_type(spec.name)
    fs_thr = next(m for m in values if _name(m) == "FS_THR_ENABLE")
    assert fs_thr.param_type == mav.MAV_PARAM_TYPE_INT8  # the reference's type, not a generic INT32


def test_param_list_is_paced_over_link_time_not_sent_in_one_burst(link):
    first, values = _list_over_time(link, 100.0, step=0.1)
    assert 0 < len(first) <= LIST_BURST
    assert len(values) == len(SERVED)
    polls_needed = (len(SERVED) - LIST_BURST) / (LIST_RATE_PER_S * 0.1)
    assert link.session.params.poll(1000.0) == []  # done: nothing more to send
    assert polls_needed > 1  # the list does take several polls at this rate


def test_a_new_param_request_list_restarts_the_stream(link):
    link.send(wire(gcs().param_request_list_encode(SYSTEM_ID, 1)), 5.0)
    link.poll(5.1)
    again = of_type(link.send(wire(gcs().param_request_list_encode(SYSTEM_ID, 1)), 5.2), "PARAM_VALUE")
    assert again[0].param_index == 0


def test_a_parameter_firefly_does_not_model_is_set_and_echoed_never_unknown(link):
    for name, value in (("ARMING_CHECK", 0), ("FS_THR_ENABLE", 0), ("FLTMODE1", 4), ("BATT_MONITOR", 3),
                        ("SERIAL1_PROTOCOL", 1)):
        out = link.send(wire(gcs().param_set_encode(SYSTEM_ID, 1, name.encode(), value,
                                                    link.vehicle.params.mav_type(name))))
        assert [(_name(m), m.param_value) for m in out] == [(name, value)]
        assert out[0].param_index == link.vehicle.params.index_of(name)
    assert link.session.params.refused == 0


def test_an_out_of_range_value_of_a_stored_parameter_is_refused_with_a_reason(link):
    link.poll()
    out = link.send(wire(gcs().param_set_encode(SYSTEM_ID, 1, b"PILOT_THR_FILT", 11.0,
                                                mav.MAV_PARAM_TYPE_REAL32)))
    assert out[0].param_value == 0.0
    texts = statustexts(link.poll())
    # the same words as a modelled parameter's refusal, cut to STATUSTEXT's 50 characters
    assert any(t.startswith("Param set failed: PILOT_THR_FILT: 11 out of range") for t in texts), texts


def test_param_set_echoes_the_new_value(link):
    out = link.send(wire(gcs().param_set_encode(SYSTEM_ID, 1, b"WPNAV_SPEED", 750.0,
                                                mav.MAV_PARAM_TYPE_REAL32)))
    assert len(out) == 1 and out[0].get_type() == "PARAM_VALUE"
    assert _name(out[0]) == "WPNAV_SPEED" and out[0].param_value == 750.0
    assert out[0].param_index == link.vehicle.params.index_of("WPNAV_SPEED")
    assert link.vehicle.params["WPNAV_SPEED"] == 750.0
    assert link.vehicle.nav_speed_m_s == pytest.approx(7.5)  # and the vehicle uses it


def test_param_set_of_an_integer_rounds(link):
    out = link.send(wire(gcs().param_set_encode(SYSTEM_ID, 1, b"MAV1_POSITION", 6.6,
                                                mav.MAV_PARAM_TYPE_INT32)))
    assert out[0].param_value == 7.0
    assert link.vehicle.params["MAV1_POSITION"] == 7.0


@pytest.mark.parametrize("value", [5000.0, -1.0, math.nan, math.inf])
def test_param_set_refused_keeps_value_echoes_old_and_says_why(link, value):
    before = link.vehicle.params["WPNAV_SPEED"]
    link.poll()  # drain the boot messages
    out = link.send(wire(gcs().param_set_encode(SYSTEM_ID, 1, b"WPNAV_SPEED", value,
                                                mav.MAV_PARAM_TYPE_REAL32)))
    assert len(out) == 1 and out[0].get_type() == "PARAM_VALUE"
    assert out[0].param_value == before
    assert link.vehicle.params["WPNAV_SPEED"] == before
    texts = statustexts(link.poll())
    assert any(t.startswith("Param set failed") and "WPNAV_SPEED" in t for t in texts), texts


def test_param_set_of_unknown_name_changes_nothing_and_says_why(link):
    link.poll()
    out = link.send(wire(gcs().param_set_encode(SYSTEM_ID, 1, b"NO_SUCH_PARAM", 1.0,
                                                mav.MAV_PARAM_TYPE_REAL32)))
    assert out == []
    assert any("NO_SUCH_PARAM" in t for t in statustexts(link.poll()))


def test_param_request_read_by_name_and_by_index(link):
    out = link.send(wire(gcs().param_request_read_encode(SYSTEM_ID, 1, b"RTL_ALT", -1)))
    assert len(out) == 1
    assert _name(out[0]) == "RTL_ALT" and out[0].param_value == link.vehicle.params["RTL_ALT"]
    index = out[0].param_index
    assert index == link.vehicle.params.index_of("RTL_ALT")
    out = link.send(wire(gcs().param_request_read_encode(SYSTEM_ID, 1, b"", index)))
    assert len(out) == 1 and _name(out[0]) == "RTL_ALT"
    assert out[0].param_count == len(SERVED)
    # Out-of-range index and unknown name: nothing to answer.
    assert link.send(wire(gcs().param_request_read_encode(SYSTEM_ID, 1, b"", len(SERVED)))) == []
    assert link.send(wire(gcs().param_request_read_encode(SYSTEM_ID, 1, b"NOPE", -1))) == []


def test_param_name_of_full_16_characters(link):
    name = "PSC_VELXY_IMAX"  # 14 chars; the longest names still round-trip through char[16]
    out = link.send(wire(gcs().param_request_read_encode(SYSTEM_ID, 1, name.encode(), -1)))
    assert _name(out[0]) == name

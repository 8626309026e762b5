"""Property tests: any sequence of well-formed but hostile MAVLink messages (NaN, +-inf, absurd
values, wrong states, unknown ids and names, other systems) leaves the vehicle valid.

Valid means: no exception reaches the loop, the state stays finite and above ground, every
parameter stays inside its table range, the mode is one of the table's, every command addressed to
us gets exactly one COMMAND_ACK for its own id, messages for other systems change nothing, and the
vehicle is never armed unless an ARM command was answered ACCEPTED.
"""
from __future__ import annotations

import math

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from firefly.autopilot.mavlink.commands import HANDLERS
from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.mavlink.session import Session
from firefly.autopilot.modes import MODE_BY_NUMBER, Guided
from firefly.autopilot.params import PARAM_TABLE, SERVED_BY_NAME, SPEC_BY_NAME

from ..fuzz.checks import vehicle_problems
from ._util import GCS_COMPONENT, GCS_SYSTEM, client_codec, mav, ready_vehicle, wire

SYSTEM_ID = 1
ARM = mav.MAV_CMD_COMPONENT_ARM_DISARM

# ----- values a fuzzer or a half-written ground station sends ----------------------------------
SPECIAL = [0.0, -0.0, 1.0, -1.0, 2989.0, 21196.0, 4.0, 9.0, 1e30, -1e30, 3.4e38, -3.4e38, 1e-30,
           math.nan, math.inf, -math.inf]
f32 = st.one_of(st.sampled_from(SPECIAL), st.floats(width=32), st.integers(-1000, 1000).map(float))
i32 = st.one_of(st.sampled_from([0, 1, -1, 2**31 - 1, -2**31, -353632610, 1491652300]),
                st.integers(-2**31, 2**31 - 1))
u8, u16 = st.integers(0, 255), st.integers(0, 65535)
i16 = st.integers(-32768, 32767)
target = st.sampled_from([0, SYSTEM_ID, SYSTEM_ID, SYSTEM_ID, 2, 255])
command_id = st.one_of(st.sampled_from(sorted(HANDLERS)), st.sampled_from([ARM, ARM, 176, 22, 21, 20]), u16)
frame = st.one_of(st.sampled_from([0, 1, 3, 5, 6, 7, 8, 9, 10, 11, 12]), u8)
mission_type = st.sampled_from([0, 1, 2, 3, 255])
param_name = st.one_of(st.sampled_from([s.name for s in PARAM_TABLE]),
                       st.text(st.characters(min_codepoint=1, max_codepoint=127), max_size=16))
mode_number = st.one_of(st.sampled_from(sorted(MODE_BY_NUMBER)), st.integers(0, 2**32 - 1))


def _cmd_long(c):
    return st.builds(lambda t, cmd, conf, p: c.command_long_encode(t, 1, cmd, conf, *p),
                     target, command_id, u8, st.lists(f32, min_size=7, max_size=7))


def _cmd_int(c):
    return st.builds(lambda t, fr, cmd, p, x, y, z: c.command_int_encode(t, 1, fr, cmd, 0, 0, *p, x, y, z),
                     target, frame, command_id, st.lists(f32, min_size=4, max_size=4), i32, i32, f32)


def _messages(c):
    """Strategies for every message type the session handles, plus a few it does not."""
    return st.one_of(
        _cmd_long(c), _cmd_long(c), _cmd_int(c),
        st.builds(lambda t, b, m: c.set_mode_encode(t, b, m), target, u8, mode_number),
        st.builds(lambda t, fr, mask, v: c.set_position_target_local_ned_encode(0, t, 1, fr, mask, *v),
                  target, frame, u16, st.lists(f32, min_size=11, max_size=11)),
        st.builds(lambda t, fr, mask, la, lo, v: c.set_position_target_global_int_encode(0, t, 1, fr, mask, la, lo, *v),
                  target, frame, u16, i32, i32, st.lists(f32, min_size=9, max_size=9)),
        st.builds(lambda t, n, v, ty: c.param_set_encode(t, 1, n.encode(), v, ty), target, param_name, f32,
                  st.integers(0, 10)),
        st.builds(lambda t, n, i: c.param_request_read_encode(t, 1, n.encode(), i), target, param_name,
                  st.integers(-32768, 32767)),
        st.builds(lambda t: c.param_request_list_encode(t, 1), target),
        st.builds(lambda t, n, k: c.mission_count_encode(t, 1, n, k), target, st.integers(0, 12) | u16,
                  mission_type),
        st.builds(lambda t, s, fr, cmd, cur, ac, p, x, y, z, k: c.mission_item_int_encode(
            t, 1, s, fr, cmd, cur, ac, *p, x, y, z, k),
            target, st.integers(0, 12) | u16, frame, command_id, u8, u8, st.lists(f32, min_size=4, max_size=4),
            i32, i32, f32, mission_type),
        st.builds(lambda t, s, fr, cmd, p, z, k: c.mission_item_encode(t, 1, s, fr, cmd, 0, 1, *p, z, k),
                  target, st.integers(0, 12), frame, command_id, st.lists(f32, min_size=6, max_size=6), f32,
                  mission_type),
        st.builds(lambda t, s, k: c.mission_request_int_encode(t, 1, s, k), target, u16, mission_type),
        st.builds(lambda t, s, k: c.mission_request_encode(t, 1, s, k), target, u16, mission_type),
        st.builds(lambda t, k: c.mission_request_list_encode(t, 1, k), target, mission_type),
        st.builds(lambda t, k: c.mission_clear_all_encode(t, 1, k), target, mission_type),
        st.builds(lambda t, s: c.mission_set_current_encode(t, 1, s), target, u16),
        st.builds(lambda t, x, y, z, r, b: c.manual_control_encode(t, x, y, z, r, b), target, i16, i16, i16, i16, u16),
        st.builds(lambda t, ch: c.rc_channels_override_encode(t, 1, *ch), target,
                  st.lists(st.sampled_from([0, 65535, 1000, 1500, 2000, 799, 2201]) | u16, min_size=8, max_size=8)),
        st.builds(lambda t, s, r, on: c.request_data_stream_encode(t, 1, s, r, on), target, u8, u16, u8),
        st.builds(lambda ty, b, cm: c.heartbeat_encode(ty, 8, b, cm, 4), st.integers(0, 40), u8, mode_number),
        st.builds(lambda a, b: c.timesync_encode(a, b), st.integers(-2**63, 2**63 - 1), st.integers(-2**63, 2**63 - 1)),
        st.builds(lambda t, p: c.file_transfer_protocol_encode(0, t, 1, p), target,
                  st.lists(u8, min_size=251, max_size=251)),
        st.builds(lambda v: c.named_value_float_encode(0, b"GND_TEMP", v), f32),  # not for the vehicle
        st.builds(lambda t: c.system_time_encode(t, 0), st.integers(0, 2**64 - 1)),  # not handled
        # a companion's navigation (external_nav_messages.py): dropped unless the vehicle is set up for it
        st.builds(lambda u, x, y, z, r: c.vision_position_estimate_encode(u, x, y, z, 0.0, 0.0, 0.0, [0.0] * 21, r),
                  st.integers(0, 2**64 - 1), f32, f32, f32, u8),
        st.builds(lambda x, y, z, fr, ch, q: c.odometry_encode(0, fr, ch, x, y, z, [1.0, 0.0, 0.0, 0.0], 0.0, 0.0, 0.0,
                                                              0.0, 0.0, 0.0, [math.nan] * 21, [math.nan] * 21, 0, 0, q),
                  f32, f32, f32, u8, u8, st.integers(-128, 127)),
        st.builds(lambda t, la, lo, al: c.set_gps_global_origin_encode(t, la, lo, al), target, i32, i32, i32),
        st.builds(lambda fix, la, lo, al, v, sats: c.gps_input_encode(0, 0, 0, 0, 0, fix, la, lo, al, 0.8, 1.0, v, v, v,
                                                                      0.2, 0.3, 0.5, sats),
                  u8, i32, i32, f32, f32, u8),
        # a companion's obstacles (proximity.py): dropped unless PRX1_TYPE is 2
        st.builds(lambda ts, fr, x, y, z, lo, hi: c.obstacle_distance_3d_encode(ts, 0, fr, 0, x, y, z, lo, hi),
                  st.integers(0, 2**32 - 1), frame, f32, f32, f32, f32, f32),
        st.builds(lambda t, key, ts: c.setup_signing_encode(t, 1, key, ts), target,
                  st.sampled_from([bytes(32), b"\x01" * 32]) | st.binary(min_size=32, max_size=32),
                  st.integers(0, 2**64 - 1)),
    )


CLIENT = client_codec()
MESSAGES = _messages(CLIENT)
STEPS = st.sampled_from([0, 1, 4, 40, 200])  # physics steps after each message (400 Hz)


def _link(flying: bool):
    v = ready_vehicle()
    if flying:
        assert v.set_mode(Guided.number) == 0 and v.arm() == 0 and v.takeoff(8.0) == 0
        v.run_until(v.time_s + 3.0)
    return v, Session(v, new_codec(SYSTEM_ID))


def _snapshot(v):
    return (v.armed, v.mode.number, dict((s.name, v.params[s.name]) for s in PARAM_TABLE),
            v.mission.version, v.home_ned)


def _assert_valid(v, session):
    problems = vehicle_problems(v, session)
    assert not problems, problems


def _decode(session, out) -> list:
    decoder = new_codec(GCS_SYSTEM, GCS_COMPONENT)
    decoded = []
    for m in out:
        got = decoder.parse_buffer(m.pack(session.codec))
        assert got and len(got) == 1  # everything the vehicle says is a well-formed frame
        decoded.extend(got)
    return decoded


def _addressed_to_us(msg) -> bool:
    return getattr(msg, "target_system", getattr(msg, "target", 0)) in (0, SYSTEM_ID)


def _check_one(v, session, msg, steps):
    before = _snapshot(v)
    out = _decode(session, session.receive(msg, v.time_s))
    acks = [m for m in out if m.get_type() == "COMMAND_ACK"]
    kind = msg.get_type()
    if not _addressed_to_us(msg):
        assert out == [] and _snapshot(v) == before, "a message for another system changed something"
    elif kind in ("COMMAND_LONG", "COMMAND_INT"):
        assert len(acks) == 1 and acks[0].command == msg.command, (msg, acks)
        assert acks[0].result in (0, 1, 2, 3, 4, 5)
    if v.armed and not before[0]:
        assert kind in ("COMMAND_LONG", "COMMAND_INT") and msg.command == ARM and msg.param1 == 1 and \
            acks and acks[0].result == 0, f"armed by {msg}"
    _assert_valid(v, session)
    armed = v.armed
    for _ in range(steps):
        v.step()
    assert v.armed <= armed, "the vehicle armed itself"
    _decode(session, session.poll(v.time_s))  # telemetry after hostile input must still encode
    _assert_valid(v, session)


SETTINGS = settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@pytest.mark.parametrize("flying", [False, True], ids=["on_the_ground", "in_flight"])
@SETTINGS
@given(st.lists(st.tuples(MESSAGES, STEPS), min_size=1, max_size=25))
def test_hostile_sequences_leave_the_vehicle_valid(flying, sequence):
    v, session = _link(flying=flying)
    for built, steps in sequence:
        _check_one(v, session, wire(built, CLIENT), steps)


@settings(max_examples=300, deadline=None)
@given(st.sampled_from(["ground", "ground-guided", "flying"]), st.sampled_from(sorted(HANDLERS)),
       st.lists(f32, min_size=7, max_size=7), st.booleans(), frame)
def test_every_known_command_with_any_params_is_acked_once_and_arms_only_when_asked(start, command, p, as_int, fr):
    v, session = _link(flying=start == "flying")
    if start == "ground-guided":
        assert v.set_mode(Guided.number) == 0
    if as_int:
        x, y = (int(max(-2**31, min(2**31 - 1, q * 1e7))) if math.isfinite(q) else 0 for q in p[4:6])
        built = CLIENT.command_int_encode(SYSTEM_ID, 1, fr, command, 0, 0, *p[:4], x, y, p[6])
    else:
        built = CLIENT.command_long_encode(SYSTEM_ID, 1, command, 0, *p)
    _check_one(v, session, wire(built, CLIENT), 40)


@SETTINGS
@given(st.lists(st.tuples(st.sampled_from(sorted(n for n in SPEC_BY_NAME if n in SERVED_BY_NAME)), f32),
                min_size=1, max_size=30))
def test_param_set_never_leaves_the_table_range(changes):
    v, session = _link(flying=False)
    for name, value in changes:
        before, refused = v.params[name], session.params.refused
        out = _decode(session, session.receive(wire(CLIENT.param_set_encode(SYSTEM_ID, 1, name.encode(), value, 9),
                                                    CLIENT), v.time_s))
        echoed = [m for m in out if m.get_type() == "PARAM_VALUE"]
        assert len(echoed) == 1  # the value now in force, accepted or not
        spec = SPEC_BY_NAME[name]
        in_range = math.isfinite(value) and spec.low <= value <= spec.high
        assert (v.params[name] != before) <= in_range
        assert session.params.refused == refused + (not in_range)  # every refusal counted
        assert echoed[0].param_value == v.params[name] or math.isclose(echoed[0].param_value, v.params[name],
                                                                         rel_tol=1e-6)
    _assert_valid(v, session)

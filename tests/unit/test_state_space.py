"""The state-space attack: hostile messages in every state a user can put the vehicle in.

The hostile-message tests (test_hostile_messages.py) attack a vehicle on the ground and in flight.
Here a stateful walk (tests/fuzz/state_machine.py) drives the sans-IO vehicle and session through
the realistic start-up (booting, before the GPS fix, before home, before the position estimate,
ready), every flight mode disarmed, armed on the ground, flying and landing, every failsafe
(battery, ground-station loss, fence, EKF), the GPS lost and back, and transfers left half done
(mission, fence and rally uploads, the parameter list, an FTP session), and sends hostile messages
in each. After every message and every 10 ms tick: nothing raised, no handler or internal error,
one COMMAND_ACK per command, a refused command changed nothing, the vehicle is valid, everything it
sends packs, and HEARTBEAT keeps its rate (the invariants are listed in state_machine.py).

Two walks: hypothesis rules (shrinkable, derandomized so CI is repeatable) and the seeded random
walk of `make fuzz` (tests/fuzz/state_walk.py), shorter; the second also checks that the walk
reaches every state it is meant to. A failure says the state, the message, what broke with its
traceback, and Python that reproduces it (shrunk).
"""
from __future__ import annotations

import pytest
from hypothesis import HealthCheck, Phase, event, settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, initialize, rule

from ..fuzz import hostile
from ..fuzz.state_machine import (ACTIONS, START_AT_S, Walk, WalkFailure, act_camera_lens, act_gps_jam, act_payload,
                                  act_terrain, render, shrink)
from ..fuzz.state_walk import run
from .test_hostile_messages import MESSAGES

SHRINK_S = 8.0  # wall seconds to shrink a failure's reproduction
RANDOM = st.randoms(use_true_random=False)
STARTS = [("instant", 0.0), ("camera", 0.0), ("payload", 0.0)] + [("realistic", t) for t in START_AT_S]


def _action(name: str):
    def step(self, rng):
        self.act(ACTIONS[name][1], rng)
    step.__name__ = name
    return rule(rng=RANDOM)(step)


class StateSpace(RuleBasedStateMachine):
    """One vehicle from one start; each rule one action of the walk (state_machine.ACTIONS)."""

    @initialize(start=st.sampled_from(STARTS))
    def start(self, start):
        kind, at_s = start
        self.walk = Walk(kind)
        if at_s:
            self.act(lambda w, _: w.advance_to(at_s), None)

    def act(self, action, rng) -> None:
        try:
            action(self.walk, rng)
        except WalkFailure as exc:
            raise WalkFailure(exc.failure, render(shrink(exc.failure, SHRINK_S))) from None

    hostile = _action("hostile")
    advance = _action("advance")
    set_mode = _action("set_mode")
    arm = _action("arm")
    arm_in_mode = _action("arm_in_mode")
    settle = _action("settle")
    disarm = _action("disarm")
    takeoff = _action("takeoff")
    fly = _action("fly")
    land = _action("land")
    goto = _action("goto")
    pilot = _action("pilot")
    mission = _action("mission")
    fence = _action("fence")
    rally = _action("rally")
    mission_start = _action("mission_start")
    battery = _action("battery")
    gcs = _action("gcs")
    gps = _action("gps")
    fence_params = _action("fence_params")
    param_list = _action("param_list")
    ftp = _action("ftp")
    known = _action("known")
    camera = _action("camera")

    @rule(rng=RANDOM)
    def payload(self, rng):
        """The winch, the flow sensor and the thermal camera's component (act_payload): not among the
        seeded walk's ACTIONS, whose draws (and the states seed WALK_SEED reaches) stay as they were."""
        self.act(act_payload, rng)

    @rule(rng=RANDOM)
    def terrain(self, rng):
        """Terrain's parameters, terrain-frame targets and TERRAIN_DATA (act_terrain): not among the
        seeded walk's ACTIONS either, for the same reason."""
        self.act(act_terrain, rng)

    @rule(rng=RANDOM)
    def gps_jam(self, rng):
        """A jammed GPS and the EKF check's parameters (act_gps_jam): not among the seeded walk's
        ACTIONS either."""
        self.act(act_gps_jam, rng)

    @rule(rng=RANDOM)
    def camera_lens(self, rng):
        """A zoom, a focus or a configure (act_camera_lens): not among the seeded walk's ACTIONS
        either."""
        self.act(act_camera_lens, rng)

    @rule(msg=MESSAGES)
    def hostile_as_in_the_hostile_message_tests(self, msg):
        self.act(lambda w, _: w.send(msg), None)

    def teardown(self):
        walk = getattr(self, "walk", None)
        if walk is not None:
            for facet in walk.facets:
                event(facet)  # `pytest --hypothesis-show-statistics` shows how often each state was reached


assert set(ACTIONS) <= set(vars(StateSpace)), "every action of the walk is a rule"

StateSpace.TestCase.settings = settings(
    max_examples=40, stateful_step_count=40, deadline=None, derandomize=True, database=None,
    phases=[Phase.explicit, Phase.generate],  # the failure is shrunk by the walk (shrink()), in bounded time
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much, HealthCheck.data_too_large])
TestStateSpaceRules = StateSpace.TestCase


# ----- the seeded walk of `make fuzz`, shorter -----------------------------------------------------------
WALK_STEPS = 10000
WALK_SEED = 6  # one whose walk reaches every REQUIRED state (seeds 1, 3 and 6 do with the payload commands)

# What the walk must reach (state_machine.facets names them): every start-up stage; every mode
# disarmed and flying; armed on the ground in the modes that arm; landing; every failsafe; the
# GPS lost; home not yet set; every transfer half done; the camera at work.
MODES = ("STABILIZE", "ALT_HOLD", "AUTO", "GUIDED", "LOITER", "RTL", "LAND", "POSHOLD", "BRAKE")
REQUIRED = (
    {f"stage:{s}" for s in ("boot", "no_fix", "no_home", "no_position", "ready", "instant")}
    | {f"{m}|disarmed" for m in MODES} | {f"{m}|flying" for m in MODES if m != "LAND"}
    | {f"{m}|armed_ground" for m in ("STABILIZE", "ALT_HOLD", "GUIDED", "LOITER", "POSHOLD", "LAND")}
    | {"LAND|landing", "RTL|landing", "GUIDED|takeoff", "phase:disarmed_air"}
    | {"fs:batt_low", "fs:batt_crit", "fs:gcs", "fs:fence", "fs:ekf", "gps_lost", "gps_glitch", "no_home"}
    | {f"xfer:{x}" for x in ("mission", "fence", "rally", "params", "ftp")}
    | {"camera_busy"})  # a camera taking pictures: by time, by distance, or one under way


@pytest.fixture(scope="module")
def walked():
    return run(WALK_STEPS, seed=WALK_SEED, repros=1, shrink_budget_s=3.0, shrink_total_s=20.0)


def _abridged(code: str, most: int = 40) -> str:
    lines = code.splitlines()
    if len(lines) <= most:
        return code
    head = [line for line in lines[:4] if not line.startswith("w.")]
    return "\n".join(head + [f"# ... {len(lines) - len(head) - most + 8} steps not shrunk "
                              "(python -m tests.fuzz.state_walk shrinks longer) ..."] + lines[-(most - 8):])


def test_the_seeded_walk_reaches_every_state(walked):
    facets = walked["facets"]
    missing = sorted(REQUIRED - set(facets))
    assert not missing, (f"the walk ({walked['steps']} steps, {walked['states_visited']} states) never reached "
                         f"{missing}; reached: {facets}")


def test_the_seeded_walk_breaks_no_invariant(walked):
    report = []
    for e in walked["distinct_failures"]:
        first = e["reproductions"][0]
        report.append(f"x{e['count']} {e['signature']}\n  state: {first['state']}\n  message: {first['message']}\n"
                      f"  {first['detail'].strip()}\n  reproduction:\n"
                      + "\n".join("    " + line for line in _abridged(first["reproduction"]).splitlines()))
    assert walked["failures_found"] == 0, (
        f"{walked['failures_found']} failures, {len(report)} distinct, in {walked['steps']} steps "
        f"(seed {WALK_SEED}):\n\n" + "\n\n".join(report))


def test_a_known_reproduction_is_sent_in_every_state_the_walk_reaches():
    """The walk's `known` action draws from these: each is well formed and addressed to the vehicle."""
    walk = Walk("instant")
    for built in hostile.known_reproductions(walk.client, walk.origin):
        decoded = walk._parser.parse_buffer(bytes(built.pack(walk.client)))
        assert decoded and decoded[0].get_type() != "BAD_DATA"
        assert getattr(decoded[0], "target_system", 0) == hostile.SYSTEM_ID


@pytest.mark.internal_errors  # a handler that raises is planted: the vehicle counts it as one
def test_a_failure_names_state_message_traceback_and_reproduction(monkeypatch):
    """The machinery itself: a handler that raises is reported with the state, the message, its
    traceback and Python that reproduces it; replaying the trace fails the same way."""
    from firefly.autopilot.mavlink import commands

    def broken(session, command):
        raise ZeroDivisionError("planted")
    monkeypatch.setitem(commands.HANDLERS, commands.mav.MAV_CMD_GET_HOME_POSITION, broken)
    walk = Walk("instant")
    walk.advance(0.5)
    with pytest.raises(WalkFailure) as caught:
        walk.command(commands.mav.MAV_CMD_GET_HOME_POSITION)
    f = caught.value.failure
    assert (f.kind, f.where) == ("handler_error", "session.receive")
    assert f.state.startswith("instant STABILIZE disarmed") and "command=410" in f.message
    assert "ZeroDivisionError: planted" in f.detail and "in broken" in f.detail  # the traceback
    assert f.signature() == ("handler_error in session.receive: ZeroDivisionError at "
                             "autopilot/mavlink/commands.py:handle")  # the innermost frame of the vehicle's code
    code = render(f.trace)
    assert code.splitlines()[:3] == ["from tests.fuzz.state_machine import Walk", "w = Walk('instant')", "c = w.client"]
    assert "w.advance_to(0.5)" in code and "w.send(c.command_long_encode(1, 1, 410, 0, 0.0," in code
    with pytest.raises(WalkFailure) as again:
        exec(code, {})
    assert again.value.failure.signature() == f.signature()


def test_a_refused_command_that_changed_the_mode_is_caught(monkeypatch):
    from firefly.autopilot.mavlink import commands
    from firefly.autopilot.results import Result

    def half_done(session, command):
        session.vehicle.set_mode(4)  # GUIDED, then refused
        return Result.FAILED
    monkeypatch.setitem(commands.HANDLERS, commands.mav.MAV_CMD_GET_HOME_POSITION, half_done)
    walk = Walk("instant")
    with pytest.raises(WalkFailure) as caught:
        walk.command(commands.mav.MAV_CMD_GET_HOME_POSITION)
    assert caught.value.failure.kind == "refused_changed"
    assert "(False, 0, " in caught.value.failure.detail and "(False, 4, " in caught.value.failure.detail


def test_a_heartbeat_that_stops_unasked_is_caught():
    walk = Walk("instant")
    walk.advance(1.0)
    walk.session.streams.set_interval_us(hostile.mav.MAVLINK_MSG_ID_HEARTBEAT, -1)  # not asked over MAVLink
    with pytest.raises(WalkFailure) as caught:
        walk.advance(3.0)
    assert caught.value.failure.kind == "heartbeat" and "no HEARTBEAT for 1.5" in caught.value.failure.detail


def test_a_heartbeat_a_ground_station_slowed_down_is_not_a_failure():
    walk = Walk("instant")
    walk.command(hostile.mav.MAV_CMD_SET_MESSAGE_INTERVAL, hostile.mav.MAVLINK_MSG_ID_HEARTBEAT, 4e6)
    walk.advance(10.0)  # one every 4 s, as asked
    walk.command(hostile.mav.MAV_CMD_SET_MESSAGE_INTERVAL, hostile.mav.MAVLINK_MSG_ID_HEARTBEAT, -1)
    walk.advance(5.0)  # none, as asked

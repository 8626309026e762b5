"""Precision landing's target-lost machine (autopilot/precland_retry.py): the retries, their count
and the failsafe for each PLND_STRICT, as measured on ArduCopter SITL (parity area precland)."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.modes import ModeNumber
from firefly.autopilot.params import ParamStore
from firefly.autopilot.precland_retry import (FAILSAFE_HOLD_S, RETRY_CLIMB_M, Action, RetryMachine,
                                              TargetState)

from ._util import altitude, fly_until
from .test_precland import beacon_vehicle

LOST, FOUND, NEVER, OUT = (TargetState.RECENTLY_LOST, TargetState.FOUND, TargetState.NEVER_SEEN,
                           TargetState.OUT_OF_RANGE)
FROM = (4.0, -4.0, -5.0)  # where the target was last measured from (down: 5 m up)


def params(**values) -> ParamStore:
    p = ParamStore()
    for name, value in values.items():
        p.set(name, value)
    return p


class Run:
    """The machine stepped as a landing steps it, its texts kept."""
    def __init__(self, **values):
        self.m, self.p, self.said = RetryMachine(), params(**values), []
        self.m.begin()

    def step(self, state, now_s, position=(4.0, -4.0, -3.0), last_valid_s=0.0):
        return self.m.update(state, now_s, lambda text, severity: self.said.append(text), self.p,
                             last_valid_s, FROM, position)


def test_a_lost_target_descends_until_the_timeout_then_retries_above_where_it_was_seen():
    r = Run()  # PLND_STRICT 1, PLND_TIMEOUT 4 s
    assert r.step(LOST, 0.1) == (Action.DESCEND, None)
    assert r.step(LOST, 3.9) == (Action.DESCEND, None)
    assert r.step(LOST, 4.0) == (Action.DESCEND, None)  # the timeout noticed: the retry next
    action, point = r.step(LOST, 4.1)
    assert action == Action.RETRY and point == pytest.approx((4.0, -4.0, -5.0 - RETRY_CLIMB_M))
    assert r.said == ["PrecLand: Retrying"]
    # Still on its way: the same point; within 0.75 m of it: straight down to the reading's height.
    assert r.step(LOST, 5.0, position=(4.0, -4.0, -4.0))[1] == pytest.approx(point)
    r.step(LOST, 6.0, position=(4.1, -4.0, -6.2))
    action, back = r.step(LOST, 6.1, position=(4.2, -3.9, -6.0))
    assert action == Action.RETRY and back == pytest.approx((4.2, -3.9, -5.0))
    r.step(LOST, 7.0, position=(4.2, -3.9, -5.6))
    assert r.said[-1] == "PrecLand: Retry Completed"
    # Done, and still not in sight: the failsafe, a 7 s hold, then down where it is.
    assert r.step(LOST, 7.1) == (Action.HOLD, None)
    assert r.said[-1] == "PrecLand: Failsafe Measures"
    assert r.step(LOST, 7.1 + FAILSAFE_HOLD_S - 0.1)[0] == Action.HOLD
    assert r.step(LOST, 7.1 + FAILSAFE_HOLD_S)[0] == Action.DESCEND
    assert r.said.count("PrecLand: Failsafe Measures") == 1


def test_not_strict_descends_where_it_is_and_very_strict_holds_for_good():
    r = Run(PLND_STRICT=0)
    assert all(r.step(LOST, t)[0] == Action.DESCEND for t in (0.1, 5.0, 60.0))
    assert r.said == []
    r = Run(PLND_STRICT=2, PLND_RET_MAX=0)
    r.step(LOST, 0.1)
    assert r.step(LOST, 4.0)[0] == Action.DESCEND  # PLND_TIMEOUT noticed
    assert all(r.step(LOST, t)[0] == Action.HOLD for t in (4.1, 20.0, 600.0))
    assert r.said == ["PrecLand: Failsafe Measures"]


def test_no_retries_allowed_is_the_failsafe_where_the_retry_would_begin():
    r = Run(PLND_RET_MAX=0)
    r.step(LOST, 0.1)
    r.step(LOST, 4.0)
    assert r.step(LOST, 4.1) == (Action.HOLD, None)
    assert r.said == ["PrecLand: Failsafe Measures"]


def test_the_target_found_again_starts_over_but_the_retries_count_on_until_the_mode_changes():
    r = Run(PLND_RET_MAX=1)
    r.step(LOST, 0.1)
    r.step(LOST, 4.0)
    assert r.step(LOST, 4.1)[0] == Action.RETRY
    assert r.step(FOUND, 5.0) == (Action.DESCEND, None)  # seen again during the climb
    r.step(LOST, 10.0, last_valid_s=9.0)
    r.step(LOST, 13.0, last_valid_s=9.0)
    # The second retry is past PLND_RET_MAX 1: flown for one step, unsaid, then the failsafe.
    assert r.step(LOST, 13.1, last_valid_s=9.0)[0] == Action.RETRY
    assert r.step(LOST, 13.2, last_valid_s=9.0)[0] == Action.HOLD
    assert r.said == ["PrecLand: Retrying", "PrecLand: Failsafe Measures"]
    r.m.begin()  # a new landing mode: the count starts again
    r.step(LOST, 20.0, last_valid_s=19.0)
    r.step(LOST, 23.0, last_valid_s=19.0)
    assert r.step(LOST, 23.1, last_valid_s=19.0)[0] == Action.RETRY
    assert r.said[-1] == "PrecLand: Retrying"


def test_out_of_range_descends_and_never_seen_is_the_failsafe():
    r = Run()
    assert r.step(OUT, 0.1) == (Action.DESCEND, None)
    assert r.step(NEVER, 0.2) == (Action.HOLD, None)
    assert r.step(OUT, 0.3) == (Action.DESCEND, None)  # below PLND_ALT_MIN: down, the failsafe forgotten
    r.step(NEVER, 0.4)
    assert r.said == ["PrecLand: Failsafe Measures"] * 2


def test_a_target_lost_out_of_range_is_never_seen_once_back_in_range():
    v = beacon_vehicle(0.0, 0.0)  # 10 m up, over the beacon, PLND_ALT_MAX 8 m
    assert v.precland.acquired
    v.params.set("SIM_PLD_ENABLE", 0)
    v.set_mode(ModeNumber.LAND)
    assert fly_until(v, lambda x: x.precland.state == TargetState.OUT_OF_RANGE, 5.0)
    assert fly_until(v, lambda x: x.precland.state == TargetState.NEVER_SEEN, 30.0)
    assert altitude(v) == pytest.approx(8.0, abs=0.3)


def test_land_retries_over_where_it_lost_the_beacon_then_lands_there():
    v = beacon_vehicle(4.0, -4.0)
    said = []
    v.text_listener = lambda severity, text: said.append(text)
    v.set_mode(ModeNumber.LAND)
    assert fly_until(v, lambda x: altitude(x) < 5.0, 60.0)
    v.params.set("SIM_PLD_ENABLE", 0)
    lost_at = altitude(v)
    assert v.precland_healthy  # SITL's beacon switched off keeps its last health
    assert fly_until(v, lambda x: "PrecLand: Retrying" in said, 10.0)
    low = altitude(v)
    assert low < lost_at - 2.5  # it descended PLND_TIMEOUT after losing it
    top = 0.0
    def climbed(x):
        nonlocal top
        top = max(top, altitude(x))
        return "PrecLand: Retry Completed" in said
    assert fly_until(v, climbed, 20.0)
    assert top > lost_at + 0.7  # towards 1.5 m over where it last saw the beacon
    assert fly_until(v, lambda x: not x.armed, 60.0)
    assert [t for t in said if "PrecLand" in t][-1] == "PrecLand: Failsafe Measures"
    beacon = v.sim.beacon
    assert math.hypot(v.body.n_m - beacon.n_m, v.body.e_m - beacon.e_m) < 0.3  # not back where LAND began

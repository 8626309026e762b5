"""The geofence's breaches (safety/fence_breach.py): what is said, kept, counted and done, as the
parity area `avoid` recorded ArduCopter."""
from __future__ import annotations

import math

from firefly.autopilot.modes import ModeNumber
from firefly.autopilot.results import Severity

from ._util import hovering_vehicle

CIRCLE, ALT_MAX = 2, 1


def fenced(action: int, **params):
    v = hovering_vehicle(10.0)
    said: list[tuple[str, int]] = []
    notify = v.notify
    v.notify = lambda text, severity=Severity.INFO: (said.append((text, severity)), notify(text, severity))[1]
    for name, value in {"AVOID_ENABLE": 0, "FENCE_TYPE": CIRCLE, "FENCE_RADIUS": 40, "FENCE_ACTION": action,
                        **params, "FENCE_ENABLE": 1}.items():
        v.params.set(name, value)
    v.fence.follow_param(v.params)
    return v, said


def fly_north_until(v, north_m: float, timeout_s: float = 40.0) -> None:
    end = v.time_s + timeout_s
    while v.body.n_m < north_m and v.time_s < end:
        v.guided_velocity(8.0, 0.0, 0.0)
        v.run_until(v.time_s + 0.2)


def test_a_breach_is_told_kept_and_counted_without_making_the_heartbeat_critical():
    v, said = fenced(action=0)
    fly_north_until(v, 45.0)
    v.run_until(v.time_s + 0.3)
    assert ("Circle fence breached", Severity.NOTICE) in said
    fence = v.failsafes.fence
    assert fence.breaches == CIRCLE and fence.count == 1 and 0 < fence.time_ms <= v.time_s * 1000
    assert not v.failsafe_active and v.mode_number == ModeNumber.GUIDED  # report only
    fly_north_until(v, 62.0)  # past the second fence, 20 m further out: a new breach
    v.run_until(v.time_s + 0.3)
    assert fence.count == 2 and [t for t, _ in said].count("Circle fence breached") == 2
    v.guided_goto(0.0, 0.0, v.body.d_m)
    v.run_until(v.time_s + 30.0)
    assert fence.breaches == 0 and said[-1] == ("Fence breach cleared", Severity.NOTICE)


def test_rtl_then_a_mode_change_is_manual_recovery_for_ten_seconds():
    v, said = fenced(action=1)
    fly_north_until(v, 45.0)
    v.run_until(v.time_s + 0.3)
    assert v.mode_number == ModeNumber.RTL
    # ArduCopter's own RTL is a mode change during a breach too
    assert [t for t, _ in said][-2:] == ["Circle fence breached", "Manual recovery started"]
    assert v.set_mode(ModeNumber.GUIDED) == 0 and said[-1][0] == "Manual recovery started"
    start = v.time_s
    fly_north_until(v, 70.0)  # past the backup fence within the recovery: no answer
    assert v.mode_number == ModeNumber.GUIDED and v.time_s - start < 10.0
    while v.time_s - start < 10.5:  # (drifting on past the next backup fence: still not answered)
        v.guided_velocity(0.0, 0.0, 0.0)
        v.run_until(v.time_s + 0.2)
    assert v.mode_number == ModeNumber.GUIDED and "Circle fence breached" not in [t for t, _ in said[-2:]]
    fly_north_until(v, 40.0 + v.failsafes.fence._backups[CIRCLE] + 2.0)  # the next one after the recovery: RTL again
    v.run_until(v.time_s + 0.3)
    assert v.mode_number == ModeNumber.RTL


def test_brake_is_fence_action_four():
    v, said = fenced(action=4)
    fly_north_until(v, 45.0)
    v.run_until(v.time_s + 0.3)
    assert v.mode_number == ModeNumber.BRAKE


def test_the_ceiling_is_max_alt():
    v, said = fenced(action=2, FENCE_TYPE=ALT_MAX, FENCE_ALT_MAX=15)
    end = v.time_s + 20.0
    while v.home_ned[2] - v.body.d_m < 15.5 and v.time_s < end:
        v.guided_velocity(0.0, 0.0, -3.0)
        v.run_until(v.time_s + 0.2)
    v.run_until(v.time_s + 0.3)
    assert "Max Alt fence breached" in [t for t, _ in said] and v.mode_number == ModeNumber.LAND
    assert math.isfinite(v.failsafes.fence.distance_outside(ALT_MAX))

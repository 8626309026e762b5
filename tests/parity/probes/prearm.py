"""The pre-arm reports a disarmed vehicle says unasked ("PreArm: ..."), which ground stations show
and scripts wait on: when the first comes after a check starts failing, how often it repeats,
and ARMING_OPTIONS bit 0 turning them off; and bit 1 silencing the arming texts.

check_fails  a ready vehicle; BATT_LOW_VOLT set above the battery's voltage (a check that fails
             at once, the same on both vehicles): the reports for 70 s, each as [seconds after the
             parameter was set, severity, text]; then the check passes again, ARMING_OPTIONS 2,
             the check fails again: the reports for 40 s
"""
from __future__ import annotations

from ..client import Client, mav
from ..facts import Tol, Trace
from .booting import each_on_a_fresh_vehicle

AREA = "prearm"
WHEN = Tol(abs=1.5, why="a once-a-second update on each vehicle, the parameter's echo and 10 Hz streams")


def _reports(c: Client, since_ms: int) -> list:
    return [[(stamp - since_ms) / 1000.0, severity, text] for stamp, severity, text in c.texts
            if stamp >= since_ms and text.startswith("PreArm: ")]


def check_fails(c: Client, trace: Trace) -> None:
    c.idle(2.0)
    t0 = c.now_ms
    trace.fact("set", c.set_param("BATT_LOW_VOLT", 20.0))
    c.idle(70.0)
    reports = _reports(c, t0)
    trace.fact("texts", sorted({r[2] for r in reports}))
    trace.fact("severities", sorted({r[1] for r in reports}))
    times = sorted({round(r[0], 1) for r in reports})
    trace.fact("count", len(times))
    trace.fact("first_s", times[0] if times else None, WHEN)
    trace.fact("then_every_s", [round(b - a, 1) for a, b in zip(times, times[1:])], WHEN)
    c.set_param("BATT_LOW_VOLT", 0.0)
    c.idle(2.0)
    trace.fact("options_set", c.set_param("ARMING_OPTIONS", 1))
    t1 = c.now_ms
    c.set_param("BATT_LOW_VOLT", 20.0)
    c.idle(40.0)
    trace.fact("options_off.count", len(_reports(c, t1)))
    c.set_param("BATT_LOW_VOLT", 0.0)
    c.set_param("BATT_ARM_VOLT", 20.0)
    c.idle(1.0)
    t2 = c.now_ms
    trace.fact("arm_volt.result", c.command(mav.MAV_CMD_RUN_PREARM_CHECKS))
    c.idle(1.0)
    trace.fact("arm_volt.said", [r[2] for r in _reports(c, t2)])


def _arm_disarm(c: Client, trace: Trace, name: str) -> None:
    for verb, value in (("arm", 1), ("disarm", 0)):
        t0 = c.now_ms
        trace.fact(f"{name}.{verb}", c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, value))
        c.idle(1.0)
        trace.fact(f"{name}.{verb}_said", [t for t in c.texts_since(t0) if not t.startswith("PreArm: ")])


def arm_texts(c: Client, trace: Trace) -> None:
    c.set_mode(4)  # GUIDED: an ARM on the ground there stays armed until disarmed
    c.idle(1.0)
    _arm_disarm(c, trace, "default")
    trace.fact("options_set", c.set_param("ARMING_OPTIONS", 2))
    _arm_disarm(c, trace, "options_2")
    c.set_param("ARMING_OPTIONS", 0)


PROBES = {"check_fails": check_fails, "arm_texts": arm_texts}


def run(target) -> dict[str, Trace]:
    return each_on_a_fresh_vehicle(target, PROBES, {name: None for name in PROBES})

"""MAV_CMD_DO_MOTOR_TEST (issue 32): a ground station's motor test, spinning one motor after
another on the ground, read off SERVO_OUTPUT_RAW (20 Hz) and HEARTBEAT's armed flag.

each_motor      disarmed on the ground: motors 1 to 4 in turn at 10 % for 1 s: the answer, the
                outputs during (the highest PWM of outputs 1-4), how long the test output lasts,
                whether HEARTBEAT says armed while it runs, what is said; armed after.
throttle_types  motor 1 for 1 s at PWM 1300 (type 1), at 150 % and at PWM 2300 (out of range),
                from the pilot's throttle (type 2), as a compass calibration at 10 % (type 3), and
                an unknown type 7: the answer, the output, what is said.
sequence        motor 1 with a count of 4 at 10 %, 1 s each: the outputs' order and when each
                starts and stops, and when the test says it finished.
armed_ground    armed on the ground in GUIDED, motor 2 at 10 % for 1 s: the answer, what is said,
                the arming after; then ARM, DISARM and ARM again: answers, arming, what is said.
during          a 4 s test of motor 1: HEARTBEAT's arming while it runs; a second MOTOR_TEST for
                motor 3 (answer, what is said, which outputs run), then ARM (answer, what is said,
                armed after) and the arming once the test is over.
odd_values      motor 0, motor 5, a NaN throttle: the answer, what is said, the outputs and armed
                after.
nan_timeout,    motor 1 at 10 % with a NaN or a negative timeout, each on its own vehicle (the test
negative_timeout  might never end): the same facts over 3 s.
"""
from __future__ import annotations

import math

from ..client import Client, mav
from ..facts import Tol, Trace
from .booting import each_on_a_fresh_vehicle
from .states import GUIDED
from .texts import said

AREA = "motor_test"
PERCENT, PWM, PILOT, COMPASS = (mav.MOTOR_TEST_THROTTLE_PERCENT, mav.MOTOR_TEST_THROTTLE_PWM,
                                mav.MOTOR_TEST_THROTTLE_PILOT, mav.MOTOR_TEST_COMPASS_CAL)
MOTOR_TEST = mav.MAV_CMD_DO_MOTOR_TEST
RESTING_US = 1000  # MOT_PWM_MIN: an output not under test
ON_S = Tol(abs=0.15, why="read off a 20 Hz stream: each end may fall a sample (50 ms) either way, and the "
                         "client reads in batches on a loaded machine")
AT_S = Tol(abs=0.2, why="when an output starts or stops after the command, read off a 20 Hz stream")


class Watch:
    """SERVO_OUTPUT_RAW's outputs 1-4 as they come, in vehicle time."""

    def __init__(self, c: Client):
        self.c = c
        self.outputs: list[tuple[int, tuple[int, int, int, int]]] = []
        c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_SERVO_OUTPUT_RAW, 50_000)

    def __call__(self, msg) -> None:
        kind = msg.get_type()
        if kind == "SERVO_OUTPUT_RAW":
            self.outputs.append((self.c.now_ms, (msg.servo1_raw, msg.servo2_raw, msg.servo3_raw, msg.servo4_raw)))

    def highest(self, t0: int, t1: int) -> list[int]:
        seen = [o for t, o in self.outputs if t0 <= t <= t1]
        return [max((o[i] for o in seen), default=0) for i in range(4)]

    def on_spans(self, t0: int, t1: int) -> list[list]:
        """[output, start s, stop s] for each run of an output above rest, from t0."""
        spans: list[list] = []
        running: dict[int, int] = {}
        for t, o in self.outputs:
            if not t0 <= t <= t1:
                continue
            for i, pwm in enumerate(o):
                if pwm > RESTING_US and i not in running:
                    running[i] = t
                elif pwm <= RESTING_US and i in running:
                    spans.append([i + 1, round((running.pop(i) - t0) / 1000, 2), round((t - t0) / 1000, 2)])
        spans.extend([i + 1, round((start - t0) / 1000, 2), None] for i, start in running.items())
        return sorted(spans, key=lambda s: s[1])


def _test(c: Client, trace: Trace, watch: Watch, name: str, *params: float, watch_s: float = 1.6,
          spans: bool = True) -> int:
    """One MOTOR_TEST: its answer, what is said, the outputs' highest, the runs, the arming
    after. The vehicle time it was sent."""
    t0 = c.now_ms
    trace.fact(f"{name}.result", c.command(MOTOR_TEST, *params))
    c.idle(watch_s)
    t1 = c.now_ms
    trace.fact(f"{name}.said", said(c.texts_since(t0, within_s=watch_s + 0.5)))
    trace.fact(f"{name}.highest_us", watch.highest(t0, t1), Tol(abs=2, why="PWM rounding"))
    if spans:
        runs = watch.on_spans(t0, t1)
        trace.fact(f"{name}.run_outputs", [output for output, _, _ in runs])
        trace.fact(f"{name}.run_starts_s", [start for _, start, _ in runs], ON_S)
        trace.fact(f"{name}.run_stops_s", [stop for _, _, stop in runs if stop is not None], ON_S)
    c.fresh_heartbeat()
    trace.fact(f"{name}.armed_after", c.armed)
    return t0


def each_motor(c: Client, trace: Trace) -> None:
    watch = Watch(c)
    with c.listening(watch):
        for seq in (1, 2, 3, 4):
            _test(c, trace, watch, f"motor{seq}", seq, PERCENT, 10, 1.0, 0, 0)


def throttle_types(c: Client, trace: Trace) -> None:
    watch = Watch(c)
    with c.listening(watch):
        _test(c, trace, watch, "pwm_1300", 1, PWM, 1300, 1.0)
        _test(c, trace, watch, "percent_150", 1, PERCENT, 150, 1.0)
        _test(c, trace, watch, "pwm_2300", 1, PWM, 2300, 1.0)
        _test(c, trace, watch, "pilot", 1, PILOT, 0, 1.0)
        _test(c, trace, watch, "compass", 1, COMPASS, 10, 1.0)
        _test(c, trace, watch, "type_7", 1, 7, 10, 1.0)


def sequence(c: Client, trace: Trace) -> None:
    watch = Watch(c)
    with c.listening(watch):
        t0 = _test(c, trace, watch, "four", 1, PERCENT, 10, 1.0, 4, watch_s=6.5)
        finished = [stamp for stamp, _, text in c.texts if stamp >= t0 and text == "finished motor test"]
        trace.fact("four.finished_after_s", round((finished[0] - t0) / 1000, 2) if finished else None, AT_S)


def armed_ground(c: Client, trace: Trace) -> None:
    watch = Watch(c)
    with c.listening(watch):
        c.set_mode(GUIDED)
        c.wait(lambda: c.mode == GUIDED, 5, what="GUIDED")
        trace.fact("arm.result", c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1))
        c.wait(lambda: c.armed, 5, what="armed")
        _test(c, trace, watch, "armed", 2, PERCENT, 10, 1.0, spans=False)
        t0 = c.now_ms
        trace.fact("rearm.result", c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1))
        c.idle(1.0)
        c.fresh_heartbeat()
        trace.fact("rearm.armed", c.armed)
        trace.fact("rearm.said", said(c.texts_since(t0, within_s=1.5)))
        for name, arm in (("disarm", 0), ("arm_again", 1)):
            t0 = c.now_ms
            trace.fact(f"{name}.result", c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, arm))
            c.idle(1.6)
            c.fresh_heartbeat()
            trace.fact(f"{name}.armed", c.armed)
            trace.fact(f"{name}.said", said(c.texts_since(t0, within_s=2.0)))
        if c.armed:
            c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0)


def during(c: Client, trace: Trace) -> None:
    watch = Watch(c)
    with c.listening(watch):
        t0 = c.now_ms
        trace.fact("first.result", c.command(MOTOR_TEST, 1, PERCENT, 10, 4.0))
        c.fresh_heartbeat()
        trace.fact("first.armed", c.armed)
        t1 = c.now_ms
        trace.fact("second.result", c.command(MOTOR_TEST, 3, PERCENT, 20, 4.0))
        c.idle(1.0)
        trace.fact("second.said", said(c.texts_since(t0, within_s=2.5)))
        trace.fact("second.highest_us", watch.highest(t1 + 300, c.now_ms), Tol(abs=2, why="PWM rounding"))
        t2 = c.now_ms
        trace.fact("arm.result", c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1))
        c.idle(1.0)
        trace.fact("arm.said", said(c.texts_since(t2, within_s=1.5)))
        c.fresh_heartbeat()
        trace.fact("arm.armed", c.armed)
        c.idle(4.0)
        c.fresh_heartbeat()
        trace.fact("end.armed", c.armed)
        trace.fact("end.said", said(c.texts_since(t2 + 1500)))
        if c.armed:
            c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0)


def odd_values(c: Client, trace: Trace) -> None:
    watch = Watch(c)
    with c.listening(watch):
        _test(c, trace, watch, "motor0", 0, PERCENT, 10, 1.0)
        _test(c, trace, watch, "motor5", 5, PERCENT, 10, 1.0)
        _test(c, trace, watch, "nan_throttle", 1, PERCENT, math.nan, 1.0)


def _timeout(value: float):
    """A timeout that may never end the test: alone on its vehicle, watched for 3 s."""
    def probe(c: Client, trace: Trace) -> None:
        watch = Watch(c)
        with c.listening(watch):
            _test(c, trace, watch, "test", 1, PERCENT, 10, value, watch_s=3.0)
    return probe


PROBES = {"each_motor": each_motor, "throttle_types": throttle_types, "sequence": sequence,
          "armed_ground": armed_ground, "during": during, "odd_values": odd_values,
          "nan_timeout": _timeout(math.nan), "negative_timeout": _timeout(-1.0)}


def run(target) -> dict[str, Trace]:
    return each_on_a_fresh_vehicle(target, PROBES, {name: None for name in PROBES})

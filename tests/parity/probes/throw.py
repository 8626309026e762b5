"""THROW flown as ArduPilot's own autotest throws it: THROW set while disarmed on the ground,
armed, left waiting longer than DISARM_DELAY, then pushed by the simulator's shove
(SIM_SHOVE_X/Y/Z for SIM_SHOVE_TIME): an upward throw (up and backwards for half a second, as
ArduCopter's ThrowMode test) handing over to LOITER, and a drop (THROW_TYPE 1: a slow lift by a
long gentle shove, as its ThrowDoubleDrop test, then let go to fall) handing over to GUIDED.

Read off GLOBAL_POSITION_INT at 50 Hz and the texts, in vehicle time counted from the launch
(the first position sample moving faster than LAUNCH_M_S after the shove was asked for): when
each stage's text came, the peak height, the height it settled at, how far it drifted, the mode
it handed over to and when, and whether it stayed armed. Entering THROW (disarmed only) and its
refusal when armed are surface_modes' facts; the entry is read again here as the first step."""
from __future__ import annotations

import math

from ..client import Client, ProbeTimeout, mav
from ..facts import Tol, Trace
from .states import GUIDED, LOITER, on_ground_disarmed
from .texts import said

AREA = "throw"
THROW = 18
DROP = 1
POSITION_US = 20_000   # GLOBAL_POSITION_INT at 50 Hz: stage times to a sample
HEARTBEAT_US = 100_000  # 10 Hz: the handover's time to a beat
ARMABLE_WITHIN_S = 30.0
WAIT_ARMED_S = 12.0    # longer than DISARM_DELAY (10 s on both): THROW never disarms by itself
LAUNCH_M_S = 1.0
SETTLE_S = 8.0         # after the handover, before the end facts are read
EARTH_M_PER_DEG = 111_195.0
STAGE_TEXTS = {"detected": "throw detected - spooling motors", "spooled": "throttle is unlimited - uprighting",
               "uprighted": "uprighted - controlling height", "height": "height achieved - controlling position"}

STAGE_TIME = Tol(abs=0.3, rel=0.2, why="stage texts timed to 50 Hz samples; spool-up, uprighting and the height "
                                       "controller's approach differ between the airframes and controllers")
HEIGHT = Tol(abs=1.5, rel=0.1, why="heights: the shove's integration, drag and the height controller's "
                                   "overshoot differ between the two simulators")
DRIFT = Tol(abs=2.0, rel=0.2, why="horizontal travel: drag while coasting and the brake's deceleration differ")
WAIT_PWM = Tol(abs=10.0, why="motor output while waiting: PWM rounding")


class Throw:
    """One throw: the parameters set before entering THROW, the shove (X, Y, Z [m/s^2], ms), the
    mode it should hand over to, how long to watch for that, and whether its heights above
    ground are the throw's (an upward throw) or only the harness's (a long lift before a drop:
    how high the simulator's drag lets it rise is no fact about THROW; heights are then read
    from where the drop was detected)."""

    def __init__(self, params: dict, shove: tuple[float, float, float, int], next_mode: int, watch_s: float,
                 heights_from_ground: bool):
        self.params, self.shove, self.next_mode, self.watch_s = params, shove, next_mode, watch_s
        self.heights_from_ground = heights_from_ground


# ArduCopter's ThrowMode autotest's throw: up and backwards at 30 and 20 m/s^2 for half a second
UPWARD = Throw({"THROW_TYPE": 0, "THROW_NEXTMODE": LOITER}, (-20.0, 0.0, -30.0, 500), LOITER, 25.0, True)
# -11 m/s^2 body-down against 9.8 of gravity: a gentle lift for 8 s (ThrowDoubleDrop's), then let go
LIFT_THEN_DROP = Throw({"THROW_TYPE": DROP, "THROW_NEXTMODE": GUIDED}, (0.0, 0.0, -11.0, 8000), GUIDED, 40.0,
                      False)


def arm(c: Client) -> int | None:
    """ARM retried while a fresh vehicle's checks still refuse; the last result."""
    start = c.now_ms
    while (result := c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)) != mav.MAV_RESULT_ACCEPTED:
        if c.now_ms - start > ARMABLE_WITHIN_S * 1000:
            return result
        c.idle(1.0)
    c.wait(lambda: c.armed, 5, what="armed")
    return result


def horizontal_m(a, b) -> float:
    dn = (b.lat - a.lat) * 1e-7 * EARTH_M_PER_DEG
    de = (b.lon - a.lon) * 1e-7 * EARTH_M_PER_DEG * math.cos(math.radians(a.lat * 1e-7))
    return math.hypot(dn, de)


def fly(c: Client, throw: Throw, trace: Trace) -> None:
    on_ground_disarmed(c)
    for name, value in throw.params.items():
        c.set_param(name, value)
    trace.fact("enter_disarmed", c.set_mode(THROW))
    c.wait(lambda: c.mode == THROW, 5, what="THROW")
    armed_ms = c.now_ms
    trace.fact("arm", arm(c))
    c.idle(WAIT_ARMED_S)
    c.fresh_heartbeat()
    trace.fact("armed_while_waiting", c.armed)
    trace.fact("said_on_arming", said(c.texts_since(armed_ms)))
    servo = c.last.get("SERVO_OUTPUT_RAW")
    trace.fact("motor_pwm_waiting", servo.servo1_raw if servo else None, WAIT_PWM)
    trace.fact("height_waiting_m", c.rel_alt_m(), Tol(abs=0.3, why="resting height: the estimates' noise"))
    x, y, z, millis = throw.shove
    for name, value in (("SIM_SHOVE_X", x), ("SIM_SHOVE_Y", y), ("SIM_SHOVE_Z", z)):
        c.set_param(name, value)
    log: list[tuple[int, object]] = []

    def record(msg) -> None:
        if msg.get_type() in ("GLOBAL_POSITION_INT", "HEARTBEAT", "STATUSTEXT"):
            log.append((c.now_ms, msg))
    with c.listening(record):
        shoved_ms = c.now_ms
        c.set_param("SIM_SHOVE_TIME", millis)  # the reference echoes 500, Firefly 0 at once: either will do
        handed = c.try_wait(lambda: c.mode == throw.next_mode, throw.watch_s)
        if handed:
            c.idle(SETTLE_S)
    read_off(c, throw, trace, [(t, m) for t, m in log if t >= shoved_ms])


def read_off(c: Client, throw: Throw, trace: Trace, log: list) -> None:
    positions = [(t, m) for t, m in log if m.get_type() == "GLOBAL_POSITION_INT"]
    moving = next(((t, m) for t, m in positions if math.hypot(m.vx, m.vy, m.vz) / 100.0 > LAUNCH_M_S), None)
    if moving is None:
        trace.fact("launched", False)
        return
    trace.fact("launched", True)
    launch_ms, at_launch = moving
    before = [m for t, m in positions if t < launch_ms]
    ground = before[-1] if before else at_launch
    texts = [(t, m.text) for t, m in log if m.get_type() == "STATUSTEXT"]
    trace.fact("said", said([text for _, text in texts]))
    for stage, text in STAGE_TEXTS.items():
        when = next((t for t, said_text in texts if said_text == text), None)
        trace.fact(f"{stage}_after_s", None if when is None else (when - launch_ms) / 1000.0, STAGE_TIME)
    handed = next((t for t, m in log if m.get_type() == "HEARTBEAT" and m.custom_mode == throw.next_mode), None)
    trace.fact("handed_over_after_s", None if handed is None else (handed - launch_ms) / 1000.0,
               Tol(abs=0.5, rel=0.2, why="the handover waits for the position hold to settle within 0.5 m"))
    end = positions[-1][1]
    if throw.heights_from_ground:
        trace.fact("peak_height_m", max(m.relative_alt for _, m in positions) / 1000.0, HEIGHT)
        trace.fact("settled_height_m", end.relative_alt / 1000.0, HEIGHT)
    detected = next((t for t, text in texts if text == STAGE_TEXTS["detected"]), None)
    after = [m.relative_alt / 1000.0 for t, m in positions if detected is not None and t >= detected]
    if after:
        if throw.heights_from_ground:
            trace.fact("height_at_detection_m", after[0], HEIGHT)
        trace.fact("climbed_after_detection_m", max(after) - after[0], HEIGHT)
        trace.fact("lowest_below_detection_m", after[0] - min(after), HEIGHT)
        trace.fact("settled_below_detection_m", after[0] - after[-1], HEIGHT)
    trace.fact("settled_speed_m_s", math.hypot(end.vx, end.vy, end.vz) / 100.0,
               Tol(abs=0.5, why="still, within the estimates' noise"))
    trace.fact("peak_drift_m", max(horizontal_m(ground, m) for _, m in positions), DRIFT)
    trace.fact("drift_m", horizontal_m(ground, end), DRIFT)
    c.fresh_heartbeat()
    trace.fact("mode_after", c.mode)
    trace.fact("armed_after", c.armed)


def run(target) -> dict[str, Trace]:
    traces = {"upward_to_loiter": Trace(), "drop_to_guided": Trace()}
    c = target.boot()
    try:
        c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_GLOBAL_POSITION_INT, POSITION_US)
        c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_HEARTBEAT, HEARTBEAT_US)
        for (name, trace), throw in zip(traces.items(), (UPWARD, LIFT_THEN_DROP)):
            try:
                fly(c, throw, trace)
            except ProbeTimeout as e:
                trace.fact("timeout", str(e))
                c = target.boot()
                c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_GLOBAL_POSITION_INT, POSITION_US)
                c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_HEARTBEAT, HEARTBEAT_US)
    finally:
        target.close()
    return traces

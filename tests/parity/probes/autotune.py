"""AUTOTUNE's dance flown as a pilot flies it, on the roll axis alone (AUTOTUNE_AXES 1, so that
the area stays short): hovering in ALT_HOLD with the throttle stick at mid by RC override (ArduCopter
SITL's own receiver holds it at the bottom), the mode switched to AUTOTUNE and left alone until
"AutoTune: Success". Then the pilot's way of keeping the result: out to ALT_HOLD and back (the
tuned gains flown for testing), down with the throttle stick until the vehicle lands and disarms
in AUTOTUNE, which saves them.

Read off, in vehicle time: the texts (numbers masked: the tuned values are the airframe's), the
order of the tune types, how long the dance took, the first twitches' size (ATTITUDE at 50 Hz),
which way each gain moved and which parameters the save announced."""
from __future__ import annotations

import math
import re

from ..client import Client, ProbeTimeout, mav
from ..facts import Tol, Trace
from .flip import LOW, MID, Sticks, hover
from .states import ALT_HOLD

AREA = "autotune"
AUTOTUNE = 15
ATTITUDE_US = 20_000  # ATTITUDE at 50 Hz for the first twitches (then the default: a 180 s dance at
DEFAULT_INTERVAL_US = 0  # 50 Hz times the speedup is more than a busy client decodes)
SETTLE_S = 2.0
STREAMS_HZ = 4  # the streams' rate: a 250 s flight at speedup 20 is a lot for a busy client to decode
TUNE_WITHIN_S = 400.0  # ArduCopter SITL tunes roll in about 100 s
FIRST_TWITCHES_S = 3.0
WATCH_S = 3.0
LAND_WITHIN_S = 120.0
GAINS = ("ATC_RAT_RLL_P", "ATC_RAT_RLL_I", "ATC_RAT_RLL_D", "ATC_ANG_RLL_P", "ATC_ACCEL_R_MAX")
STAGE = re.compile(r"^AutoTune: Roll (.+) \d+%$")
NUMBER = re.compile(r"\d+(\.\d+)?")

DURATION = Tol(rel=1.0, why="how many twitches each tune type takes depends on how far the airframe's "
                            "gains are from its tune: ArduCopter SITL's quad tunes roll in ~103 s, "
                            "Firefly's heavier-inertia airframe in ~180 s")
TWITCH_RATE = Tol(rel=0.3, why="the first twitches' peak roll rate: both ask the rate that saturates the "
                               "rate loop in four ticks; the airframes' authority differs")
TWITCH_LEAN = Tol(abs=15.0, why="how far the first twitches roll: ArduCopter's stop at their peak "
                                "rate by ~7 degrees; Firefly's slower airframe runs to the 15-degree "
                                "abort and smaller twitches")


def read_gains(c: Client) -> dict[str, float | None]:
    out: dict[str, float | None] = {}
    for name in GAINS:
        c.last.pop("PARAM_VALUE", None)
        c.conn.mav.param_request_read_send(1, 1, name.encode(), -1)
        got = c.try_wait(lambda: getattr(c.last.get("PARAM_VALUE"), "param_id", None) == name, 5)
        out[name] = c.last["PARAM_VALUE"].param_value if got else None
    return out


def direction(before: float | None, after: float | None) -> str:
    if before is None or after is None:
        return "unread"
    if math.isclose(before, after, rel_tol=1e-4):
        return "same"
    return "up" if after > before else "down"


def masked(texts: list[str]) -> list[str]:
    """The texts without their percentages' repeats and with numbers as #: the sequence."""
    out: list[str] = []
    for text in texts:
        if STAGE.match(text):
            continue
        out.append(NUMBER.sub("#", text))
    return out


def tune(c: Client, sticks: Sticks, trace: Trace) -> None:
    before = read_gains(c)
    hover(c)
    sticks.pwm[2] = MID
    sticks.send()
    c.set_mode(ALT_HOLD)
    c.wait(lambda: c.mode == ALT_HOLD, 3, what="ALT_HOLD")
    c.idle(SETTLE_S)
    log: list[tuple[int, object]] = []

    def record(msg) -> None:
        if msg.get_type() in ("ATTITUDE", "STATUSTEXT", "COMMAND_ACK", "PARAM_VALUE"):
            log.append((c.now_ms, msg))
    with c.listening(record):
        c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_ATTITUDE, ATTITUDE_US)
        sent = c.now_ms
        trace.fact("result", c.set_mode(AUTOTUNE))
        acked = next((t for t, m in log if m.get_type() == "COMMAND_ACK" and m.command == mav.MAV_CMD_DO_SET_MODE),
                     sent)
        c.wait(lambda: c.now_ms >= acked + FIRST_TWITCHES_S * 1000, FIRST_TWITCHES_S + 5, what="the first twitches")
        c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_ATTITUDE, DEFAULT_INTERVAL_US)
        c.wait(lambda: any(t in ("AutoTune: Success", "AutoTune: Failed") or "Determination Failed" in t
                           or "Failed to level" in t for _, _, t in c.texts), TUNE_WITHIN_S, what="the tune's end")
        said = [(t, m.text) for t, m in log if m.get_type() == "STATUSTEXT" and t >= acked]
        ended = next((t for t, text in said if text == "AutoTune: Success"), c.now_ms)
        trace.fact("tuned_in_s", (ended - acked) / 1000.0, DURATION)
        stages = []
        for _, text in said:
            m = STAGE.match(text)
            if m and (not stages or stages[-1] != m.group(1)):
                stages.append(m.group(1))
        trace.fact("stages", stages)
        trace.fact("said", masked([text for _, text in said]))
        first = [m for t, m in log if m.get_type() == "ATTITUDE" and acked <= t <= acked + FIRST_TWITCHES_S * 1000]
        trace.fact("first_twitch_peak_rate_deg_s", max((abs(math.degrees(m.rollspeed)) for m in first), default=0.0),
                   TWITCH_RATE)
        trace.fact("first_twitch_lean_deg", max((abs(math.degrees(m.roll)) for m in first), default=0.0), TWITCH_LEAN)
        c.idle(WATCH_S)
        c.fresh_heartbeat()
        trace.fact("mode_after_success", c.mode)
        trace.fact("gains_after_success", {n: direction(before[n], v) for n, v in read_gains(c).items()})
        mark = c.now_ms
        c.set_mode(ALT_HOLD)
        c.wait(lambda: c.mode == ALT_HOLD, 3, what="ALT_HOLD")
        c.idle(WATCH_S)
        trace.fact("said_leaving", masked(c.texts_since(mark)))
        mark = c.now_ms
        trace.fact("result_again", c.set_mode(AUTOTUNE))
        c.idle(WATCH_S)
        trace.fact("said_again", masked(c.texts_since(mark)))
        mark = c.now_ms
        sticks.pwm[2] = LOW  # down on the throttle stick: lands and disarms in AUTOTUNE
        sticks.send()
        c.wait(lambda: not c.armed, LAND_WITHIN_S, what="landed and disarmed")
        c.idle(WATCH_S)
        trace.fact("said_disarming", [t for t in masked(c.texts_since(mark))
                                      if t.startswith("AutoTune") or t == "Disarming motors"])
        announced = {m.param_id for t, m in log if m.get_type() == "PARAM_VALUE" and t >= mark}
        trace.fact("save_announced", sorted(set(GAINS) & announced))
    after = read_gains(c)
    trace.fact("gains_saved", {n: direction(before[n], v) for n, v in after.items()})


def run(target) -> dict[str, Trace]:
    traces = {"roll_from_alt_hold": Trace()}
    c = target.boot(streams_hz=STREAMS_HZ)
    try:
        sticks = Sticks(c)
        with c.listening(sticks):
            if not c.set_param("AUTOTUNE_AXES", 1):
                raise ProbeTimeout("AUTOTUNE_AXES not set")
            tune(c, sticks, traces["roll_from_alt_hold"])
    finally:
        target.close()
    return traces

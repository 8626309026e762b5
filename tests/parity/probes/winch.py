"""ArduCopter's winch (AP_Winch, WINCH_*), as a copter user reaches it (issue 32): MAV_CMD_DO_WINCH
by COMMAND_LONG, COMMAND_INT and as a mission item, the WINCH_STATUS it streams (EXTRA1), the PWM
winch's servo output (SERVOn_FUNCTION 88) read off SERVO_OUTPUT_RAW, the aux switch (RCn_OPTION 44,
here by DO_AUX_FUNCTION) and the pre-arm check. ArduCopter's SITL simulates no winch: the line is
the autopilot's own estimate (it assumes the winch runs at the rate it asks), with no load on it.

none       defaults (WINCH_TYPE 0): DO_WINCH's answers for every action, no WINCH_STATUS on the
           streams, REQUEST_MESSAGE of it; then WINCH_TYPE 1 set without a reboot (no winch made
           yet): the answer and the pre-arm check.
unhealthy  WINCH_TYPE 1 at boot, no output with function 88: WINCH_* values and types, WINCH_STATUS
           at rest, a rate command (accepted, the line does not move), the pre-arm check.
pwm        WINCH_TYPE 1 at boot, output 9 the winch (SERVO9_FUNCTION 88): WINCH_STATUS at rest and
           its rate; a length-control run (+2 m then -1 m: the texts, the line over time), a
           rate-control run (the line's growth, the output at each rate, beyond WINCH_RATE_MAX,
           reversed, stopped, relaxed); bad parameters (NaN, out of range, unknown actions, a
           winch number); COMMAND_INT; the aux switch.
mission    the same winch in AUTO: DO_WINCH rate 0.5 m/s, a 4 s loiter, DO_WINCH relax: what is said
           and reached, the line and output after, the item as downloaded.
rc         the same winch with channel 9 its stick (RC9_OPTION 45), moved by override: the dead zone
           AP_Winch gives it, the rate from the stick, a DO_WINCH taking over until the stick
           moves past the dead zone again, the channel given back.
"""
from __future__ import annotations

import math
import re

from ..client import Client, mav
from ..facts import Tol, Trace
from ..targets import run_each
from .missions import upload
from .states import AUTO, GUIDED, reach_flying
from .surface_mission import Geometry, item
from .texts import said

AREA = "winch"
WINCH_OUT = 9
MSG_WINCH_STATUS = 9005  # (not in the v1.0 dialect the client may start with)
PWM_BOOT = {"WINCH_TYPE": 1, "SERVO9_FUNCTION": 88}
WINCH_PARAMS = ("WINCH_TYPE", "WINCH_RATE_MAX", "WINCH_POS_P", "WINCH_OPTIONS")
RELAXED, LENGTH, RATE = 0, 1, 2  # WINCH_ACTIONS ArduCopter handles
LINE = Tol(abs=0.08, why="the line read off a 10 Hz WINCH_STATUS, each report its own moment: "
                         "up to 0.1 s at up to 1 m/s either way")
PASSING = Tol(abs=0.05, why="interpolated between 10 Hz reports of a line moving at up to 1 m/s, each vehicle "
                            "updating it at its own rate (ArduCopter's 50 Hz winch in a 400 Hz loop, Firefly's in 100 Hz)")
SPEED = Tol(abs=0.08, why="the length controller's rate (error x WINCH_POS_P), read off a 10 Hz stream")
NAN = float("nan")
# How long an answer is waited for: generous, as on a busy machine a vehicle run at 20x moves its
# clock on by seconds between two reads
ANSWER_S = 30.0


def _plain(value: float):
    """NaN as a word (facts compare by equality)."""
    return "nan" if isinstance(value, float) and math.isnan(value) else value


def _param(c: Client, name: str) -> list:
    c.conn.mav.param_request_read_send(1, 1, name.encode(), -1)
    c.last.pop("PARAM_VALUE", None)
    if not c.try_wait(lambda: "PARAM_VALUE" in c.last and c.last["PARAM_VALUE"].param_id == name, ANSWER_S):
        return [None, None]
    m = c.last["PARAM_VALUE"]
    return [m.param_value, m.param_type]


def _status(c: Client) -> dict | None:
    """A WINCH_STATUS sent from now on (None: none came)."""
    seen = c.received.get("WINCH_STATUS", 0)
    if not c.try_wait(lambda: c.received.get("WINCH_STATUS", 0) > seen, ANSWER_S):
        return None
    m = c.last["WINCH_STATUS"]
    return {"line_length": m.line_length, "speed": m.speed, "tension": _plain(m.tension),
            "voltage": _plain(m.voltage), "current": _plain(m.current), "temperature": m.temperature,
            "status": m.status}


def _output(c: Client) -> int:
    c.fresh("SERVO_OUTPUT_RAW", ANSWER_S)
    return getattr(c.last["SERVO_OUTPUT_RAW"], f"servo{WINCH_OUT}_raw")


def _winch(c: Client, p1=1.0, action=RATE, length=0.0, rate=0.0) -> int | None:
    return c.command(mav.MAV_CMD_DO_WINCH, p1, action, length, rate, sim_s=ANSWER_S)


def _count(c: Client, kind: str, seconds: float) -> int:
    before = c.received.get(kind, 0)
    c.idle(seconds)
    return c.received.get(kind, 0) - before


def _prearm_winch(c: Client) -> list[str]:
    """The winch's words among what RUN_PREARM_CHECKS has said within 2 s."""
    t0 = c.now_ms
    c.command(mav.MAV_CMD_RUN_PREARM_CHECKS, sim_s=ANSWER_S)

    def winch_said() -> list[str]:
        return [text for text in c.texts_since(t0) if "inch" in text]
    c.try_wait(lambda: bool(winch_said()), 2.0)
    return winch_said()


def none(c: Client, trace: Trace) -> None:
    for action in (RELAXED, LENGTH, RATE, 3, 7):
        trace.fact(f"long.action{action}.result", _winch(c, 1, action, 1.0, 0.5))
    trace.fact("int.rate.result", c.command_int(mav.MAV_CMD_DO_WINCH, 0, 1, RATE, 0, 0.5, sim_s=ANSWER_S))
    trace.fact("status_sent_in_3s", _count(c, "WINCH_STATUS", 3.0))
    trace.fact("request_message.result", c.command(mav.MAV_CMD_REQUEST_MESSAGE, MSG_WINCH_STATUS, sim_s=ANSWER_S))
    trace.fact("prearm_no_winch", _prearm_winch(c))
    trace.fact("set_type_live", c.set_param("WINCH_TYPE", 1))
    trace.fact("type_live.rate.result", _winch(c, 1, RATE, 0, 0.5))
    trace.fact("type_live.status_sent_in_2s", _count(c, "WINCH_STATUS", 2.0))
    trace.fact("type_live.prearm", _prearm_winch(c))


def unhealthy(c: Client, trace: Trace) -> None:
    for name in WINCH_PARAMS:
        trace.fact(f"param.{name}", _param(c, name))
    trace.fact("rest.status", _status(c))
    trace.fact("rate.result", _winch(c, 1, RATE, 0, 0.5))
    c.idle(2.0)
    trace.fact("rate.status", _status(c))
    trace.fact("prearm", _prearm_winch(c))


class Watch:
    """WINCH_STATUS as it comes, stamped with its own time_usec (the vehicle's clock, as exact as
    either vehicle sends it: no lag of the client's reading in it)."""

    def __init__(self, c: Client):
        self.status: list[tuple[float, object]] = []

    def __call__(self, msg) -> None:
        if msg.get_type() == "WINCH_STATUS":
            self.status.append((msg.time_usec / 1e6, msg))

    def at(self, t_s: float):
        return min(self.status, key=lambda s: abs(s[0] - t_s))[1]

    def crossing_s(self, line_m: float, after_s: float) -> float | None:
        """When the line passed `line_m` (either way), interpolated between two reports."""
        seen = [(t, m.line_length) for t, m in self.status if t >= after_s]
        for (t0, a), (t1, b) in zip(seen, seen[1:]):
            if min(a, b) <= line_m <= max(a, b) and a != b:
                return t0 + (line_m - a) / (b - a) * (t1 - t0)
        return None


def _between(watch: Watch, after_s: float, a_m: float, b_m: float) -> float | None:
    ta, tb = watch.crossing_s(a_m, after_s), watch.crossing_s(b_m, after_s)
    return None if ta is None or tb is None else tb - ta


def _step(c: Client, trace: Trace, name: str, *params: float, settle_s: float = 2.0) -> None:
    """A DO_WINCH: its answer, what was said, and after `settle_s` the speed and the output."""
    t0 = c.now_ms
    trace.fact(f"{name}.result", _winch(c, *params))
    c.idle(settle_s)
    trace.fact(f"{name}.said", said(c.texts_since(t0)))
    trace.fact(f"{name}.speed", _plain(_status(c)["speed"]), SPEED)
    trace.fact(f"{name}.output", _output(c))


def pwm(c: Client, trace: Trace) -> None:
    c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_SERVO_OUTPUT_RAW, 100_000)
    for name in WINCH_PARAMS:
        trace.fact(f"param.{name}", _param(c, name))
    trace.fact("rest.status", _status(c))
    trace.fact("rest.output", _output(c))
    attitudes = c.received.get("ATTITUDE", 0)
    winch_status = _count(c, "WINCH_STATUS", 4.0)
    # EXTRA1's rate, as ATTITUDE (both asked at 10 Hz by the client's REQUEST_DATA_STREAM)
    trace.fact("status_per_attitude", round(winch_status / max(1, c.received.get("ATTITUDE", 0) - attitudes), 1),
               Tol(abs=0.1, why="a 4 s window cut between two 10 Hz messages"))
    watch = Watch(c)
    with c.listening(watch):
        # length control from the line at rest (0 m): +2 m, then -1 m once there. Flat out
        # (WINCH_RATE_MAX) while over a metre short, then closing in by WINCH_POS_P: the times
        # between lengths passed, by the reports' own stamps
        t0 = c.now_ms
        start_s = 0.0  # (watched from here: the line only rises from 0 in this run)
        trace.fact("lower2.result", _winch(c, 1, LENGTH, 2.0, 0))
        c.idle(10.0)
        trace.fact("lower2.said", said(c.texts_since(t0)))
        for a_m, b_m in ((0.2, 0.8), (1.0, 1.5), (1.5, 1.9)):
            trace.fact(f"lower2.s_{a_m:g}_to_{b_m:g}m", _between(watch, start_s, a_m, b_m), PASSING)
        passed = watch.crossing_s(1.5, start_s)
        trace.fact("lower2.speed_at_1.5m", None if passed is None else watch.at(passed).speed, SPEED)
        trace.fact("lower2.line_end", _status(c)["line_length"], LINE)
        trace.fact("lower2.output_end", _output(c))
        t0 = c.now_ms
        seen = len(watch.status)
        trace.fact("raise1.result", _winch(c, 1, LENGTH, -1.0, 0))
        c.wait(lambda: any(m.speed < 0 for _, m in watch.status[seen:]), ANSWER_S, what="the line winding in")
        c.idle(8.0)
        trace.fact("raise1.said", said(c.texts_since(t0)))
        # from the first report winding in (the line at most 0.1 m down from 2 m by then)
        start_s = next(t for t, m in watch.status[seen:] if m.speed < 0)
        trace.fact("raise1.s_1.8_to_1.5m", _between(watch, start_s, 1.8, 1.5), PASSING)
        trace.fact("raise1.line_end", _status(c)["line_length"], LINE)
        # rate control: the line grows at the rate asked
        seen = len(watch.status)
        trace.fact("rate05.result", _winch(c, 1, RATE, 0, 0.5))

        def running() -> list[tuple[float, float]]:
            return [(t, m.line_length) for t, m in watch.status[seen:] if m.speed == 0.5]
        c.wait(lambda: len(running()) > 1 and running()[-1][0] - running()[0][0] >= 2.0, ANSWER_S,
               what="2 s of the line at 0.5 m/s")
        (t0_s, a_m), (t1_s, b_m) = running()[0], running()[-1]
        trace.fact("rate05.line_m_per_s", (b_m - a_m) / (t1_s - t0_s), SPEED)
        trace.fact("rate05.output", _output(c))
    _step(c, trace, "rate_over_max", 1, RATE, 0, 3.0)
    _step(c, trace, "rate_back", 1, RATE, 0, -0.5)
    _step(c, trace, "relax", 1, RELAXED, 0, 0)
    trace.fact("relax.line_still", abs(_status(c)["line_length"] - _status(c)["line_length"]) < 0.01)
    _step(c, trace, "rate0", 1, RATE, 0, 0)
    _step(c, trace, "rate_nan", 1, RATE, 0, NAN)
    _step(c, trace, "rate_inf", 1, RATE, 0, math.inf)
    _step(c, trace, "length_nan", 1, LENGTH, NAN, 0)
    _step(c, trace, "action_nan", 1, NAN, 0, 0.3)
    _step(c, trace, "action258", 1, 258, 0, 0.4)
    _step(c, trace, "action_minus1", 1, -1, 0, 0.2)
    _step(c, trace, "action3_lock", 1, 3, 0, 0.2)
    _step(c, trace, "action7_load_line", 1, 7, 0, 0.2)
    _step(c, trace, "winch5", 5, RATE, 0, 0.1)
    trace.fact("int.rate.result", c.command_int(mav.MAV_CMD_DO_WINCH, 0, 1, RATE, 0, -0.25, sim_s=ANSWER_S))
    c.idle(1.0)
    trace.fact("int.rate.speed", _status(c)["speed"], SPEED)
    trace.fact("int.rate.output", _output(c))
    for position in (0, 2, 1):
        t0 = c.now_ms
        trace.fact(f"aux44_{position}.result", c.command(mav.MAV_CMD_DO_AUX_FUNCTION, 44, position, sim_s=ANSWER_S))
        c.idle(1.0)
        trace.fact(f"aux44_{position}.said", said(c.texts_since(t0)))
        trace.fact(f"aux44_{position}.speed", _status(c)["speed"], SPEED)
        trace.fact(f"aux44_{position}.output", _output(c))
    trace.fact("prearm", _prearm_winch(c))


def mission(c: Client, trace: Trace) -> None:
    c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_SERVO_OUTPUT_RAW, 100_000)
    reach_flying(c, 10.0)
    m = c.last["GLOBAL_POSITION_INT"]
    geo = Geometry(m.lat, m.lon)
    items = [item(mav.MAV_CMD_NAV_WAYPOINT, geo, at=(0.0, 0.0), alt=10.0),
             item(mav.MAV_CMD_DO_WINCH, geo, (1, RATE, 0, 0.5)),
             item(mav.MAV_CMD_NAV_LOITER_TIME, geo, (4, 0, 0, 0), at=(0.0, 0.0), alt=10.0),
             item(mav.MAV_CMD_DO_WINCH, geo, (1, RELAXED, 0, 0)),
             item(mav.MAV_CMD_NAV_LOITER_UNLIM, geo, at=(0.0, 0.0), alt=10.0)]
    trace.fact("upload", upload(c, items))
    trace.fact("downloaded_item2", _download_item(c, 2))
    reached: list[int] = []

    def take(msg) -> None:
        if msg.get_type() == "MISSION_ITEM_REACHED":
            reached.append(msg.seq)
    with c.listening(take):
        t0 = c.now_ms
        c.set_mode(AUTO)
        c.wait(lambda: "MISSION_CURRENT" in c.last and c.last["MISSION_CURRENT"].seq == 5, 60, what="the loiter")
        c.idle(2.0)
    trace.fact("said", [text for text in said(c.texts_since(t0)) if text != "Flight plan received"])
    trace.fact("reached", reached)
    status = _status(c)
    trace.fact("end.line", status["line_length"], Tol(abs=0.4, why="0.5 m/s over the 4 s loiter and the "
                                                                        "moments either side of it, which each "
                                                                        "vehicle's waypoint takes its own time over"))
    trace.fact("end.speed", status["speed"], SPEED)
    trace.fact("end.output", _output(c))
    c.set_mode(GUIDED)


def _ch9(c: Client, pwm: int) -> None:
    """RC_CHANNELS_OVERRIDE of channel 9 alone (its extension field: 0 leaves a channel, 65534 gives
    it back to the receiver); held, as RC_OVERRIDE_TIME is -1 here."""
    c.conn.mav.rc_channels_override_send(1, 1, *([65535] * 8), pwm, *([0] * 9))


def rc(c: Client, trace: Trace) -> None:
    c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_SERVO_OUTPUT_RAW, 100_000, sim_s=ANSWER_S)
    trace.fact("param.RC9_DZ", _param(c, "RC9_DZ"))
    c.fresh("RC_CHANNELS", ANSWER_S)
    trace.fact("rest.ch9", c.last["RC_CHANNELS"].chan9_raw)
    trace.fact("rest.speed", _status(c)["speed"])
    trace.fact("rest.output", _output(c))

    def stick(name: str, pwm: int, output_tol: Tol | None = None) -> None:
        before = len(c.texts)  # (counted, not timed: a text read in the same instant belongs before)
        _ch9(c, pwm)
        c.idle(1.5)
        trace.fact(f"{name}.said", said([text for _, _, text in c.texts[before:]]))
        trace.fact(f"{name}.speed", _status(c)["speed"], SPEED)
        trace.fact(f"{name}.output", _output(c), output_tol)
    stick("stick1800", 1800)
    stick("stick1500", 1500)
    stick("stick1200", 1200)
    trace.fact("command_rate.result", _winch(c, 1, RATE, 0, 0.2))
    c.idle(1.0)
    trace.fact("command_rate.speed", _status(c)["speed"], SPEED)
    stick("stick1220_within_dz", 1220)
    stick("stick1700", 1700)
    t0 = c.now_ms
    trace.fact("command_length.result", _winch(c, 1, LENGTH, 0.5, 0))
    c.try_wait(lambda: any(text.startswith("Winch:") for text in c.texts_since(t0)), 2.0)
    # (the target is the line out then plus 0.5 m: where the stick's runs, timed by each vehicle, left it)
    trace.fact("command_length.said", [re.sub(r"\d+\.\d", "#", text) for text in said(c.texts_since(t0))])
    # (length control closing in: the rate and the output fall with the time since the command)
    stick("stick1690_within_dz", 1690, Tol(abs=35, why="the output follows the length controller's rate, "
                                                       "400 us per m/s: within SPEED's 0.08 m/s"))
    stick("released", 65534)
    c.fresh("RC_CHANNELS", ANSWER_S)
    trace.fact("released.ch9", c.last["RC_CHANNELS"].chan9_raw)


def _download_item(c: Client, seq: int) -> list | None:
    """MISSION_REQUEST_INT of one item after the count: (command, frame, p1..p4)."""
    got: list = []

    def answer(msg):
        if msg.get_type() == "MISSION_COUNT":
            c.conn.mav.mission_request_int_send(1, 1, seq, 0)
        elif msg.get_type() == "MISSION_ITEM_INT" and msg.seq == seq and not got:
            got.append([msg.command, msg.frame, msg.param1, msg.param2, msg.param3, msg.param4])
            c.conn.mav.mission_ack_send(1, 1, mav.MAV_MISSION_ACCEPTED, 0)
    with c.listening(answer):
        c.conn.mav.mission_request_list_send(1, 1, 0)
        c.try_wait(lambda: bool(got), 10)
    return got[0] if got else None


PROBES = {"none": (none, None), "pwm": (pwm, PWM_BOOT), "mission": (mission, PWM_BOOT),
          "rc": (rc, {**PWM_BOOT, "RC9_OPTION": 45, "RC_OVERRIDE_TIME": -1})}


def run(target, only: tuple[str, ...] = ()) -> dict[str, Trace]:
    traces = {}
    if not only or "unhealthy" in only:
        # never armable (the winch fails its check): booted without run_each's wait to arm once
        try:
            c = target.boot(streams_hz=None, params={"WINCH_TYPE": 1})
            c.request_streams(10)
            c.wait(lambda: "ATTITUDE" in c.last and "SYS_STATUS" in c.last, 60, what="requested streams")
            c.idle(15.0)  # past the start-up's own pre-arm reasons
            c.texts.clear()
            traces["unhealthy"] = Trace()
            unhealthy(c, traces["unhealthy"])
        finally:
            target.close()
    return {**traces, **run_each(target, PROBES, only)}

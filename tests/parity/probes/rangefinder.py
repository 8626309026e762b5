"""The rangefinder RNGFND1 (AP_RangeFinder) facing down, as ArduCopter runs it (issue 31).

sitl        RNGFND1_TYPE 100 at power-on (SITL's simulated beam): the parameters it brings, then on
            the ground (also with the RANGEFINDER aux function low, then high), hovering at 4 m
            (in range) and at 9 m (above RNGFND1_MAX, 7 m): what
            DISTANCE_SENSOR and RANGEFINDER carry and SYS_STATUS's laser-position bit; then
            SIM_SONAR_RND 0.5 m: the spread and mean of 40 ranges.
companion   RNGFND1_TYPE 10 at power-on (a companion's DISTANCE_SENSOR): before any message (the bit,
            RANGEFINDER, an ARM's answer), while one facing down comes at 20 Hz, one facing forward,
            and a second after they stop.
not_booted  RNGFND1_TYPE 100 set while running, no reboot: the bit and an ARM's answer.
"""
from __future__ import annotations

import time

from ..client import Client, mav
from ..facts import Tol, Trace
from .nav_flight import goto
from .states import GUIDED, reach_armed_on_ground

AREA = "rangefinder"
LASER = mav.MAV_SYS_STATUS_SENSOR_LASER_POSITION
PROBES_PARAMS = {"sitl": {"RNGFND1_TYPE": 100}, "companion": {"RNGFND1_TYPE": 10}, "not_booted": None}
PARAMS_READ = ("RNGFND1_ORIENT", "RNGFND1_MIN", "RNGFND1_MAX", "RNGFND1_GNDCLR")
LOW_M, HIGH_M = 4.0, 9.0
AUX_RANGEFINDER = 10  # RC_Channel's AUX_FUNC::RANGEFINDER
RANGE_CM = Tol(abs=15.0, why="a hover's height within the two position controllers' hold, and the "
                             "airframes' ground clearance; 15 cm of 4-9 m")
RANGE_M = Tol(abs=0.15, why="as RANGE_CM, in metres")
NOISE_M, NOISE_SAMPLES = 0.5, 40  # SIM_SONAR_RND while hovering at HIGH_M
COMPANION_SEND_WALL_S = 0.005  # DISTANCE_SENSOR sent at most this often (wall): 20 Hz at 10x is 5 ms
COMPANION_SIM_S = 3.0


def _laser(c: Client) -> dict:
    c.fresh("SYS_STATUS")
    s = c.last["SYS_STATUS"]
    return {"present": bool(s.onboard_control_sensors_present & LASER),
            "enabled": bool(s.onboard_control_sensors_enabled & LASER),
            "healthy": bool(s.onboard_control_sensors_health & LASER)}


def _bits(c: Client, trace: Trace, name: str) -> None:
    for key, value in _laser(c).items():
        trace.fact(f"{name}.laser_{key}", value)


def _distance_sensor(c: Client, trace: Trace, name: str, tol: Tol | None = RANGE_CM) -> None:
    c.fresh("DISTANCE_SENSOR", 5.0)
    d = c.last["DISTANCE_SENSOR"]
    trace.fact(f"{name}.current_cm", d.current_distance, tol)
    for field in ("min_distance", "max_distance", "type", "id", "orientation", "covariance", "signal_quality"):
        trace.fact(f"{name}.{field}", getattr(d, field))


def _rangefinder(c: Client, trace: Trace, name: str, tol: Tol | None = RANGE_M) -> None:
    c.fresh("RANGEFINDER", 5.0)
    r = c.last["RANGEFINDER"]
    trace.fact(f"{name}.rangefinder_m", round(r.distance, 2), tol)
    trace.fact(f"{name}.voltage", round(r.voltage, 3))


def _sent(c: Client, kind: str, sim_s: float = 2.0) -> bool:
    """Whether the vehicle sends `kind` within sim_s of vehicle time from now."""
    seen = c.received.get(kind, 0)
    return c.try_wait(lambda: c.received.get(kind, 0) > seen, sim_s)


def _read_param(c: Client, name: str) -> float | None:
    c.last.pop("PARAM_VALUE", None)
    c.conn.mav.param_request_read_send(1, 1, name.encode(), -1)
    got = c.try_wait(lambda: c.last.get("PARAM_VALUE") is not None and c.last["PARAM_VALUE"].param_id == name, 5.0)
    return round(c.last["PARAM_VALUE"].param_value, 4) if got else None


def _arm_texts(c: Client) -> tuple[int | None, list[str]]:
    """An ARM's result and the texts that came with it."""
    since = c.now_ms
    result = c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    c.idle(0.5)
    return result, [t for t in c.texts_since(since) if "angefinder" in t]


def sitl(c: Client, trace: Trace) -> None:
    for name in PARAMS_READ:
        trace.fact(f"param.{name}", _read_param(c, name))
    c.wait(lambda: "HOME_POSITION" in c.last, 60, what="home")
    _distance_sensor(c, trace, "ground", Tol(abs=15.0, why="the airframes' origin above the ground at rest"))
    _rangefinder(c, trace, "ground", Tol(abs=0.15, why="as ground.current_cm"))
    _bits(c, trace, "ground")
    for position, name in ((0, "aux_low"), (2, "aux_high")):  # the RANGEFINDER aux function (10)
        trace.fact(f"{name}.result", c.command(mav.MAV_CMD_DO_AUX_FUNCTION, AUX_RANGEFINDER, position))
        c.idle(0.3)
        _bits(c, trace, name)
        trace.fact(f"{name}.distance_sensor_sent", _sent(c, "DISTANCE_SENSOR"))
    reach_armed_on_ground(c, GUIDED)
    trace.fact("low.takeoff", c.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, LOW_M))
    c.wait(lambda: c.rel_alt_m() > LOW_M - 0.3, 60, what="the low hover")
    c.idle(3.0)
    _distance_sensor(c, trace, "low")
    _rangefinder(c, trace, "low")
    trace.fact("low.minus_rel_alt_m", round(c.last["RANGEFINDER"].distance - c.rel_alt_m(), 2),
               Tol(abs=0.15, why="range against the height above home while hovering"))
    _bits(c, trace, "low")
    goto(c, 0.0, 0.0, HIGH_M)
    c.idle(2.0)
    _distance_sensor(c, trace, "high")
    _rangefinder(c, trace, "high")
    _bits(c, trace, "high")
    trace.fact("noise.set", c.set_param("SIM_SONAR_RND", NOISE_M))
    samples = []
    for _ in range(NOISE_SAMPLES):
        c.fresh("DISTANCE_SENSOR", 5.0)
        samples.append(c.last["DISTANCE_SENSOR"].current_distance)
    trace.fact("noise.spread_cm", max(samples) - min(samples),
               Tol(abs=25.0, why=f"the widest of {NOISE_SAMPLES} uniform draws within +-{NOISE_M:g} m"))
    trace.fact("noise.mean_cm", round(sum(samples) / len(samples)), RANGE_CM)


def companion(c: Client, trace: Trace) -> None:
    c.wait(lambda: "HOME_POSITION" in c.last and c.last["GPS_RAW_INT"].fix_type >= 3, 120, what="home")
    c.idle(5.0)
    _bits(c, trace, "silent")
    trace.fact("silent.distance_sensor_sent", _sent(c, "DISTANCE_SENSOR"))
    _rangefinder(c, trace, "silent", None)
    c.set_mode(GUIDED)
    result, texts = _arm_texts(c)
    trace.fact("silent.arm", result)
    trace.fact("silent.arm_texts", texts)
    last_sent = [0.0]

    def feeding(orientation: int, current_cm: int):
        def send(_msg):
            wall = time.monotonic()
            if wall - last_sent[0] >= COMPANION_SEND_WALL_S:
                last_sent[0] = wall
                c.conn.mav.distance_sensor_send(0, 10, 50, current_cm, mav.MAV_DISTANCE_SENSOR_LASER, 7,
                                                orientation, 255)
        return send

    with c.listening(feeding(25, 20)):
        c.idle(COMPANION_SIM_S)
        _distance_sensor(c, trace, "fed", None)
        _rangefinder(c, trace, "fed", None)
        _bits(c, trace, "fed")
    c.idle(1.5)
    _bits(c, trace, "stopped")
    trace.fact("stopped.distance_sensor_sent", _sent(c, "DISTANCE_SENSOR"))
    _rangefinder(c, trace, "stopped", None)
    with c.listening(feeding(0, 300)):
        c.idle(COMPANION_SIM_S)
        _bits(c, trace, "forward")
        trace.fact("forward.distance_sensor_sent", _sent(c, "DISTANCE_SENSOR"))


def not_booted(c: Client, trace: Trace) -> None:
    c.wait(lambda: "HOME_POSITION" in c.last, 60, what="home")
    trace.fact("set", c.set_param("RNGFND1_TYPE", 100))
    c.idle(1.0)
    _bits(c, trace, "after_set")
    trace.fact("after_set.distance_sensor_sent", _sent(c, "DISTANCE_SENSOR"))
    trace.fact("after_set.rangefinder_sent", _sent(c, "RANGEFINDER"))
    c.set_mode(GUIDED)
    result, texts = _arm_texts(c)
    trace.fact("after_set.arm", result)
    trace.fact("after_set.arm_texts", texts)


PROBES = {"sitl": sitl, "companion": companion, "not_booted": not_booted}


def run(target) -> dict[str, Trace]:
    traces = {}
    try:
        for name, probe in PROBES.items():
            if name == "companion":  # never armable without its messages: booted without waiting for it
                client = target.boot(streams_hz=None, params=PROBES_PARAMS[name])
                client.request_streams(10)
                client.wait(lambda: "ATTITUDE" in client.last, 60, what="requested streams")
            else:
                client = target.boot(params=PROBES_PARAMS[name])
            trace = traces[name] = Trace()
            probe(client, trace)
    finally:
        target.close()
    return traces

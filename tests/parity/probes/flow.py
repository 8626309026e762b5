"""The optical flow sensor (AP_OpticalFlow, SITL's FLOW_TYPE 10) and FLOWHOLD (issue 31, items 2 and 4).

absent   default parameters (FLOW_TYPE 0): FLOWHOLD's answer, SYS_STATUS's optical-flow bits, whether
         OPTICAL_FLOW comes; then FLOW_TYPE 10 set while running (no driver until a reboot): the same.
no_sim   FLOW_TYPE 10 at power-on with SIM_FLOW_ENABLE 0 (a driver with nothing to read): the same;
         then SIM_FLOW_ENABLE 1 (the sensor wakes, no reboot): the same, FLOWHOLD now accepted;
         then the EXTRA3 stream stopped and started again: whether OPTICAL_FLOW stops and comes back.
flight   FLOW_TYPE 10 and SIM_FLOW_ENABLE 1 at power-on: the parameters' defaults; OPTICAL_FLOW on
         the ground (its fields, its rate at a requested 10 Hz), hovering at HOVER_M and flying north at SPEED_M_S in
         GUIDED; then FLOWHOLD with the sticks centred by override: the drift over HOLD_S and the
         height; then the pitch stick forward for STICK_S: the speed and distance it makes; then
         released: how far and how long it takes to stop; then a 3 m/s wind: how far it pushes and
         the drift after; then SIM_FLOW_ENABLE 0 in flight: the mode, the bits, the message, and
         FLOWHOLD asked for again from ALT_HOLD.
Numbers carry tolerances: the flow is noisy (SIM_FLOW_RND) and the airframes and controllers differ.
"""
from __future__ import annotations

import math

from ..client import Client, ProbeTimeout, mav
from ..facts import Tol, Trace
from .booting import each_on_a_fresh_vehicle
from .pilot import MID, Sticks
from .states import ALT_HOLD, GUIDED, reach_flying

AREA = "flow"
FLOWHOLD = 22
FLOW_BIT = mav.MAV_SYS_STATUS_SENSOR_OPTICAL_FLOW
SITL_FLOW = {"FLOW_TYPE": 10, "SIM_FLOW_ENABLE": 1}
PROBES_PARAMS = {"absent": None, "no_sim": {"FLOW_TYPE": 10}, "flight": SITL_FLOW}
PARAMS_READ = ("FLOW_TYPE", "FLOW_FXSCALER", "FLOW_FYSCALER", "FLOW_ORIENT_YAW", "FLOW_POS_X",
               "SIM_FLOW_ENABLE", "SIM_FLOW_RATE", "SIM_FLOW_DELAY", "SIM_FLOW_RND", "SIM_FLOW_POS_X",
               "FHLD_XY_P", "FHLD_XY_I", "FHLD_XY_IMAX", "FHLD_XY_FILT_HZ", "FHLD_FLOW_MAX", "FHLD_FILT_HZ",
               "FHLD_QUAL_MIN", "FHLD_BRAKE_RATE")
HOVER_M = 4.0
SPEED_M_S = 2.0
HOLD_S = 20.0
STICK_S = 3.0
STICK_FORWARD = 1300  # pitch channel: below mid is nose down, forward
STOP_M_S = 0.3
SAMPLES = 10
VELOCITY_ONLY = 0b0000_1111_1100_0111

RATE = Tol(abs=0.08, why="flow rates [rad/s]: SIM_FLOW_RND's +-0.05 uniform noise on both, averaged over "
                         f"{SAMPLES} samples, and the two hovers' own motion")
RATE_MOVING = Tol(abs=0.12, rel=0.15, why="flow rates flying at 2 m/s at 4 m (about 0.5 rad/s): the two "
                                          "vehicles' speed and height within their controllers' hold, and the noise")
DISTANCE = Tol(abs=0.5, why="OPTICAL_FLOW's ground_distance: each vehicle's height above ground estimate")
DRIFT = Tol(abs=1.5, why="a flow hold's drift: the integral of noisy flow, two vehicles' random walks")
HEIGHT = Tol(abs=0.6, why="a height held with the throttle at mid")
SPEED = Tol(abs=0.8, rel=0.3, why="the speed a stick makes against FLOWHOLD's own flow P term: two "
                                  "airframes' drag and lean dynamics")
TRAVEL = Tol(abs=2.0, rel=0.4, why="distances flown under a stick or braking: as SPEED")
STOP_TIME = Tol(abs=1.5, rel=0.4, why="braking to 0.3 m/s: FLOWHOLD's brake angle on two airframes")
WIND_M_S, WIND_SETTLE_S = 3.0, 5.0
WIND_PUSH = Tol(abs=2.0, rel=0.5, why="how far a 3 m/s wind carries the vehicle before FLOWHOLD's integrator "
                                      "leans against it: the two airframes' drag differs")
WIND_DRIFT = Tol(abs=2.0, why="a flow hold's drift in a steady wind, once leaning against it")
STREAM_RATE = Tol(abs=0.5, why="OPTICAL_FLOW's rate at a requested 10 Hz, from its own time stamps")
RATE_SAMPLES = 21


def _bits(c: Client, trace: Trace, name: str) -> None:
    c.fresh("SYS_STATUS")
    s = c.last["SYS_STATUS"]
    trace.fact(f"{name}.flow_bits", [bool(s.onboard_control_sensors_present & FLOW_BIT),
                                     bool(s.onboard_control_sensors_enabled & FLOW_BIT),
                                     bool(s.onboard_control_sensors_health & FLOW_BIT)])


def _sent(c: Client, kind: str, sim_s: float = 2.0) -> bool:
    seen = c.received.get(kind, 0)
    return c.try_wait(lambda: c.received.get(kind, 0) > seen, sim_s)


def _flowhold_answer(c: Client, trace: Trace, name: str, back: int) -> None:
    """FLOWHOLD asked for: the ACK, the texts, the mode after; then `back` again if it was taken."""
    since = c.now_ms
    trace.fact(f"{name}.flowhold", c.set_mode(FLOWHOLD))
    c.fresh_heartbeat()
    trace.fact(f"{name}.mode_after", c.mode)
    trace.fact(f"{name}.texts", [t for t in c.texts_since(since) if "ode" in t])
    if c.mode == FLOWHOLD:
        c.set_mode(back)
        c.fresh_heartbeat()


def _state(c: Client, trace: Trace, name: str, back: int = GUIDED) -> None:
    _bits(c, trace, name)
    trace.fact(f"{name}.optical_flow_sent", _sent(c, "OPTICAL_FLOW"))
    _flowhold_answer(c, trace, name, back)


def _read_param(c: Client, name: str) -> float | None:
    c.last.pop("PARAM_VALUE", None)
    c.conn.mav.param_request_read_send(1, 1, name.encode(), -1)
    got = c.try_wait(lambda: c.last.get("PARAM_VALUE") is not None and c.last["PARAM_VALUE"].param_id == name, 5.0)
    return round(c.last["PARAM_VALUE"].param_value, 4) if got else None


def _before_and_after(c: Client, trace: Trace, name: str, param: str) -> None:
    """The state at boot, then after `param` is set to 1 while running (no reboot)."""
    c.wait(lambda: "HOME_POSITION" in c.last, 60, what="home")
    c.set_mode(GUIDED)
    _state(c, trace, "boot")
    trace.fact(name, c.set_param(param, 10 if param == "FLOW_TYPE" else 1))
    c.idle(1.0)
    _state(c, trace, name)


def absent(c: Client, trace: Trace) -> None:
    _before_and_after(c, trace, "type_set", "FLOW_TYPE")


def no_sim(c: Client, trace: Trace) -> None:
    _before_and_after(c, trace, "sim_on", "SIM_FLOW_ENABLE")
    # which stream carries it: EXTRA3 stopped, then started again
    for name, hz in (("extra3_off", 0), ("extra3_on", 5)):
        c.conn.mav.request_data_stream_send(1, 1, mav.MAV_DATA_STREAM_EXTRA3, hz, 1 if hz else 0)
        c.idle(1.0)
        trace.fact(f"{name}.optical_flow_sent", _sent(c, "OPTICAL_FLOW"))


def _samples(c: Client, count: int = SAMPLES, keep_going=None) -> list:
    """The next `count` OPTICAL_FLOWs, every one (a client reading batches at speedup would skip
    some by reading only the last); keep_going() is called between reads (a target to repeat)."""
    out: list = []

    def take(msg):
        if msg.get_type() == "OPTICAL_FLOW":
            msg.heard_at_ms = c.now_ms  # the vehicle's clock as the message came (its other messages')
            out.append(msg)
    give_up_ms = c.now_ms + 20_000
    with c.listening(take):
        while len(out) < count:
            if c.now_ms > give_up_ms:
                raise ProbeTimeout(f"{len(out)} of {count} OPTICAL_FLOWs in 20 s")
            if keep_going is not None:
                keep_going()
            c.try_wait(lambda: len(out) >= count, 0.5)
    return out[:count]


def _mean(msgs: list, field: str) -> float:
    return round(sum(getattr(m, field) for m in msgs) / len(msgs), 3)


def _optical_flow(c: Client, trace: Trace, name: str, rate: Tol, distance: Tol | None = DISTANCE,
                  keep_going=None) -> None:
    msgs = _samples(c, keep_going=keep_going)
    m = msgs[-1]
    trace.fact(f"{name}.ids_quality", [m.sensor_id, m.quality])
    trace.fact(f"{name}.flow_xy", [m.flow_x, m.flow_y])  # int16 pixel fields: ArduPilot's rates, truncated
    trace.fact(f"{name}.flow_rate", [_mean(msgs, "flow_rate_x"), _mean(msgs, "flow_rate_y")], rate)
    trace.fact(f"{name}.flow_comp", [_mean(msgs, "flow_comp_m_x"), _mean(msgs, "flow_comp_m_y")], rate)
    # flow_rate_* and the compensated fields carry the same rates: the body rates, never zero in a
    # real hover, are what lies between them
    trace.fact(f"{name}.rate_is_flow_x", all(abs(x.flow_rate_x - x.flow_x) < 1.0 for x in msgs))
    if distance is not None:
        trace.fact(f"{name}.ground_distance", _mean(msgs, "ground_distance"), distance)
    trace.fact(f"{name}.time_is_boot_ms", all(abs(x.time_usec - x.heard_at_ms) < 1000 for x in msgs))


def _ne(c: Client) -> tuple[float, float]:
    c.fresh("LOCAL_POSITION_NED")
    p = c.last["LOCAL_POSITION_NED"]
    return p.x, p.y


def _speed(c: Client) -> float:
    p = c.last["LOCAL_POSITION_NED"]
    return math.hypot(p.vx, p.vy)


def _north(c: Client) -> None:
    c.conn.mav.set_position_target_local_ned_send(0, 1, 1, mav.MAV_FRAME_LOCAL_NED, VELOCITY_ONLY,
                                                  0, 0, 0, SPEED_M_S, 0, 0, 0, 0, 0, 0, 0)


def _fly_north(c: Client, sim_s: float) -> None:
    end = c.now_ms + sim_s * 1000
    while c.now_ms < end:
        _north(c)
        c.idle(0.5)


def flight(c: Client, trace: Trace) -> None:
    for name in PARAMS_READ:
        trace.fact(f"param.{name}", _read_param(c, name))
    c.wait(lambda: "HOME_POSITION" in c.last and c.last["GPS_RAW_INT"].fix_type >= 3, 120, what="home")
    _bits(c, trace, "ground")
    _optical_flow(c, trace, "ground", RATE, None)
    stamps = [m.time_usec for m in _samples(c, RATE_SAMPLES)]  # their own times (ms)
    trace.fact("ground.rate_hz", round((len(stamps) - 1) * 1000.0 / (stamps[-1] - stamps[0]), 1), STREAM_RATE)
    reach_flying(c, HOVER_M)
    c.idle(3.0)
    _optical_flow(c, trace, "hover", RATE)
    _fly_north(c, 4.0)
    _optical_flow(c, trace, "moving", RATE_MOVING, keep_going=lambda: _north(c))
    c.conn.mav.set_position_target_local_ned_send(0, 1, 1, mav.MAV_FRAME_LOCAL_NED, VELOCITY_ONLY,
                                                  0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0)
    c.wait(lambda: _speed(c) < 0.1, 20, what="stopped")
    sticks = Sticks(c)
    with c.listening(sticks):
        sticks.hold(MID, MID, MID, MID)
        c.idle(0.5)
        since = c.now_ms
        trace.fact("hold.flowhold", c.set_mode(FLOWHOLD))
        c.fresh_heartbeat()
        trace.fact("hold.mode", c.mode)
        trace.fact("hold.texts", [t for t in c.texts_since(since) if "ode" in t])
        c.idle(2.0)
        n0, e0 = _ne(c)
        alt0 = c.rel_alt_m()
        hest = []

        def heard(msg):
            if msg.get_type() == "NAMED_VALUE_FLOAT" and msg.name == "HEST":
                hest.append(msg.value)
        with c.listening(heard):
            c.idle(HOLD_S)
        n1, e1 = _ne(c)
        trace.fact("hold.drift_m", round(math.hypot(n1 - n0, e1 - e0), 2), DRIFT)
        trace.fact("hold.height_change_m", round(c.rel_alt_m() - alt0, 2), HEIGHT)
        trace.fact("hold.hest_sent", bool(hest))
        trace.fact("hold.hest_last", round(hest[-1], 2) if hest else None, Tol(abs=1.0, why="FLOWHOLD's "
                   "height estimate: learnt from flow against acceleration, clamped to 0.1-3 m"))
        trace.fact("hold.optical_flow_quality", c.last["OPTICAL_FLOW"].quality)
        # the stick: pitch forward, then released
        sticks.hold(MID, STICK_FORWARD, MID, MID)
        c.idle(STICK_S)
        n2, e2 = _ne(c)
        trace.fact("stick.speed_m_s", round(_speed(c), 2), SPEED)
        trace.fact("stick.north_m", round(n2 - n1, 2), TRAVEL)
        trace.fact("stick.east_m", round(e2 - e1, 2), TRAVEL)
        sticks.hold(MID, MID, MID, MID)
        released = c.now_ms
        stopped = c.try_wait(lambda: _speed(c) < STOP_M_S and c.now_ms - released > 300, 15)
        trace.fact("release.stopped", stopped)
        trace.fact("release.stop_s", round((c.now_ms - released) / 1000, 1), STOP_TIME)
        n3, e3 = _ne(c)
        trace.fact("release.north_m", round(n3 - n2, 2), TRAVEL)
        c.idle(5.0)
        n4, e4 = _ne(c)
        trace.fact("release.after_5s_m", round(math.hypot(n4 - n3, e4 - e3), 2), DRIFT)
        trace.fact("release.mode", c.mode)
        # a wind from the south: how far it carries the vehicle before the integrator leans against it
        trace.fact("wind.set", c.set_param("SIM_WIND_SPD", WIND_M_S) and c.set_param("SIM_WIND_DIR", 180))
        c.idle(WIND_SETTLE_S)
        n5, e5 = _ne(c)
        trace.fact("wind.pushed_north_m", round(n5 - n4, 2), WIND_PUSH)
        c.idle(HOLD_S)
        n6, e6 = _ne(c)
        trace.fact("wind.drift_m", round(math.hypot(n6 - n5, e6 - e5), 2), WIND_DRIFT)
        c.set_param("SIM_WIND_SPD", 0)
        # the camera stops: the mode stays, flying as ALT_HOLD; the message stops, the bit unhealthy
        trace.fact("sensor_off.set", c.set_param("SIM_FLOW_ENABLE", 0))
        c.idle(1.0)
        _bits(c, trace, "sensor_off")
        trace.fact("sensor_off.optical_flow_sent", _sent(c, "OPTICAL_FLOW"))
        c.fresh_heartbeat()
        trace.fact("sensor_off.mode", c.mode)
        # left for ALT_HOLD, FLOWHOLD is refused in flight without its sensor
        c.set_mode(ALT_HOLD)
        _flowhold_answer(c, trace, "sensor_off", ALT_HOLD)


PROBES = {"absent": absent, "no_sim": no_sim, "flight": flight}


def run(target) -> dict[str, Trace]:
    return each_on_a_fresh_vehicle(target, PROBES, PROBES_PARAMS)

"""EKF_STATUS_REPORT's variances: the numbers a ground station turns into its EKF indicator
(QGroundControl's EKF page, MAVProxy's red "EKF"), and that a user's script watches to call a
GPS bad before the failsafe does.

EKF3 reports the square roots of its innovation test ratios: 1 is the gate, FS_EKF_THRESH (0.8)
the failsafe's line. Each window collects the report as it streams (10 Hz) and keeps, per field,
its median and its highest value:

quiet   on the ground (settled past the EKF's start), then hovering 10 m up in GUIDED;
lost    hovering, then SIM_GPS1_ENABLE 0: when the position flag goes and the flags then (the
        variances held from the last fix, not raised); when the EKF stops aiding and holds a
        constant position (EKF_CONST_POS_MODE), and the flags and variances 20 s in.
no_gps  booted without a GPS: the flags and variances on the ground 40 s in.
jammed  hovering, then SIM_GPS1_JAM 1 (SITL's jammed receiver), the first 6 vehicle seconds:
        whether the velocity ratio passes the gate (1; how far is chance: ArduCopter's went to 173
        in one flight), the height's and compass's highest, and how long until the velocity
        variance first reaches FS_EKF_THRESH. The position ratio is not compared: whether a fix
        far enough off comes within the window is chance (ArduCopter's passed 1 in one of two
        flights, reaching 16.7).
"""
from __future__ import annotations

import statistics

from ..client import Client, mav
from ..facts import Tol, Trace
from .booting import each_on_a_fresh_vehicle
from .states import reach_flying

AREA = "ekf_variances"
FIELDS = ("velocity_variance", "pos_horiz_variance", "pos_vert_variance", "compass_variance")
WINDOW_S = 10.0
JAM_WINDOW_S = 6.0
LOST_WINDOW_S = 20.0  # past the EKF's dead reckoning (7 s) and its aiding (15 s)
HOVER_M = 10.0
THRESH = 0.8  # FS_EKF_THRESH's default

QUIET = Tol(abs=0.1, why="test ratios of a settled EKF: noise over its gates, a few hundredths on both "
                         "vehicles, never near the 0.8 a client or the failsafe acts on")
# Firefly's GPS has 0.3 m of noise per fix (sim/sensors.py), ArduCopter SITL's none (SIM_GPS1_NOISE
# 0): its position ratio is that noise over the 5 m gate, where ArduCopter's reads 0.00-0.01.
QUIET_POSITION = Tol(abs=0.3, why="Firefly's GPS has 0.3 m of noise per fix, ArduCopter SITL's none: the "
                                  "position ratio is that noise over EKF3's 5 m gate, up to about 0.25 at rest")
# A jammed receiver's readings are drawn at random on both vehicles (SITL's jamming and Firefly's
# alike): how high the ratios go and when they first pass the line vary from flight to flight.
LOST_TIME = Tol(abs=2.0, why="the EKF's dead reckoning after the last fix: seconds on both vehicles, seen at 10 Hz")
JAMMED_TIME = Tol(abs=3.0, why="chance: the first jammed fix far enough off to pass the line")


def _collect(c: Client, sim_s: float) -> list:
    reports: list = []

    def take(msg) -> None:
        if msg.get_type() == "EKF_STATUS_REPORT":
            reports.append((c.now_ms, msg))
    with c.listening(take):
        c.idle(sim_s)
    return reports


def _quiet(field: str) -> Tol:
    return QUIET_POSITION if field == "pos_horiz_variance" else QUIET


def _window(trace: Trace, name: str, reports: list) -> None:
    for field in FIELDS:
        values = [getattr(m, field) for _, m in reports]
        tol = _quiet(field)
        trace.fact(f"{name}.{field}.median", round(statistics.median(values), 2) if values else None, tol)
        trace.fact(f"{name}.{field}.max", round(max(values), 2) if values else None, tol)


def _settled(c: Client) -> None:
    c.wait(lambda: "HOME_POSITION" in c.last and c.last["GPS_RAW_INT"].fix_type >= 3, 120, what="a fix")
    c.idle(20.0)  # past the EKF's settling


def quiet(c: Client, trace: Trace) -> None:
    _settled(c)
    _window(trace, "ground", _collect(c, WINDOW_S))
    reach_flying(c, HOVER_M)
    c.idle(3.0)
    _window(trace, "hover", _collect(c, WINDOW_S))


def _fault_in_hover(c: Client, param: str, window_s: float) -> tuple[int, list]:
    """Hovering, SIM fault `param` set to 1 (0 for an ENABLE): when, and the reports of window_s."""
    _settled(c)
    reach_flying(c, HOVER_M)
    c.idle(3.0)
    start_ms = c.now_ms
    c.set_param(param, 0 if param.endswith("ENABLE") else 1)
    return start_ms, _collect(c, window_s)


def gps_lost(c: Client, trace: Trace) -> None:
    start_ms, reports = _fault_in_hover(c, "SIM_GPS1_ENABLE", LOST_WINDOW_S)
    def first(condition):
        t = next((t for t, m in reports if condition(m)), None)
        return (t, next(m for u, m in reports if u == t)) if t is not None else (None, None)
    gone, report = first(lambda m: not m.flags & mav.EKF_POS_HORIZ_ABS)
    trace.fact("lost.position_gone_s", round((gone - start_ms) / 1000.0, 1) if gone is not None else None, LOST_TIME)
    trace.fact("lost.flags_then", hex(report.flags) if report else None)
    for field in FIELDS:
        trace.fact(f"lost.{field}.then", round(getattr(report, field), 2) if report else None, _quiet(field))
    held, _ = first(lambda m: m.flags & mav.EKF_CONST_POS_MODE)
    trace.fact("lost.constant_position_s", round((held - start_ms) / 1000.0, 1) if held is not None else None,
               LOST_TIME)
    _, last = reports[-1]
    trace.fact("lost.flags_after", hex(last.flags))
    for field in FIELDS:
        trace.fact(f"lost.{field}.after", round(getattr(last, field), 2), _quiet(field))


def no_gps(c: Client, trace: Trace) -> None:
    """Booted with no GPS (SIM_GPS1_ENABLE 0): on the ground, disarmed, past the EKF's start."""
    c.request_streams(10)  # (booted without the wait for armable, which never comes)
    c.idle(40.0)
    c.fresh("EKF_STATUS_REPORT")
    r = c.last["EKF_STATUS_REPORT"]
    trace.fact("ground.flags", hex(r.flags))
    for field in FIELDS:
        trace.fact(f"ground.{field}", round(getattr(r, field), 2), _quiet(field))


def jammed(c: Client, trace: Trace) -> None:
    start_ms, reports = _fault_in_hover(c, "SIM_GPS1_JAM", JAM_WINDOW_S)
    trace.fact("jammed.velocity_variance.passes_gate", any(m.velocity_variance > 1.0 for _, m in reports))
    for field in ("pos_vert_variance", "compass_variance"):  # what the jamming leaves alone
        trace.fact(f"jammed.{field}.max", round(max(getattr(m, field) for _, m in reports), 2) if reports else None,
                   QUIET)
    over = next((t for t, m in reports if m.velocity_variance >= THRESH), None)
    trace.fact("jammed.velocity_over_thresh_s", round((over - start_ms) / 1000.0, 1) if over is not None else None,
               JAMMED_TIME)


PROBES = {"quiet": quiet, "jammed": jammed, "gps_lost": gps_lost}
PROBES_PARAMS = {"quiet": None, "jammed": None, "gps_lost": None}


def run(target) -> dict[str, Trace]:
    traces = each_on_a_fresh_vehicle(target, PROBES, PROBES_PARAMS)
    traces.update(each_on_a_fresh_vehicle(target, {"no_gps": no_gps}, {"no_gps": {"SIM_GPS1_ENABLE": 0}},
                                          streams_hz=None))
    return traces

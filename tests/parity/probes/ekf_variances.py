"""EKF_STATUS_REPORT's variances: the numbers a ground station turns into its EKF indicator
(QGroundControl's EKF page, MAVProxy's red "EKF"), and that a user's script watches to call a
GPS bad before the failsafe does.

EKF3 reports the square roots of its innovation test ratios: 1 is the gate, FS_EKF_THRESH (0.8)
the failsafe's line. Each window collects the report as it streams (10 Hz) and keeps, per field,
its median and its highest value:

quiet   on the ground (settled past the EKF's start), then hovering 10 m up in GUIDED;
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
JAMMED_TIME = Tol(abs=3.0, why="chance: the first jammed fix far enough off to pass the line")


def _collect(c: Client, sim_s: float) -> list:
    reports: list = []

    def take(msg) -> None:
        if msg.get_type() == "EKF_STATUS_REPORT":
            reports.append((c.now_ms, msg))
    with c.listening(take):
        c.idle(sim_s)
    return reports


def _window(trace: Trace, name: str, reports: list) -> None:
    for field in FIELDS:
        values = [getattr(m, field) for _, m in reports]
        tol = QUIET_POSITION if field == "pos_horiz_variance" else QUIET
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


def jammed(c: Client, trace: Trace) -> None:
    _settled(c)
    reach_flying(c, HOVER_M)
    c.idle(3.0)
    start_ms = c.now_ms
    c.set_param("SIM_GPS1_JAM", 1)
    reports = _collect(c, JAM_WINDOW_S)
    trace.fact("jammed.velocity_variance.passes_gate", any(m.velocity_variance > 1.0 for _, m in reports))
    for field in ("pos_vert_variance", "compass_variance"):  # what the jamming leaves alone
        trace.fact(f"jammed.{field}.max", round(max(getattr(m, field) for _, m in reports), 2) if reports else None,
                   QUIET)
    over = next((t for t, m in reports if m.velocity_variance >= THRESH), None)
    trace.fact("jammed.velocity_over_thresh_s", round((over - start_ms) / 1000.0, 1) if over is not None else None,
               JAMMED_TIME)


PROBES = {"quiet": quiet, "jammed": jammed}
PROBES_PARAMS = {"quiet": None, "jammed": None}


def run(target) -> dict[str, Trace]:
    return each_on_a_fresh_vehicle(target, PROBES, PROBES_PARAMS)

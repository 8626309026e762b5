"""The WIND message as the autopilot fills it, with a steady wind blowing (issue 30: a companion
that reads WIND must get what ArduCopter sends, not the simulator's truth).

ArduCopter estimates the wind only when its EKF fuses the rotors' drag (EK3_DRAG_BCOEF_X/Y above
zero, with EK3_DRAG_MCOEF: ArduPilot's own copter-wind-estimates.parm values below); without, it
sends zero. Probes, each a fresh vehicle with SIM_WIND_SPD 5 from SIM_WIND_DIR 90 (the east):
- no_drag: the defaults; hovering at 10 m, then flying 60 m north at 5 m/s, then hovering;
- drag: the same flight with drag fusion on;
- drag_calm: drag fusion on and no wind: what the estimate reads in calm air.
WIND is read as where the wind blows from, north and east parts [m/s], and its vertical speed.
"""
from __future__ import annotations

import math

from ..client import Client, mav
from ..facts import Tol, Trace
from .flight import EARTH_M_PER_DEG, ne
from .states import GUIDED, reach_armed_on_ground

AREA = "wind"
WIND = {"SIM_WIND_SPD": 5.0, "SIM_WIND_DIR": 90.0}
DRAG = {"EK3_DRAG_BCOEF_X": 9.5, "EK3_DRAG_BCOEF_Y": 9.5, "EK3_DRAG_MCOEF": 0.082}
PROBES = {"no_drag": WIND, "drag": WIND | DRAG, "drag_calm": DRAG}
HOVER_ALT_M = 10.0
LEG_M, LEG_SPEED_M_S = 60.0, 5.0
WIND_INTERVAL_US = 250_000
READ_AT_S = (5.0, 20.0, 40.0)  # hovering, seconds after reaching the height

TOL_WIND = Tol(abs=1.0, why="an estimate converging from two different airframes' drag; 1 m/s of a 5 m/s wind")
TOL_ZERO = Tol(abs=0.05, why="none estimated: zero on both")


def wind_parts(client: Client) -> tuple[float, float, float]:
    """(from north, from east, up) [m/s] of the last WIND."""
    w = client.last["WIND"]
    rad = math.radians(w.direction)
    return w.speed * math.cos(rad), w.speed * math.sin(rad), w.speed_z


def read(client: Client, trace: Trace, name: str, tol: Tol) -> None:
    client.fresh("WIND")
    n, e, up = wind_parts(client)
    trace.fact(f"{name}.from_north_m_s", round(n, 2), tol)
    trace.fact(f"{name}.from_east_m_s", round(e, 2), tol)
    trace.fact(f"{name}.up_m_s", round(up, 2), tol)


def fly(client: Client, trace: Trace, tol: Tol) -> None:
    client.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_WIND, WIND_INTERVAL_US)
    client.conn.mav.command_long_send(1, 1, mav.MAV_CMD_REQUEST_MESSAGE, 0, 242, 0, 0, 0, 0, 0, 0)
    client.wait(lambda: "HOME_POSITION" in client.last and "WIND" in client.last, 10, what="HOME_POSITION and WIND")
    read(client, trace, "on_ground", tol)
    reach_armed_on_ground(client, GUIDED)
    trace.fact("takeoff", client.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, HOVER_ALT_M))
    client.wait(lambda: client.rel_alt_m() > HOVER_ALT_M - 0.3, 60, what="the hover height")
    waited = 0.0
    for at in READ_AT_S:
        client.idle(at - waited)
        waited = at
        read(client, trace, f"hover_{at:.0f}s", tol)
    client.command(mav.MAV_CMD_DO_CHANGE_SPEED, 1, LEG_SPEED_M_S, -1, 0)
    home = client.last["HOME_POSITION"]
    lat = home.latitude + int(LEG_M / EARTH_M_PER_DEG * 1e7)
    client.conn.mav.set_position_target_global_int_send(
        0, 1, 1, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, 0b110111111000, lat, home.longitude, HOVER_ALT_M,
        0, 0, 0, 0, 0, 0, 0, 0)
    client.wait(lambda: ne(client)[0] > LEG_M / 2, 60, what="half the leg")
    read(client, trace, "mid_leg", tol)
    client.wait(lambda: abs(ne(client)[0] - LEG_M) < 1.0, 60, what="the leg's end")
    client.idle(10.0)
    read(client, trace, "after_leg_10s", tol)


def run(target) -> dict[str, Trace]:
    traces: dict[str, Trace] = {}
    try:
        for probe, params in PROBES.items():
            client = target.boot(params=params)
            fly(client, traces.setdefault(probe, Trace()), TOL_ZERO if probe == "no_drag" else TOL_WIND)
    finally:
        target.close()
    return traces

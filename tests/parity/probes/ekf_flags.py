"""EKF_STATUS_REPORT's flags with and without a rangefinder (issue 31): which bits ArduCopter's
EKF3 sets, EKF_POS_VERT_AGL (0x40, a terrain height estimate) above all.

plain        no rangefinder: on the ground (settled) and hovering at 5 m.
rangefinder  RNGFND1_TYPE 100 (SITL's beam, RNGFND1_MAX 7 m) at power-on: on the ground, hovering at
             4 m (in range), then at 10 m (out of range) at once and 8 s later.
"""
from __future__ import annotations

from ..client import Client, mav
from ..facts import Trace
from .booting import each_on_a_fresh_vehicle
from .nav_flight import goto
from .states import GUIDED, reach_armed_on_ground

AREA = "ekf_flags"
PROBES_PARAMS = {"plain": None, "rangefinder": {"RNGFND1_TYPE": 100, "RNGFND1_MAX": 7}}


def _flags(c: Client) -> str:
    c.fresh("EKF_STATUS_REPORT")
    return hex(c.last["EKF_STATUS_REPORT"].flags)


def _ready(c: Client) -> None:
    c.wait(lambda: "HOME_POSITION" in c.last and c.last["GPS_RAW_INT"].fix_type >= 3, 120, what="a fix")
    c.idle(20.0)  # past the EKF's settling


def _climb_to(c: Client, height_m: float) -> None:
    c.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, height_m)
    c.wait(lambda: c.rel_alt_m() > height_m - 0.3, 60, what=f"{height_m:g} m")
    c.idle(3.0)


def _ground_then_hover(c: Client, trace: Trace, height_m: float) -> None:
    _ready(c)
    trace.fact("ground", _flags(c))
    reach_armed_on_ground(c, GUIDED)
    _climb_to(c, height_m)
    trace.fact(f"hover_{height_m:g}m", _flags(c))


def plain(c: Client, trace: Trace) -> None:
    _ground_then_hover(c, trace, 5.0)


def rangefinder(c: Client, trace: Trace) -> None:
    _ground_then_hover(c, trace, 4.0)
    goto(c, 0.0, 0.0, 10.0)
    trace.fact("hover_10m.at_once", _flags(c))
    c.idle(8.0)
    trace.fact("hover_10m.after_8s", _flags(c))


PROBES = {"plain": plain, "rangefinder": rangefinder}


def run(target) -> dict[str, Trace]:
    return each_on_a_fresh_vehicle(target, PROBES, PROBES_PARAMS)

"""Flight profiles, reduced to figures a client would notice: the takeoff climb, a GUIDED goto,
the LAND descent above and below LAND_ALT_LOW, and RTL's phases (climb to RTL_ALT, return, loiter
over home for RTL_LOIT_TIME, descent)."""
from __future__ import annotations

import math

from ..client import Client, mav
from ..facts import Tol, Trace
from .states import GUIDED, LAND, RTL, reach_armed_on_ground

AREA = "flight"
EARTH_M_PER_DEG = 111_195.0
# Speeds and times come from two different controllers flying two different airframe models:
# within 15 % (and 0.3 m/s) a user's timeouts and speed checks pass on both.
RATE = Tol(abs=0.3, rel=0.15, why="different airframe and controller tuning; 15 % keeps user timeouts valid")
TIME = Tol(abs=1.0, rel=0.15, why="different airframe and controller tuning")
ALT = Tol(abs=0.5, why="altitude held within half a metre")


def ne(client: Client) -> tuple[float, float]:
    p, h = client.last["GLOBAL_POSITION_INT"], client.last["HOME_POSITION"]
    dn = (p.lat - h.latitude) * 1e-7 * EARTH_M_PER_DEG
    de = (p.lon - h.longitude) * 1e-7 * EARTH_M_PER_DEG * math.cos(math.radians(h.latitude * 1e-7))
    return dn, de


def time_between(client: Client, cond_a, cond_b, sim_s: float) -> float:
    client.wait(cond_a, sim_s, what="start of the phase")
    return client.wait(cond_b, sim_s, what="end of the phase")


def run(target) -> dict[str, Trace]:
    traces = {}
    client = target.boot()
    try:
        client.conn.mav.command_long_send(1, 1, mav.MAV_CMD_REQUEST_MESSAGE, 0, 242, 0, 0, 0, 0, 0, 0)
        client.wait(lambda: "HOME_POSITION" in client.last, 10, what="HOME_POSITION")
        t = traces["takeoff_20m"] = Trace()
        reach_armed_on_ground(client, GUIDED)
        t.fact("result", client.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 20))
        climb = time_between(client, lambda: client.rel_alt_m() > 2, lambda: client.rel_alt_m() > 18, 60)
        t.fact("climb_rate_2_to_18m", 16.0 / climb, RATE)
        client.wait(lambda: abs(client.rel_alt_m() - 20) < 0.3, 30, what="20 m")
        client.idle(3.0)
        t.fact("alt_held", client.rel_alt_m(), ALT)

        t = traces["guided_goto_north_60m"] = Trace()
        lat = client.last["HOME_POSITION"].latitude + int(60 / EARTH_M_PER_DEG * 1e7)
        lon = client.last["HOME_POSITION"].longitude
        client.conn.mav.set_position_target_global_int_send(
            0, 1, 1, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, 0b110111111000, lat, lon, 20, 0, 0, 0, 0, 0, 0, 0, 0)
        top = [0.0]

        def arrived():
            v = client.last["GLOBAL_POSITION_INT"]
            top[0] = max(top[0], math.hypot(v.vx, v.vy) / 100.0)
            return abs(ne(client)[0] - 60) < 1.0
        took = client.wait(arrived, 60, what="arrival 60 m north")
        t.fact("time_to_1m", took, TIME)
        t.fact("top_speed", top[0], RATE)
        client.idle(3.0)
        t.fact("overshoot_m", max(0.0, ne(client)[0] - 60), Tol(abs=1.0, why="stops within a metre on both"))

        t = traces["rtl_from_60m_north"] = Trace()
        t.fact("result", client.set_mode(RTL))
        home_reached = client.wait(lambda: math.hypot(*ne(client)) < 2.0, 90, what="back over home")
        t.fact("return_time", home_reached, TIME)
        descent_start = client.wait(lambda: client.rel_alt_m() < 19.0, 60, what="final descent")
        t.fact("loiter_over_home", descent_start, Tol(abs=1.5, why="RTL_LOIT_TIME 5 s plus stopping"))
        client.wait(lambda: client.rel_alt_m() < 15, 60, what="below 15 m")
        rate = time_between(client, lambda: client.rel_alt_m() < 15, lambda: client.rel_alt_m() < 11, 60)
        t.fact("descent_rate_above_land_alt_low", 4.0 / rate, RATE)
        rate = time_between(client, lambda: client.rel_alt_m() < 8, lambda: client.rel_alt_m() < 4, 60)
        t.fact("descent_rate_below_land_alt_low", 4.0 / rate, RATE)
        client.wait(lambda: not client.armed, 60, what="disarm after landing")
        t.fact("landed_mode", client.mode)
        t.fact("landed_within_m_of_home", math.hypot(*ne(client)) < 1.0)

        t = traces["land_from_20m"] = Trace()
        reach_armed_on_ground(client, GUIDED)
        client.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 20)
        client.wait(lambda: client.rel_alt_m() > 19.5, 60, what="20 m")
        client.idle(2.0)
        t.fact("result", client.set_mode(LAND))
        rate = time_between(client, lambda: client.rel_alt_m() < 18, lambda: client.rel_alt_m() < 12, 60)
        t.fact("descent_rate_high", 6.0 / rate, RATE)
        rate = time_between(client, lambda: client.rel_alt_m() < 6, lambda: client.rel_alt_m() < 2, 60)
        t.fact("descent_rate_low", 4.0 / rate, RATE)
        touchdown = [None]

        def disarmed():
            if touchdown[0] is None and client.rel_alt_m() < 0.2:
                touchdown[0] = client.now_ms
            return not client.armed
        client.wait(disarmed, 60, what="disarm after LAND")
        t.fact("disarm_after_touchdown_s", (client.now_ms - (touchdown[0] or client.now_ms)) / 1000.0,
               Tol(abs=1.5, why="touchdown is judged from a 0.2 m altitude; the reference itself gave "
                                  "2.4 s and 3.4 s in two recordings"))
    finally:
        target.close()
    return traces

"""RTL's return as a waypoint leg: take off to 10 m in GUIDED, go 40 m north, switch to RTL
(RTL_ALT 15 m: a 5 m climb blended into the return leg) and reduce the flight home to a few
figures. Flies the reference ArduCopter SITL or Firefly alike:

    python -m tests.parity.rtl_return --url udpin:127.0.0.1:14903
"""
from __future__ import annotations

import argparse
import json
import math
import time

from tests.parity.square import GUIDED, Link, arm_in_guided, mav, ne_to_latlon, record_positions, wait_home

RTL = 6
OUT_M = 40.0
RTL_ALT_M = 15.0  # ArduCopter's default RTL_ALT
FRAME_RELATIVE_ALT_INT = 6
POSITION_ONLY = 0b110111111000


def fly(url: str, timeout: float = 300.0) -> dict:
    """Figures: climb time to 14.5 m, how far it had moved home by then, times to within 2 m and
    0.3 m of home, highest altitude, overshoot past home and largest sideways offset."""
    link = Link(url)
    deadline = time.monotonic() + timeout
    hp = wait_home(link, deadline)
    home = (hp.latitude * 1e-7, hp.longitude * 1e-7)
    samples: list = []
    record_positions(link, home, samples)
    arm_in_guided(link, deadline)
    link.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 10.0)
    if link.recv("GLOBAL_POSITION_INT", 60, lambda m: m.relative_alt > 9700) is None:
        raise RuntimeError("no takeoff")
    lat, lon = ne_to_latlon(home, OUT_M, 0.0)
    link.mav.set_position_target_global_int_send(0, link.sys, link.comp, FRAME_RELATIVE_ALT_INT,
                                                 POSITION_ONLY, lat, lon, 10.0, 0, 0, 0, 0, 0, 0, 0, 0)

    def settled_at(n: float, e: float):
        return lambda m: (samples and math.hypot(samples[-1][1] - n, samples[-1][2] - e) < 0.3
                          and math.hypot(m.vx, m.vy) < 10)

    if link.recv("GLOBAL_POSITION_INT", 60, settled_at(OUT_M, 0.0)) is None:
        raise RuntimeError("did not get there")
    t_rtl = samples[-1][0]
    if link.command(mav.MAV_CMD_DO_SET_MODE, 1, RTL) != 0:
        raise RuntimeError("RTL refused")
    if link.recv("GLOBAL_POSITION_INT", 120, settled_at(0.0, 0.0)) is None:
        raise RuntimeError("did not come home")
    ret = [s for s in samples if s[0] >= t_rtl]
    climbed = next(s for s in ret if s[3] >= RTL_ALT_M - 0.5)
    t_home = next(s[0] for s in ret if math.hypot(s[1], s[2]) < 2.0)
    t_stop = next(s[0] for s in ret if math.hypot(s[1], s[2]) < 0.3)
    figures = {"climb_time_s": round(climbed[0] - t_rtl, 2),
               "moved_home_when_climbed_m": round(OUT_M - climbed[1], 2),
               "time_to_2m_of_home_s": round(t_home - t_rtl, 2), "time_to_0.3m_s": round(t_stop - t_rtl, 2),
               "max_alt_m": round(max(s[3] for s in ret), 2),
               "overshoot_past_home_m": round(-min(s[1] for s in ret), 2),
               "max_sideways_m": round(max(abs(s[2]) for s in ret), 2)}
    link.command(mav.MAV_CMD_DO_SET_MODE, 1, GUIDED)
    link.conn.close()
    return figures


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--url", required=True)
    print(json.dumps(fly(ap.parse_args().url), indent=1))


if __name__ == "__main__":
    main()

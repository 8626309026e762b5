"""SITL's ADS-B receiver: what ArduPilot SITL's simulated transceiver (on SERIAL1) reports of the
simulated traffic (sim/traffic.py), as the autopilot hears it.

It is there when SIM_ADSB_COUNT is 0 or more at boot (ArduPilot attaches it when it opens
SERIAL1, so a count set later needs a reboot), or the scenario flies aircraft of its own
([[traffic]]), and reports while SIM_ADSB_TYPES has bit 0. From 10 s after
boot, once a second, it sends one ADSB_VEHICLE per aircraft flying: its position off the sim's
origin, its altitude above the origin as an altitude above sea level (SITL's own reading), heading
and speeds from its velocity, tslc 1, every flag of a good report, squawk 1200, from component
156. With ADSB_TYPE set the autopilot lists them; without, it forwards them to the ground
stations as they are (measured: from system 1, component 156).
"""
from __future__ import annotations

import math

from firefly.sim.traffic import Aircraft

from ..location import Loc
from .traffic_list import AdsbReport

START_S = 10.0  # nothing before the autopilot has run this long
PERIOD_S = 1.0
FLAGS = 0x1FF  # COORDS, ALTITUDE, HEADING, VELOCITY, CALLSIGN, SQUAWK, SIMULATED, VERTICAL_VELOCITY, BARO
ALTITUDE_TYPE_QNH = 0
SQUAWK = 1200


def _c_int(value: float, low: int, high: int) -> int:
    """A float stored into a C integer field: truncated, held in range."""
    return int(max(low, min(high, value)))


def report_of(a: Aircraft, origin: Loc) -> AdsbReport:
    where = origin.offset(a.n_m, a.e_m)
    heading = math.degrees(math.atan2(a.ve_m_s, a.vn_m_s)) * 100.0 % 36000.0
    altitude_m = a.up_m + (origin.alt_cm * 0.01 if a.scripted else 0.0)  # SITL's own report their height
    return AdsbReport(a.icao, where.lat_e7, where.lon_e7, ALTITUDE_TYPE_QNH, _c_int(altitude_m * 1000, -2**31, 2**31 - 1),
                      _c_int(heading, 0, 65535), _c_int(math.hypot(a.vn_m_s, a.ve_m_s) * 100, 0, 65535),
                      _c_int(-a.vd_m_s * 100, -32768, 32767), a.callsign.encode(), a.emitter_type, 1, FLAGS, SQUAWK)


class SitlTransceiver:
    def __init__(self, attached: bool):
        self.attached = attached
        self._next_s = START_S

    def due(self, now_s: float) -> bool:
        """Whether a burst of reports goes out now (at most once a second, from START_S)."""
        if not self.attached or now_s + 1e-9 < self._next_s:
            return False
        self._next_s = now_s + PERIOD_S
        return True

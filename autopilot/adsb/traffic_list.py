"""The ADS-B receiver's list of aircraft, as ArduPilot's AP_ADSB keeps it (measured on ArduCopter
SITL, parity area adsb).

ADSB_TYPE switches it on (any type: each takes ADSB_VEHICLE over MAVLink, as the uAvionix one does,
and SITL's traffic comes that way); it starts the first time it is looked at with a type set, so
no reboot is needed. A report is kept by its ICAO address unless it is refused, and a refused
report of a kept aircraft drops it:
- at 0 latitude, longitude and altitude, or an ICAO past 24 bits, or with neither the coordinates
  nor the altitude flagged valid;
- farther than ADSB_LIST_RADIUS or, with ADSB_LIST_ALT, more than that above or below (while the
  vehicle knows where it is; ADSB_ICAO_SPECL's aircraft is never filtered out);
- older than 5 s (its tslc, time since last contact, says how old it came).
A full list (ADSB_LIST_MAX, read when it starts) takes a newcomer in place of the farthest
aircraft only when it is nearer. An aircraft not heard of for 5 s is dropped, checked at 10 Hz.

The list goes back out in the ADSB stream (MAVn_ADSB), one aircraft per message as received,
round-robin; a new pass over the list starts no sooner than 1 s after the last one started (the
first pass after boot counts from 0, so the second follows it at once, as measured).
"""
from __future__ import annotations

from typing import NamedTuple

from ..location import ZERO, Loc

TIMEOUT_MS = 5000  # AP_ADSB's VEHICLE_TIMEOUT_MS
PASS_MS = 1000  # a new pass of the ADSB stream no sooner than this after the last began
ICAO_MAX = 0xFFFFFF
FLAG_COORDS, FLAG_ALTITUDE, FLAG_HEADING, FLAG_VELOCITY = 1, 2, 4, 8  # ADSB_FLAGS_VALID_*
POSITION_FLAGS = FLAG_COORDS | FLAG_ALTITUDE
AVOIDANCE_FLAGS = FLAG_COORDS | FLAG_ALTITUDE | FLAG_HEADING | FLAG_VELOCITY
SAMPLES_MAX = 30  # AP_ADSB's queue for avoidance: a report finding it full is not queued


class AdsbReport(NamedTuple):
    """One ADSB_VEHICLE's fields, kept as received and sent back unchanged."""
    icao: int
    lat_e7: int
    lon_e7: int
    altitude_type: int
    altitude_mm: int  # taken as above mean sea level, whatever altitude_type says (as ArduPilot)
    heading_cdeg: int
    hor_velocity_cms: int
    ver_velocity_cms: int  # up is positive
    callsign: bytes
    emitter_type: int
    tslc: int  # seconds since last contact, as the sender counted them
    flags: int
    squawk: int

    @property
    def location(self) -> Loc:
        return Loc(self.lat_e7, self.lon_e7, int(self.altitude_mm * 0.1))


class Tracked(NamedTuple):
    report: AdsbReport
    heard_ms: int  # vehicle time of the last contact: when it came, less its tslc


class TrafficList:
    def __init__(self, params):
        self._params = params
        self.started = False
        self.capacity = 0
        self.aircraft: list[Tracked] = []
        self.samples: list[Tracked] = []  # reports for avoidance (threats.py) since it last took them
        self.own = ZERO  # where the vehicle is, as of the last update (zero: not known)
        self._furthest: tuple[int, float] = (0, 0.0)  # (index, distance) of the farthest; 0 m: not known
        self._send_index = 0
        self._send_start_ms = 0

    @property
    def enabled(self) -> bool:
        return self._params["ADSB_TYPE"] != 0

    def available(self) -> bool:
        """AP_ADSB's healthy(): a type is set and the list has started (it starts now if it can)."""
        return self._start()

    def _start(self) -> bool:
        """AP_ADSB's check_startup: off until a type is set; the list is made the first time."""
        if not self.started:
            if not self.enabled:
                return False
            self.started = True
            self.capacity = int(min(max(self._params["ADSB_LIST_MAX"], 1), 32767))
        return self.started

    def update(self, now_ms: int, own: Loc) -> None:
        """The 10 Hz update: where the vehicle is, and aircraft not heard of for 5 s dropped."""
        if not self._start():
            return
        self.own = own
        i = 0
        while i < len(self.aircraft):
            if now_ms - self.aircraft[i].heard_ms > TIMEOUT_MS:
                self._delete(i)
            else:
                i += 1

    def _delete(self, i: int) -> None:
        if i == self._furthest[0] and self._furthest[1] > 0:
            self._furthest = (0, 0.0)
        last = self.aircraft.pop()
        if i < len(self.aircraft):
            self.aircraft[i] = last

    def _special(self, icao: int) -> bool:
        special = int(self._params["ADSB_ICAO_SPECL"])
        return special != 0 and icao == special

    def receive(self, report: AdsbReport, now_ms: int) -> None:
        """An ADSB_VEHICLE from any link."""
        if not self._start():
            return
        tracked = Tracked(report, now_ms - report.tslc * 1000)
        where = report.location
        own = self.own
        known = not own.is_zero()
        distance = own.distance_to(where)
        special = self._special(report.icao)
        radius, alt_band = self._params["ADSB_LIST_RADIUS"], self._params["ADSB_LIST_ALT"]
        index = next((i for i, a in enumerate(self.aircraft) if a.report.icao == report.icao), None)
        if (where.is_zero()
                or (radius > 0 and known and distance > radius and not special)
                or (alt_band > 0 and known and abs(where.alt_cm - own.alt_cm) > alt_band * 100 and not special)
                or report.icao > ICAO_MAX
                or not report.flags & POSITION_FLAGS
                or now_ms - tracked.heard_ms > TIMEOUT_MS):
            if index is not None:
                self._delete(index)
            return
        if index is not None:
            self.aircraft[index] = tracked
        elif len(self.aircraft) < self.capacity:
            self.aircraft.append(tracked)
        elif not known:
            self._furthest = (0, 0.0)
        else:
            if self._furthest[1] <= 0:
                self._find_furthest()
            far_index, far_distance = self._furthest
            if distance < far_distance:
                self.aircraft[far_index] = tracked
                self._furthest = (0, 0.0)
        if report.flags & AVOIDANCE_FLAGS and len(self.samples) < SAMPLES_MAX:
            self.samples.append(tracked)

    def _find_furthest(self) -> None:
        best = (0, 0.0)
        for i, a in enumerate(self.aircraft):
            if self._special(a.report.icao):
                continue
            d = self.own.distance_to(a.report.location)
            if best[1] < d or i == 0:
                best = (i, d)
        self._furthest = best

    def take_samples(self) -> list[Tracked]:
        samples, self.samples = self.samples, []
        return samples

    def next_to_send(self, now_ms: int) -> AdsbReport | None:
        """The ADSB stream's next message (AP_ADSB::send_adsb_vehicle), or None."""
        if not self._start() or not self.aircraft:
            return None
        if self._send_index >= len(self.aircraft):
            if now_ms - self._send_start_ms < PASS_MS:
                return None
            self._send_start_ms, self._send_index = now_ms, 0
        report = self.aircraft[self._send_index].report
        self._send_index += 1
        return report

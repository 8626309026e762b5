"""ADS-B's messages (adsb/): the ADSB_VEHICLE a ground station, a companion or SITL's traffic sends
in, the list going back out in the ADSB stream (one aircraft per message, as received), and
COLLISION, which every link gets when avoidance reports a threat."""
from __future__ import annotations

from ..adsb.threats import Collision
from ..adsb.traffic_list import AdsbReport
from ..views import TelemetryView
from .encoding import time_boot_ms
from .dialect import mavlink as mav


def report_of(msg) -> AdsbReport:
    callsign = msg.callsign if isinstance(msg.callsign, bytes) else msg.callsign.encode("latin-1", "replace")
    return AdsbReport(msg.ICAO_address, msg.lat, msg.lon, msg.altitude_type, msg.altitude, msg.heading,
                      msg.hor_velocity, msg.ver_velocity, callsign, msg.emitter_type, msg.tslc, msg.flags,
                      msg.squawk)


def adsb_vehicle(v: TelemetryView, codec):
    r = v.adsb_next_to_send(time_boot_ms(v))
    if r is None:
        return None
    return codec.adsb_vehicle_encode(r.icao, r.lat_e7, r.lon_e7, r.altitude_type, r.altitude_mm, r.heading_cdeg,
                                     r.hor_velocity_cms, r.ver_velocity_cms, r.callsign, r.emitter_type, r.tslc,
                                     r.flags, r.squawk)


def collision(codec, c: Collision):
    return codec.collision_encode(c.src, c.src_id, c.action, c.threat_level, c.time_to_minimum_delta,
                                  c.altitude_minimum_delta, c.horizontal_minimum_delta)


BUILDERS = {mav.MAVLINK_MSG_ID_ADSB_VEHICLE: adsb_vehicle}

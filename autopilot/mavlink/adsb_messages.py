"""ADS-B's messages (adsb/): the ADSB_VEHICLE a ground station, a companion or SITL's traffic sends
in, the list going back out in the ADSB stream (one aircraft per message, as received), and
COLLISION, which every link gets when avoidance reports a threat."""
from __future__ import annotations

from ..adsb.threats import Collision
from ..adsb.traffic_list import AdsbReport
from ..views import TelemetryView
from .component_frames import FromComponent
from .encoding import time_boot_ms
from .dialect import mavlink as mav


def report_of(msg) -> AdsbReport:
    callsign = msg.callsign if isinstance(msg.callsign, bytes) else msg.callsign.encode("latin-1", "replace")
    return AdsbReport(msg.ICAO_address, msg.lat, msg.lon, msg.altitude_type, msg.altitude, msg.heading,
                      msg.hor_velocity, msg.ver_velocity, callsign, msg.emitter_type, msg.tslc, msg.flags,
                      msg.squawk)


def adsb_vehicle(v: TelemetryView, codec):
    r = v.adsb_next_to_send(time_boot_ms(v))
    return None if r is None else _encode(codec, r)


class FromTransceiver(FromComponent):
    """An ADSB_VEHICLE of SITL's transceiver forwarded as it came: from the vehicle's system, the
    ADS-B component (156), in a numbering of its own."""
    COMPONENT = 156  # MAV_COMP_ID_ADSB


def forwarded(codec, reports: list[AdsbReport], first_seq: int) -> list[FromTransceiver]:
    return [FromTransceiver(_encode(codec, r), (first_seq + i) & 0xFF) for i, r in enumerate(reports)]


def _encode(codec, r: AdsbReport):
    return codec.adsb_vehicle_encode(r.icao, r.lat_e7, r.lon_e7, r.altitude_type, r.altitude_mm, r.heading_cdeg,
                                     r.hor_velocity_cms, r.ver_velocity_cms, r.callsign, r.emitter_type, r.tslc,
                                     r.flags, r.squawk)


def collision(codec, c: Collision):
    return codec.collision_encode(c.src, c.src_id, c.action, c.threat_level, c.time_to_minimum_delta,
                                  c.altitude_minimum_delta, c.horizontal_minimum_delta)


BUILDERS = {mav.MAVLINK_MSG_ID_ADSB_VEHICLE: adsb_vehicle}

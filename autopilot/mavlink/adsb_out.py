"""A uAvionix ADS-B transponder's messages to the autopilot (UAVIONIX_ADSB_OUT_CFG, its health
report), kept and announced as ArduCopter's AP_ADSB does: the configuration a ground station set
("ADSB: Using ICAO_id ... and Callsign ..."), and the MAVLink channel the transceiver was found on
(said once per change of channel). The session numbers channels in the order transceivers first
report on them: with one link, 0, as ArduPilot's SERIAL0 is channel 0."""
from __future__ import annotations

from ..results import Severity


class AdsbOut:
    def __init__(self) -> None:
        self.icao_id: int | None = None
        self.callsign = ""
        self.channel: int | None = None  # where the transceiver reports from
        self.rf_health = 0

    def on_config(self, msg) -> tuple[int, str]:
        self.icao_id = msg.ICAO
        raw = msg.callsign if isinstance(msg.callsign, bytes) else msg.callsign.encode("latin-1", "replace")
        self.callsign = raw.split(b"\0", 1)[0].decode("latin-1")
        as_int = self.icao_id - (1 << 32) if self.icao_id >= 1 << 31 else self.icao_id  # printed with %d
        return Severity.INFO, f"ADSB: Using ICAO_id {as_int} and Callsign {self.callsign}"

    def on_health(self, msg, channel: int) -> tuple[int, str] | None:
        found = self.channel != channel
        self.channel, self.rf_health = channel, msg.rfHealth
        return (Severity.DEBUG, f"ADSB: Found transceiver on channel {channel}") if found else None

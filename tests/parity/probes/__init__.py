"""Probes by area. Each module has AREA and run(target) -> {probe name: Trace}."""
from . import commands, flight, ftp, mavsdk_client, missions, modes, params, refusals, startup, telemetry

AREAS = {m.AREA: m for m in (commands, modes, telemetry, flight, missions, mavsdk_client, params, ftp, startup,
                             refusals)}

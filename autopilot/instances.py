"""How a SITL instance number names its vehicle: instance N is MAVLink system N + 1, as ArduPilot
SITL users number their vehicles, and from 1 again past 254. MAVLink system ids end at 255 on one
network; a fleet larger than that runs in parts of 255 consecutive instances, each part a process
of its own (cli/fleet.py), so the vehicles that share a process never share an id."""
from __future__ import annotations

PART_SIZE = 255  # vehicles per process of a fleet: one MAVLink network's system ids


def system_id_of(instance: int) -> int:
    return instance % PART_SIZE + 1

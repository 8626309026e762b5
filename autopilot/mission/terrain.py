"""Whether the stored mission has items at heights above terrain (MAV_FRAME_GLOBAL_TERRAIN_ALT and
its _INT form), as AP_Mission::contains_terrain_alt_items asks: ArduCopter then needs its terrain
database filled (autopilot/terrain.py) before it arms, unless its waypoint navigator follows the
terrain by rangefinder (safety/arming.py).
"""
from __future__ import annotations

from .commands import STORED_IN_LOCATION
from .store import MISSION, MissionStore

TERRAIN_FRAMES = frozenset({10, 11})  # MAV_FRAME_GLOBAL_TERRAIN_ALT, MAV_FRAME_GLOBAL_TERRAIN_ALT_INT


class TerrainItems:
    """store -> whether its mission has a terrain-frame item with a location; worked out again
    only when the store changed (the pre-arm checks ask every second)."""
    __slots__ = ("_store", "_version", "_found")

    def __init__(self, store: MissionStore) -> None:
        self._store, self._version, self._found = store, -1, False

    def __call__(self) -> bool:
        if self._store.version != self._version:
            self._version = self._store.version
            self._found = any(item.frame in TERRAIN_FRAMES and item.command in STORED_IN_LOCATION
                              for item in self._store.items(MISSION))
        return self._found

"""The vehicle's terrain: what AP_Terrain makes of the grid (terrain_grid.py) for the rest of it.

update() runs AP_Terrain::update's wishes (home, here and around, the mission's waypoints) and
remembers the last height known under the vehicle and whether home's is known; report() is a
TERRAIN_REPORT's figures for a location; prearm_failure() is AP_Terrain::pre_arm_checks; request()
the block TERRAIN_REQUEST asks for. TERRAIN_ENABLE 0 turns all of it off; TERRAIN_OPTIONS bit 0
(DisableDownload) stops the asking only.
"""
from __future__ import annotations

from dataclasses import dataclass

from .location import Loc
from .terrain_grid import FULL_MASK, Block, TerrainGrid

NAV_WAYPOINT, NAV_SPLINE_WAYPOINT = 16, 82  # the mission items whose terrain is fetched ahead
DISABLE_DOWNLOAD = 1  # TERRAIN_OPTIONS bit 0
# AC_WPNav's terrain sources (Vehicle.terrain_source; None: unavailable)
FROM_RANGEFINDER, FROM_DATABASE = "rangefinder", "database"


@dataclass(frozen=True)
class TerrainReport:
    spacing: int  # 0: no height at the location
    terrain_height_m: float  # AMSL
    current_height_m: float  # the vehicle above the terrain under it
    pending: int
    loaded: int


class VehicleTerrain:
    def __init__(self) -> None:
        self.grid = TerrainGrid()
        self.last_current_height_m: float | None = None  # under the vehicle, the last time known
        self.home_height_known = False
        self._mission_version = -1
        self._waypoints: list[Loc] = []

    def spacing(self, params) -> int:
        return int(params["TERRAIN_SPACING"])

    def enabled(self, params) -> bool:
        return bool(params["TERRAIN_ENABLE"])

    def _fit_cache(self, params) -> None:
        self.grid.cache_size = max(int(params["TERRAIN_CACHE_SZ"]), 1)
        self.grid.margin_e7 = int(float(params["TERRAIN_MARGIN"]) * 100)

    def update(self, params, here: Loc | None, home: Loc | None, store) -> None:
        """AP_Terrain::update: the blocks wanted now, and the heights it remembers."""
        if not self.enabled(params):
            return
        self._fit_cache(params)
        spacing = self.spacing(params)
        if store.version != self._mission_version:
            self._mission_version = store.version
            self._waypoints = [Loc(item.x, item.y, 0) for item in store.items(0)
                               if item.command in (NAV_WAYPOINT, NAV_SPLINE_WAYPOINT)
                               and (item.x or item.y)]
        self.grid.want_around(here, home, self._waypoints, spacing)
        if home is not None:
            self.home_height_known = self.grid.height_amsl(home.lat_e7, home.lon_e7, spacing) is not None
        if here is not None:
            height = self.grid.height_amsl(here.lat_e7, here.lon_e7, spacing)
            if height is not None:
                self.last_current_height_m = height

    def height_amsl(self, params, loc: Loc) -> float | None:
        if not self.enabled(params) or (loc.lat_e7 == 0 and loc.lon_e7 == 0):
            return None  # (nowhere: a report before the vehicle knows where it is wants no block)
        return self.grid.height_amsl(loc.lat_e7, loc.lon_e7, self.spacing(params))

    def report(self, params, loc: Loc, here: Loc | None, extrapolate: bool) -> TerrainReport:
        """AP_Terrain::send_terrain_report: the terrain at `loc`, the vehicle (at `here`) above the
        terrain under it; extrapolated from the last height known when asked (the periodic report)."""
        spacing = self.spacing(params)
        height = self.height_amsl(params, loc)
        shown_spacing = spacing if height is not None else 0
        if height is None:
            height = self.last_current_height_m if extrapolate and self.last_current_height_m is not None else 0.0
        current = 0.0
        if here is not None:
            under = self.height_amsl(params, here)
            if under is None and extrapolate:  # (0 before any height was known: AP_Terrain's start)
                under = self.last_current_height_m if self.last_current_height_m is not None else 0.0
            if under is not None:
                current = here.alt_cm * 0.01 - under
        pending, loaded = self.grid.statistics(spacing)
        return TerrainReport(shown_spacing, height, current, pending, loaded)

    def height_above_terrain(self, params, here: Loc) -> float | None:
        """The vehicle above the terrain under it [m] (extrapolating over a gap, as ArduCopter's
        navigation does), or None without any height known."""
        under = self.height_amsl(params, here)
        if under is None:
            under = self.last_current_height_m
        return None if under is None else here.alt_cm * 0.01 - under

    def prearm_failure(self, params) -> str | None:
        """AP_Terrain::pre_arm_checks: nothing pending, the vehicle's and home's heights known."""
        pending, _ = self.grid.statistics(self.spacing(params))
        if pending or self.last_current_height_m is None or not self.home_height_known:
            return "waiting for terrain data"
        if self.spacing(params) <= 0:
            return "TERRAIN_SPACING can't be <= 0"
        return None

    def request(self, params, here: Loc | None) -> Block | None:
        """The block a TERRAIN_REQUEST asks for now (its missing sub-grids: FULL_MASK & ~bitmap)."""
        if not self.enabled(params) or int(params["TERRAIN_OPTIONS"]) & DISABLE_DOWNLOAD:
            return None
        return self.grid.missing(here, self.spacing(params))

    def store(self, params, lat_e7: int, lon_e7: int, spacing: int, gridbit: int, data) -> bool:
        if not self.enabled(params):
            return False
        return self.grid.store(lat_e7, lon_e7, spacing, gridbit, data, self.spacing(params))


def missing_mask(block: Block) -> int:
    return FULL_MASK & ~block.bitmap

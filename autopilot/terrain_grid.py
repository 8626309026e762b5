"""The terrain database as AP_Terrain keeps it: grid blocks of heights a ground station sends.

A block is 28 x 32 points (north x east) at TERRAIN_SPACING metres, anchored on whole degrees and
24 x 28 spacings from the next (a one-point overlap, so a point's four neighbours are always in one
block). A ground station fills it in 4 x 4 sub-grids (TERRAIN_DATA's gridbit, 7 x 8 of them); the
block's bitmap says which have come. The vehicle keeps up to 12 blocks (TERRAIN_GRID_BLOCK_CACHE_SIZE),
the least recently used given up for a new one, and wants those around it: home's, its own, the 9
under points 0.7 of a block away, and 5 about each mission waypoint. Whatever is missing in them is
`pending`, what has come `loaded` (TERRAIN_REPORT). A height is the bilinear mean of the four grid
points around it, known only when all four have come.

Firefly has no disk: a block is empty when first wanted (ArduCopter SITL reads its terrain
directory first; with none there, the same).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

from .location import M_PER_E7, Loc, longitude_scale

BLOCK_SIZE_N, BLOCK_SIZE_E = 28, 32  # points per block
BLOCK_STEP_N, BLOCK_STEP_E = 24, 28  # spacings between block corners
SUBGRIDS_E = 8  # 4 x 4 sub-grids across a block's east side
SUBGRIDS = 56
FULL_MASK = (1 << SUBGRIDS) - 1
CACHE_SIZE = 12  # TERRAIN_GRID_BLOCK_CACHE_SIZE
SURROUND_SHARE = 0.7  # update_surrounding_tiles: points 0.7 of a block away
MISSION_POINT_SPACINGS = 10  # update_mission_data: 4 points 10 spacings from each waypoint, and itself
DEGREE_EAST_MAX_M, EARTH_RADIUS_M = 112_000.0, 6_371_000.0  # (_Around's bound on the east scale's drift)


def _whole_degree_e7(x_e7: int) -> int:
    """The whole degree at or below x (AP_Terrain rounds negatives away from zero)."""
    return math.floor(x_e7 / 10_000_000) * 10_000_000


@dataclass(frozen=True)
class GridInfo:
    block_lat_e7: int  # the block's south-west corner
    block_lon_e7: int
    idx_n: int  # the grid point at or south-west of the location, within the block
    idx_e: int
    frac_n: float  # how far on to the next point (0..1)
    frac_e: float


@lru_cache(maxsize=1024)  # home, waypoints and a vehicle on the ground ask about the same places
def grid_info(lat_e7: int, lon_e7: int, spacing_m: int) -> GridInfo:
    """Where a location falls in the grid (AP_Terrain::calculate_grid_info)."""
    ref = Loc(_whole_degree_e7(lat_e7), _whole_degree_e7(lon_e7), 0)
    north, east = ref.ne_to(Loc(lat_e7, lon_e7, 0))
    idx_n, idx_e = int(north / spacing_m), int(east / spacing_m)
    lat, lon = block_corner(ref.lat_e7, ref.lon_e7, idx_n // BLOCK_STEP_N, idx_e // BLOCK_STEP_E, spacing_m)
    return GridInfo(lat, lon, idx_n % BLOCK_STEP_N, idx_e % BLOCK_STEP_E,
                    (north - idx_n * spacing_m) / spacing_m, (east - idx_e * spacing_m) / spacing_m)


@lru_cache(maxsize=1024)
def block_corner(ref_lat_e7: int, ref_lon_e7: int, block_n: int, block_e: int, spacing_m: int) -> tuple[int, int]:
    """The south-west corner of the block_n'th, block_e'th block from a whole degree."""
    corner = Loc(ref_lat_e7, ref_lon_e7, 0).offset(block_n * BLOCK_STEP_N * float(spacing_m),
                                                   block_e * BLOCK_STEP_E * float(spacing_m))
    return corner.lat_e7, corner.lon_e7


def blocks_around(lat_e7: int, lon_e7: int, spacing_m: int) -> list[tuple[int, int]]:
    """The corners of the blocks under the 9 points 0.7 of a block about a location
    (update_surrounding_tiles)."""
    return _blocks_around(lat_e7, lon_e7, spacing_m)[0]


def _blocks_around(lat_e7: int, lon_e7: int, spacing_m: int) -> tuple[list[tuple[int, int]], float, float]:
    """blocks_around's corners, each point moved and measured as ArduPilot moves and measures it
    (Location::offset, get_distance_NE), inline; and how far north and east [m] the location may
    move before any point crosses into another block (0 when a point lies in the next degree's
    grid, whose edges are not worked out here)."""
    ref_lat, ref_lon = _whole_degree_e7(lat_e7), _whole_degree_e7(lon_e7)
    step_n, step_e = BLOCK_SIZE_N * SURROUND_SHARE * spacing_m, BLOCK_SIZE_E * SURROUND_SHARE * spacing_m
    edge_n, edge_e = BLOCK_STEP_N * spacing_m, BLOCK_STEP_E * spacing_m
    corners = []
    free_n = free_e = math.inf
    for dn in (-1, 0, 1):
        d_lat = int(dn * step_n / M_PER_E7)
        lat = lat_e7 + d_lat
        east_scale = M_PER_E7 * longitude_scale(lat_e7 + d_lat / 2)
        ne_scale = M_PER_E7 * longitude_scale((ref_lat + lat) * 0.5)
        for de in (-1, 0, 1):
            lon = lon_e7 + int(de * step_e / east_scale)
            if _whole_degree_e7(lat) != ref_lat or _whole_degree_e7(lon) != ref_lon:  # the next degree's grid
                info = grid_info(lat, lon, spacing_m)
                corners.append((info.block_lat_e7, info.block_lon_e7))
                free_n = free_e = 0.0
                continue
            north, east = (lat - ref_lat) * M_PER_E7, (lon - ref_lon) * ne_scale
            idx_n, idx_e = int(north / spacing_m), int(east / spacing_m)
            block_n, block_e = idx_n // BLOCK_STEP_N, idx_e // BLOCK_STEP_E
            corners.append(block_corner(ref_lat, ref_lon, block_n, block_e, spacing_m))
            free_n = min(free_n, north - block_n * edge_n, (block_n + 1) * edge_n - north)
            free_e = min(free_e, east - block_e * edge_e, (block_e + 1) * edge_e - east)
    return corners, free_n, free_e


class _Around:
    """The last blocks_around worked out, kept while the vehicle stays well inside what keeps every
    point in its block: a vehicle in flight asks 10 times a second, and crosses a block's edge
    seldom. Moving north also changes the longitude scale the points' east distances are measured
    with, by tan(lat) / R of their up to a degree's 112 km per metre moved: the way the vehicle may
    go (north plus east) is the smaller free distance, less a metre for rounding, over 1 + that."""
    __slots__ = ("lat_e7", "lon_e7", "spacing_m", "corners", "free_m")

    def __init__(self, lat_e7: int, lon_e7: int, spacing_m: int):
        self.lat_e7, self.lon_e7, self.spacing_m = lat_e7, lon_e7, spacing_m
        self.corners, free_n, free_e = _blocks_around(lat_e7, lon_e7, spacing_m)
        drift = abs(math.tan(math.radians(lat_e7 * 1e-7))) * DEGREE_EAST_MAX_M / EARTH_RADIUS_M + 0.01
        self.free_m = (min(free_n, free_e) - 1.0) / (1.0 + drift)

    def holds(self, lat_e7: int, lon_e7: int, spacing_m: int) -> bool:
        moved = (abs(lat_e7 - self.lat_e7) + abs(lon_e7 - self.lon_e7) * longitude_scale(lat_e7)) * M_PER_E7
        return spacing_m == self.spacing_m and moved < self.free_m


def subgrid_bit(idx_n: int, idx_e: int) -> int:
    """The bitmap bit of the 4 x 4 sub-grid holding point (idx_n, idx_e) (AP_Terrain::grid_bitnum)."""
    return idx_e // 4 + SUBGRIDS_E * (idx_n // 4)


@dataclass
class Block:
    lat_e7: int
    lon_e7: int
    spacing_m: int
    bitmap: int = 0
    heights: list[int] = field(default_factory=lambda: [0] * (BLOCK_SIZE_N * BLOCK_SIZE_E))
    used: int = 0  # when last wanted (the database's counter): the oldest is given up first

    def has(self, idx_n: int, idx_e: int) -> bool:
        return bool(self.bitmap >> subgrid_bit(idx_n, idx_e) & 1)

    def height(self, idx_n: int, idx_e: int) -> int:
        return self.heights[idx_n * BLOCK_SIZE_E + idx_e]


class TerrainGrid:
    """The blocks a vehicle holds; it is told TERRAIN_SPACING with each question (the parameter
    may change: blocks of another spacing then count for nothing, as AP_Terrain's)."""

    def __init__(self, margin_e7: int = 5) -> None:
        self.blocks: list[Block] = []
        self.margin_e7 = margin_e7  # TERRAIN_MARGIN's 0.05 m as lat/lon matches are judged (x100)
        self.cache_size = CACHE_SIZE  # TERRAIN_CACHE_SZ
        self._clock = 0
        self._around: _Around | None = None

    def _find(self, lat_e7: int, lon_e7: int, spacing_m: int) -> Block | None:
        m = self.margin_e7
        for block in self.blocks:
            if abs(block.lat_e7 - lat_e7) <= m and abs(block.lon_e7 - lon_e7) <= m and block.spacing_m == spacing_m:
                return block
        return None

    def want(self, info: GridInfo, spacing_m: int) -> Block:
        """The block holding `info`, made empty (giving up the least recently wanted) if not held."""
        return self.want_block(info.block_lat_e7, info.block_lon_e7, spacing_m)

    def want_block(self, lat_e7: int, lon_e7: int, spacing_m: int) -> Block:
        self._clock += 1
        block = self._find(lat_e7, lon_e7, spacing_m)
        if block is None:
            block = Block(lat_e7, lon_e7, spacing_m)
            while len(self.blocks) >= self.cache_size:  # (a loop: TERRAIN_CACHE_SZ may have shrunk)
                self.blocks.remove(min(self.blocks, key=lambda b: b.used))
            self.blocks.append(block)
        block.used = self._clock
        return block

    def height_amsl(self, lat_e7: int, lon_e7: int, spacing_m: int) -> float | None:
        """The terrain's height AMSL [m] at a location, or None while its grid points have not come.
        Asking makes the block wanted (AP_Terrain::height_amsl)."""
        if spacing_m <= 0:
            return None
        info = grid_info(lat_e7, lon_e7, spacing_m)
        block = self.want(info, spacing_m)
        n, e = info.idx_n, info.idx_e
        if not (block.has(n, e) and block.has(n, e + 1) and block.has(n + 1, e) and block.has(n + 1, e + 1)):
            return None
        west = (1.0 - info.frac_n) * block.height(n, e) + info.frac_n * block.height(n + 1, e)
        east = (1.0 - info.frac_n) * block.height(n, e + 1) + info.frac_n * block.height(n + 1, e + 1)
        return (1.0 - info.frac_e) * west + info.frac_e * east

    def want_around(self, here: Loc | None, home: Loc | None, waypoints: list[Loc], spacing_m: int) -> bool:
        """AP_Terrain::update's wishes: home's block, the vehicle's and the 9 around it, and 5 points
        about each mission waypoint. Returns whether the vehicle's own height is known."""
        if spacing_m <= 0:
            return False
        if home is not None:
            self.height_amsl(home.lat_e7, home.lon_e7, spacing_m)
        for wp in waypoints:
            for k in range(4):
                p = _offset_bearing(wp, 45.0 + 90.0 * k, spacing_m * MISSION_POINT_SPACINGS)
                self.height_amsl(p.lat_e7, p.lon_e7, spacing_m)
            self.height_amsl(wp.lat_e7, wp.lon_e7, spacing_m)
        if here is None:
            return False
        around = self._around
        if around is None or not around.holds(here.lat_e7, here.lon_e7, spacing_m):
            around = self._around = _Around(here.lat_e7, here.lon_e7, spacing_m)
        for lat, lon in around.corners:
            self.want_block(lat, lon, spacing_m)
        return self.height_amsl(here.lat_e7, here.lon_e7, spacing_m) is not None

    def store(self, lat_e7: int, lon_e7: int, spacing_m: int, gridbit: int, data, own_spacing_m: int) -> bool:
        """A TERRAIN_DATA: its 16 heights into the held block it names, as AP_Terrain takes them
        (a block not held, another spacing or a gridbit past 55 is ignored). Whether it was kept."""
        if spacing_m != own_spacing_m or not 0 <= gridbit < SUBGRIDS:
            return False
        block = self._find(lat_e7, lon_e7, spacing_m)
        if block is None:
            return False
        n0, e0 = gridbit // SUBGRIDS_E * 4, gridbit % SUBGRIDS_E * 4
        for i in range(4):
            for j in range(4):
                block.heights[(n0 + i) * BLOCK_SIZE_E + e0 + j] = int(data[i * 4 + j])
        block.bitmap |= 1 << gridbit
        return True

    def statistics(self, spacing_m: int) -> tuple[int, int]:
        """(pending, loaded) 4 x 4 sub-grids over the held blocks of this spacing."""
        pending = loaded = 0
        for block in self.blocks:
            if block.spacing_m != spacing_m:
                continue
            have = bin(block.bitmap).count("1")
            pending += SUBGRIDS - have
            loaded += have
        return pending, loaded

    def missing(self, here: Loc | None, spacing_m: int) -> Block | None:
        """The block to ask the ground station about next: the vehicle's own if it lacks anything,
        else the first held block that does (AP_Terrain::send_request)."""
        if here is not None and spacing_m > 0:
            block = self.want(grid_info(here.lat_e7, here.lon_e7, spacing_m), spacing_m)
            if block.bitmap != FULL_MASK:
                return block
        return next((b for b in self.blocks if b.spacing_m == spacing_m and b.bitmap != FULL_MASK), None)


def _offset_bearing(loc: Loc, bearing_deg: float, distance_m: float) -> Loc:
    b = math.radians(bearing_deg)
    return loc.offset(math.cos(b) * distance_m, math.sin(b) * distance_m)


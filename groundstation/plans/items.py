"""One mission item as a ground station plans it, and the few kinds the planners make."""
from __future__ import annotations

import math
from dataclasses import dataclass

FRAME_GLOBAL, FRAME_MISSION, FRAME_RELATIVE = 0, 2, 3
NAV_WAYPOINT, NAV_RTL, NAV_LAND, NAV_TAKEOFF, NAV_SPLINE_WAYPOINT = 16, 20, 21, 22, 82
DO_LAND_START, DO_SET_ROI_LOCATION, DO_SET_ROI_WPNEXT_OFFSET, DO_SET_ROI_NONE = 189, 195, 196, 197
DO_SET_CAM_TRIGG_DIST = 206
NAN = math.nan


@dataclass(frozen=True)
class PlannedItem:
    command: int
    frame: int
    params: tuple  # p1..p4
    lat_deg: float
    lon_deg: float
    alt_m: float
    autocontinue: bool = True

    @property
    def has_position(self) -> bool:
        return not (self.lat_deg == 0 and self.lon_deg == 0) and self.frame != FRAME_MISSION

    def qgc_json(self, jump_id: int) -> dict:
        """The item as QGroundControl saves a SimpleItem (NaN written as null)."""
        values = list(self.params) + [self.lat_deg, self.lon_deg, self.alt_m]
        return {"autoContinue": self.autocontinue, "command": self.command, "doJumpId": jump_id,
                "frame": self.frame, "params": [None if math.isnan(v) else v for v in values],
                "type": "SimpleItem"}


def waypoint(lat: float, lon: float, alt: float, yaw: float = NAN) -> PlannedItem:
    """A pass-through waypoint: no hold, the vehicle's own acceptance radius, yaw unchanged (NaN)."""
    return PlannedItem(NAV_WAYPOINT, FRAME_RELATIVE, (0.0, 0.0, 0.0, yaw), lat, lon, alt)


def spline_waypoint(lat: float, lon: float, alt: float) -> PlannedItem:
    return PlannedItem(NAV_SPLINE_WAYPOINT, FRAME_RELATIVE, (0.0, 0.0, 0.0, 0.0), lat, lon, alt)


def takeoff(alt: float) -> PlannedItem:
    return PlannedItem(NAV_TAKEOFF, FRAME_RELATIVE, (0.0, 0.0, 0.0, NAN), 0.0, 0.0, alt)


def land(lat: float = 0.0, lon: float = 0.0) -> PlannedItem:
    return PlannedItem(NAV_LAND, FRAME_RELATIVE, (0.0, 0.0, 0.0, NAN), lat, lon, 0.0)


def return_to_launch() -> PlannedItem:
    return PlannedItem(NAV_RTL, FRAME_MISSION, (0.0, 0.0, 0.0, 0.0), 0.0, 0.0, 0.0)


def trigger_distance(metres: float, shoot_now: bool) -> PlannedItem:
    """DO_SET_CAM_TRIGG_DIST: a photo every `metres` (0 stops); param 3 = 1 shoots one at once."""
    return PlannedItem(DO_SET_CAM_TRIGG_DIST, FRAME_MISSION, (metres, 0.0, 1.0 if shoot_now else 0.0, 0.0), 0.0, 0.0, 0.0)


def land_start(lat: float, lon: float) -> PlannedItem:
    """DO_LAND_START: where a landing sequence begins (RTL and AUTO_RTL jump here)."""
    return PlannedItem(DO_LAND_START, FRAME_RELATIVE, (0.0, 0.0, 0.0, 0.0), lat, lon, 0.0)

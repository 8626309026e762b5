"""A command's location (param 5-7, or COMMAND_INT's x, y, z and frame) as ArduPilot reads one:
whether it is a location at all, and where it is in the local frame."""
from __future__ import annotations

import math

from ..results import Severity
from ..vehicle import LOCATION_ALT_MAX_M
from .dialect import mavlink as mav

ABSOLUTE_ALT_FRAMES = {mav.MAV_FRAME_GLOBAL, mav.MAV_FRAME_GLOBAL_INT}
TERRAIN_ALT_FRAMES = {mav.MAV_FRAME_GLOBAL_TERRAIN_ALT, mav.MAV_FRAME_GLOBAL_TERRAIN_ALT_INT}
# Altitude above home, or above terrain. Where a command's position is flown (DO_REPOSITION, the
# guided waypoint) the terrain frame is GUIDED's above the terrain (terrain_target_ned); elsewhere
# (DO_SET_HOME, a gimbal's point) it is taken as above home.
RELATIVE_ALT_FRAMES = {mav.MAV_FRAME_GLOBAL_RELATIVE_ALT, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT,
                       mav.MAV_FRAME_GLOBAL_TERRAIN_ALT, mav.MAV_FRAME_GLOBAL_TERRAIN_ALT_INT}


def is_location(s, c) -> bool:
    """Whether a command's lat/lon/alt make a location, as ArduPilot converts a command to one: a
    latitude and longitude on the globe, an altitude that is a number within LOCATION_ALT_MAX_M, a frame it
    knows (an unknown one is named in a STATUSTEXT, as ArduPilot's SITL names it). False: DENIED."""
    lat, lon, alt = c.p5, c.p6, c.p7
    if not (math.isfinite(lat) and math.isfinite(lon) and -90 <= lat <= 90 and -180 <= lon <= 180):
        return False
    if not (math.isfinite(alt) and abs(alt) <= LOCATION_ALT_MAX_M):
        return False
    if c.frame not in ABSOLUTE_ALT_FRAMES and c.frame not in RELATIVE_ALT_FRAMES:
        s.vehicle.notify(f"Unknown mavlink coordinate frame {c.frame}", Severity.INFO)
        return False
    return True


def terrain_target_ned(s, c):
    """A location in a terrain frame as GUIDED flies it: local north, east, and down as minus its
    height above the terrain (Guided.set_target with terrain); None without a position."""
    v = s.vehicle
    if not v.has_position():
        return None
    n, e, _ = v.ned_of(c.p5, c.p6, v.origin.alt_m)
    return n, e, -c.p7


def target_ned(s, c):
    """A location (is_location) in local NED, or None while the vehicle cannot place it: a height
    above home needs home, and any point the EKF's origin (a position)."""
    v = s.vehicle
    lat, lon, alt = c.p5, c.p6, c.p7
    if not v.has_position() and v.home_ned is None:
        return None
    if c.frame in ABSOLUTE_ALT_FRAMES:
        d = v.ned_of(lat, lon, alt)[2]
    elif v.home_ned is not None:
        d = v.home_ned[2] - alt
    else:
        return None
    n, e, _ = v.ned_of(lat, lon, v.origin.alt_m)
    return n, e, d

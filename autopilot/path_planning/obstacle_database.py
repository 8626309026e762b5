"""ArduCopter's object-avoidance database (AP_OADatabase, OA_DB_*): proximity readings kept as
obstacles for BendyRuler, made with the path planner at boot (any OA_TYPE but 0).

Each reading of a proximity sensor that feeds it (a companion's OBSTACLE_DISTANCE with PRX1_TYPE 2;
ArduCopter SITL's own lidar, PRX1_TYPE 10, feeds none) becomes a point: the reading's distance
along its body-frame bearing, rotated by the vehicle's attitude, from where the vehicle is (north,
east, up from the local origin). Its radius is the distance times tan(OA_DB_BEAM_WIDTH, at least 1
degree), at least OA_DB_RADIUS_MIN. A point within the larger radius of one kept is the same
obstacle: only its time (and radius) are refreshed, when the radius differs or 0.5 s have passed;
else it is added while fewer than OA_DB_SIZE are kept. Readings are dropped whose near edge is
beyond OA_DB_DIST_MAX (0: none), and all readings while the vehicle is within 3 m of home below
OA_DB_ALT_MIN (0: never). Obstacles older than OA_DB_EXPIRE seconds (0: never) are forgotten at
each plan. OA_DB_SIZE or OA_DB_QUEUE_SIZE 0 at boot: no database ("DB init failed . Sizes
queue:Q, db:D"). Obstacles are not sent to the ground station (OA_DB_OUTPUT's default sends only
high-importance ones, which proximity's are not).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..params import ParamStore

Vec3 = tuple[float, float, float]  # north, east, up
REFRESH_S = 0.5  # a matched obstacle's time is refreshed after this (or a new radius)
NEAR_HOME_M = 3.0  # AP_OADATABASE_DISTANCE_FROM_HOME


@dataclass
class Obstacle:
    pos: Vec3
    radius: float
    time_s: float


def body_to_ned(roll: float, pitch: float, yaw: float, v: Vec3) -> Vec3:
    """A body-frame (forward, right, down) vector in NED, for the given Euler angles [rad]."""
    cr, sr, cp, sp, cy, sy = math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch), math.cos(yaw), \
        math.sin(yaw)
    x, y, z = v
    return (cp * cy * x + (sr * sp * cy - cr * sy) * y + (cr * sp * cy + sr * sy) * z,
            cp * sy * x + (sr * sp * sy + cr * cy) * y + (cr * sp * sy - sr * cy) * z,
            -sp * x + sr * cp * y + cr * cp * z)


class ObstacleDatabase:
    def __init__(self, params: ParamStore):
        self._params = params
        self.size = int(params["OA_DB_SIZE"])
        queue = int(params["OA_DB_QUEUE_SIZE"])
        self.healthy = self.size > 0 and queue > 0
        self.init_failure = None if self.healthy else f"DB init failed . Sizes queue:{queue}, db:{self.size}"
        self._radius_scale = math.tan(math.radians(max(float(params["OA_DB_BEAM_WIDTH"]), 1.0)))
        self.obstacles: list[Obstacle] = []

    def push(self, now_s: float, here: Vec3, attitude: tuple[float, float, float], bearing_deg: float,
             distance: float, home: Vec3) -> None:
        """A reading `distance` metres along the body-frame `bearing_deg` (level), the vehicle at
        `here` with `attitude` (roll, pitch, yaw), home at `home`."""
        if not self.healthy or not (math.isfinite(distance) and math.isfinite(bearing_deg)):
            return
        p = self._params
        alt_min = float(p["OA_DB_ALT_MIN"])
        if alt_min != 0.0 and math.hypot(here[0] - home[0], here[1] - home[1]) < NEAR_HOME_M \
                and here[2] - home[2] < alt_min:
            return
        radius = max(float(p["OA_DB_RADIUS_MIN"]), distance * self._radius_scale)
        dist_max = float(p["OA_DB_DIST_MAX"])
        if dist_max > 0.0 and distance - radius > dist_max:
            return
        b = math.radians(bearing_deg)
        dn, de, dd = body_to_ned(*attitude, (math.cos(b) * distance, math.sin(b) * distance, 0.0))
        pos = (here[0] + dn, here[1] + de, here[2] - dd)
        for kept in self.obstacles:
            if math.dist(kept.pos, pos) < max(kept.radius, radius):
                if kept.radius != radius or now_s - kept.time_s >= REFRESH_S:
                    kept.time_s, kept.radius = now_s, radius
                return
        if len(self.obstacles) < self.size:
            self.obstacles.append(Obstacle(pos, radius, now_s))

    def expire(self, now_s: float) -> None:
        """Forget obstacles older than OA_DB_EXPIRE (the planner's update, once a plan)."""
        expiry = float(self._params["OA_DB_EXPIRE"])
        if expiry > 0.0:
            self.obstacles = [o for o in self.obstacles if now_s - o.time_s <= expiry]

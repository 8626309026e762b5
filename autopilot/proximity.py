"""A 360-degree proximity sensor, as ArduPilot's AP_Proximity keeps one (PRX1_TYPE, read at boot):
eight sectors of 45 degrees in the body frame (0 ahead, clockwise), each with its last distance and
a low-pass filtered one (PRX_FILT), and the boundary simple avoidance keeps the vehicle inside.

Two sensors feed it:
- PRX1_TYPE 10, SITL's lidar: in each sector's middle direction, the distance to the edge of the
  inclusion fence uploaded (found by halving, to 0.1 m, out to 200 m, as AP_Proximity_SITL does),
  and upward the distance to FENCE_ALT_MAX. No inclusion fence: no data.
- PRX1_TYPE 2, a companion: OBSTACLE_DISTANCE (its sectors folded into the eight, the nearest of
  each), DISTANCE_SENSOR facing one of the eight ways or up, and OBSTACLE_DISTANCE_3D
  (AP_Proximity_MAV). No message for 0.5 s: no data. Readings of 0, 65535, or outside the
  message's own limits are none. OBSTACLE_DISTANCE_3D gives one point per message in the body
  FRD frame (any other frame is heard, keeping the sensor healthy, and dropped); the points
  that share a time stamp are one batch, the nearest per sector kept, which reaches the boundary
  when a message with another stamp comes (or one more than 50 ms later). Only points within
  15 degrees of level count here: the middle of AP_Proximity's five layers, the one Firefly keeps.

The boundary is AP_Proximity_Boundary_3D's middle layer: a point on each edge between two sectors
at the nearer of their filtered distances (100 m where neither has one; 0.6 m at least), and an
obstacle per sector the point nearest the vehicle on the line between its two edge points. A
sector not heard from for a second is forgotten. Distances are in metres, as float32s where
ArduPilot's centimetre fields come from them.
"""
from __future__ import annotations

import math
from collections.abc import Callable, Sequence

from .c_casts import float32

SECTORS = 8
SECTOR_DEG = 45.0
NONE, MAVLINK, SITL = 0, 2, 10  # PRX1_TYPE
SITL_RANGE_M, SITL_ACCURACY_M = 200.0, 0.1  # AP_Proximity_SITL's PROXIMITY_MAX_RANGE / _ACCURACY
MAVLINK_TIMEOUT_S = 0.5  # PROXIMITY_MAV_TIMEOUT_MS
FACE_RESET_S = 1.0  # PROXIMITY_FACE_RESET_MS
BOUNDARY_DEFAULT_M, BOUNDARY_MIN_M = 100.0, 0.6  # PROXIMITY_BOUNDARY_DIST_DEFAULT / _MIN
UPWARD = 24  # MAV_SENSOR_ROTATION_PITCH_90
BODY_FRD = 12  # MAV_FRAME_BODY_FRD, OBSTACLE_DISTANCE_3D's only frame taken
BATCH_GAP_S = 0.05  # PROXIMITY_TIMESTAMP_MSG_TIMEOUT_MS
MIDDLE_LAYER_DEG = 15.0  # half of PROXIMITY_PITCH_WIDTH_DEG about level
FIRST_ID = 10  # PROXIMITY_SENSOR_ID_START: DISTANCE_SENSOR ids 10-17 by sector, 19 upward
# each edge's direction: the clockwise edge of sector i, at 45 i + 22.5 degrees
EDGES = tuple((math.cos(math.radians(SECTOR_DEG * i + SECTOR_DEG / 2)), math.sin(math.radians(SECTOR_DEG * i + SECTOR_DEG / 2)))
              for i in range(SECTORS))

Vec2 = tuple[float, float]


def sector_of(yaw_deg: float) -> int:
    """The sector a body-frame bearing falls in (AP_Proximity_Boundary_3D::get_face)."""
    return int(((yaw_deg + SECTOR_DEG / 2) % 360.0) // SECTOR_DEG) % SECTORS


def _nearest_on_segment(a: Vec2, b: Vec2) -> Vec2:
    """The point of segment a-b nearest the vehicle (the origin)."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    l2 = dx * dx + dy * dy
    if l2 <= 0.0:
        return a
    t = max(0.0, min(1.0, -(a[0] * dx + a[1] * dy) / l2))
    return a[0] + dx * t, a[1] + dy * t


class Proximity:
    def __init__(self, params) -> None:
        self.params = params
        kind = int(params["PRX1_TYPE"])
        self.kind = kind if kind in (MAVLINK, SITL) else NONE  # read at boot, as ArduPilot does
        self.distance = [0.0] * SECTORS
        self.filtered = [0.0] * SECTORS
        self.valid = [False] * SECTORS
        self.angle = [0.0] * SECTORS
        self._heard_s = [-math.inf] * SECTORS
        self._filter_s = [-math.inf] * SECTORS
        self.points: list[Vec2] = [(e[0] * BOUNDARY_DEFAULT_M, e[1] * BOUNDARY_DEFAULT_M) for e in EDGES]
        self.ever_valid = 0  # sectors ever reported: DISTANCE_SENSOR goes on for those (send_proximity)
        self.good = False  # AP_Proximity::Status::Good
        self.range_m = (0.0, SITL_RANGE_M)  # the sensor's min and max
        self.upward_m: float | None = None
        self._last_message_s = -math.inf
        self._last_upward_s = -math.inf
        self._batch: dict[int, tuple[float, float]] = {}  # OBSTACLE_DISTANCE_3D's: sector -> (angle, m)
        self._batch_stamp_ms: int | None = None

    # ----- the boundary ----------------------------------------------------------------------------
    def _set(self, sector: int, angle_deg: float, distance_m: float, now_s: float) -> None:
        self.angle[sector], self.distance[sector] = angle_deg, distance_m
        cutoff = self.params["PRX_FILT"]
        dt = now_s - self._filter_s[sector]
        if not self.valid[sector] or cutoff <= 0.0 or dt > FACE_RESET_S:
            self.filtered[sector] = distance_m
        else:
            rc = 1.0 / (2.0 * math.pi * cutoff)
            self.filtered[sector] += (distance_m - self.filtered[sector]) * dt / (dt + rc)
        self._filter_s[sector] = self._heard_s[sector] = now_s
        self.valid[sector] = True
        self.ever_valid |= 1 << sector
        self._edges_of(sector)

    def _reset(self, sector: int) -> None:
        if self.valid[sector]:
            self.valid[sector] = False
            self._edges_of(sector)

    def _edge(self, edge: int) -> float:
        """The edge between sector `edge` and the next one, at the nearer filtered distance."""
        a, b = edge, (edge + 1) % SECTORS
        near = [self.filtered[s] for s in (a, b) if self.valid[s]]
        return max(min(near), BOUNDARY_MIN_M) if near else BOUNDARY_DEFAULT_M

    def _edges_of(self, sector: int) -> None:
        """Both edges of a sector moved; an unheard neighbour's far edge follows (a cup)."""
        for edge, beyond in ((sector, (sector + 1) % SECTORS), ((sector - 1) % SECTORS, (sector - 2) % SECTORS)):
            d = self._edge(edge)
            self.points[edge] = (EDGES[edge][0] * d, EDGES[edge][1] * d)
            if not self.valid[beyond]:
                self.points[beyond] = (EDGES[beyond][0] * d, EDGES[beyond][1] * d)

    def obstacles(self) -> list[Vec2]:
        """Body-frame (forward, right) points to keep away from: per sector with a reading near it,
        the boundary's nearest point between its edges (AP_Proximity_Boundary_3D::get_obstacle)."""
        out = []
        for sector in range(SECTORS):
            if any(self.valid[(sector + k) % SECTORS] for k in range(3)):
                out.append(_nearest_on_segment(self.points[(sector + 1) % SECTORS], self.points[sector]))
        return out

    def objects(self) -> list[tuple[float, float]]:
        """(bearing in degrees, filtered distance) of each sector with a reading."""
        return [(self.angle[s], self.filtered[s]) for s in range(SECTORS) if self.valid[s]]

    def closest(self) -> tuple[float, float] | None:
        """(bearing in degrees, distance) of the nearest reading (the pre-arm check's)."""
        found = [(self.distance[s], self.angle[s]) for s in range(SECTORS) if self.valid[s]]
        if not found:
            return None
        distance, angle = min(found)
        return angle, distance

    # ----- the sensors -----------------------------------------------------------------------------
    def update(self, now_s: float, yaw_rad: float, outside: Callable[[float, float], bool],
               fenced: bool, height_m: float) -> None:
        """10 Hz: SITL's lidar measures; a companion's silence, or a sector's, is timed out."""
        for sector in range(SECTORS):
            if self.valid[sector] and now_s - self._heard_s[sector] > FACE_RESET_S:
                self._reset(sector)
        if self.kind == SITL:
            self.upward_m = max(0.0, self.params["FENCE_ALT_MAX"] - height_m)
            self.good = fenced
            if fenced:
                for sector in range(SECTORS):
                    d = self._sitl_range(yaw_rad + math.radians(sector * SECTOR_DEG), outside)
                    self._set(sector, sector * SECTOR_DEG, d, now_s)
        elif self.kind == MAVLINK:
            self.good = (now_s - self._last_message_s <= MAVLINK_TIMEOUT_S
                         or now_s - self._last_upward_s <= MAVLINK_TIMEOUT_S)
            if now_s - self._last_upward_s > MAVLINK_TIMEOUT_S:
                self.upward_m = None

    @staticmethod
    def _sitl_range(bearing_rad: float, outside: Callable[[float, float], bool]) -> float:
        """The distance along a bearing to where the fence is breached, halved down to 0.1 m."""
        c, s = math.cos(bearing_rad), math.sin(bearing_rad)
        low, high = 0.0, SITL_RANGE_M
        while high - low > SITL_ACCURACY_M:
            mid = (low + high) * 0.5
            if outside(c * mid, s * mid):
                high = mid
            else:
                low = mid
        return low

    def obstacle_distance(self, distances: Sequence[int], increment_deg: float, angle_offset_deg: float,
                          min_cm: int, max_cm: int, now_s: float) -> list[tuple[float, float]]:
        """A companion's OBSTACLE_DISTANCE (body frame): the nearest reading of each sector.
        Returns the readings taken, (body-frame bearing [deg], distance [m]) each, for the
        obstacle database."""
        readings: list[tuple[float, float]] = []
        if self.kind != MAVLINK or not math.isfinite(increment_deg) or increment_deg == 0.0 \
                or not math.isfinite(angle_offset_deg):
            return readings
        count = min(int(360.0 / abs(increment_deg) + 0.5), len(distances))
        self.range_m = (float32(min_cm * float32(0.01)), float32(max_cm * float32(0.01)))
        self._last_message_s = now_s
        offset = angle_offset_deg % 360.0  # (PRX1_YAW_CORR and PRX1_ORIENT are not served: 0)
        step = increment_deg
        nearest: dict[int, tuple[float, float]] = {}
        for j in range(count):
            cm = distances[j]
            if cm == 0 or cm == 65535 or cm < min_cm or cm > max_cm:
                continue
            angle = (j * step + offset) % 360.0
            sector, metres = sector_of(angle), float32(cm * float32(0.01))
            readings.append((angle, metres))
            if sector not in nearest or metres < nearest[sector][1]:
                nearest[sector] = (angle, metres)
        for sector in range(SECTORS):
            if sector in nearest:
                self._set(sector, *nearest[sector], now_s)
            else:
                self._reset(sector)
        self.good = True
        return readings

    def obstacle_3d(self, stamp_ms: int, frame: int, xyz: tuple[float, float, float], min_m: float, max_m: float,
                    now_s: float) -> None:
        """A companion's OBSTACLE_DISTANCE_3D: one point (forward, right, down [m])."""
        if self.kind != MAVLINK:
            return
        gap = now_s - self._last_message_s
        self._last_message_s = now_s
        self.good = True
        new_batch = stamp_ms != self._batch_stamp_ms or gap > BATCH_GAP_S
        self._batch_stamp_ms = stamp_ms  # (a message in another frame moves the stamp on too)
        if frame != BODY_FRD:
            return
        if new_batch:
            for sector, (angle, metres) in self._batch.items():
                self._set(sector, angle, metres, now_s)
            self._batch = {}
        if not (0.0 <= min_m <= max_m < math.inf):  # NaN too: no range to report or test against
            return
        self.range_m = (float32(min_m), float32(max_m))
        x, y, z = xyz
        metres = math.sqrt(x * x + y * y + z * z)
        if not (metres > 0.0 and min_m <= metres <= max_m):  # NaN too; max_m is finite
            return
        if not -MIDDLE_LAYER_DEG <= math.degrees(math.atan2(-z, math.hypot(x, y))) < MIDDLE_LAYER_DEG:
            return  # above or below the middle layer (AP_Proximity_Boundary_3D::get_layer's bands)
        angle = math.degrees(math.atan2(y, x)) % 360.0
        sector = sector_of(angle)
        held = self._batch.get(sector)
        if held is None or metres < held[1]:
            self._batch[sector] = (angle, float32(metres))

    def distance_sensor(self, orientation: int, distance_cm: int, min_cm: int, max_cm: int, now_s: float) -> None:
        """A companion's DISTANCE_SENSOR facing one of the eight ways, or up."""
        if self.kind != MAVLINK:
            return
        metres = float32(distance_cm * float32(0.01))
        if orientation == UPWARD:
            self.upward_m, self._last_upward_s = metres, now_s
            self.good = True
            return
        if not 0 <= orientation < SECTORS:
            return
        self._last_message_s = now_s
        self.range_m = (float32(min_cm * float32(0.01)), float32(max_cm * float32(0.01)))
        if self.range_m[0] <= metres <= self.range_m[1]:
            self._set(orientation, orientation * SECTOR_DEG, metres, now_s)
        self.good = True

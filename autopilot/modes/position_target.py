"""The position controller's own target run to a point, as ArduCopter's AC_PosControl::input_pos_NEU_m
moves it: jerk-limited towards the point horizontally and vertically, with no speed at the point
(where BendyRuler's points go, AC_WPNav_OA, rather than to the waypoint navigator).

The speed limit is taken along the way to the point (kinematic_limit): the horizontal limit for a
level way, the climb or descent limit for a vertical one, whichever binds first between. The
vertical braking is capped at 7.5 m/s/s, as ArduCopter's is.
"""
from __future__ import annotations

import math

from ..control.shaping import advance_2d, shape_pos_vel_accel, shape_pos_vel_accel_2d

Vec2 = tuple[float, float]
Vec3 = tuple[float, float, float]
ACCEL_DOWN_MAX_M_S2 = 7.5


def kinematic_limit(direction: Vec3, max_xy: float, max_up: float, max_down: float) -> float:
    """The speed along `direction` (north, east, up) that keeps within each limit."""
    if max_xy == 0.0 or max_up == 0.0 or max_down == 0.0:
        return 0.0
    length = math.sqrt(direction[0] ** 2 + direction[1] ** 2 + direction[2] ** 2)
    if length == 0.0:
        return 0.0
    xy = math.hypot(direction[0], direction[1]) / length
    z = direction[2] / length
    max_xy, max_up, max_down = abs(max_xy), abs(max_up), abs(max_down)
    if xy == 0.0:
        return max_up if z > 0.0 else max_down
    if z == 0.0:
        return max_xy
    slope = z / xy
    vertical = max_up if slope > 0.0 else max_down
    return max_xy / xy if abs(slope) < vertical / max_xy else abs(vertical / z)


class PositionTarget:
    """The target (north, east, up position, velocity and acceleration) from a given start."""
    __slots__ = ("pos_ne", "vel_ne", "accel_ne", "pos_up", "vel_up", "accel_up")

    def __init__(self, pos: Vec3, vel: Vec3, accel: Vec3):
        self.pos_ne: Vec2 = (pos[0], pos[1])
        self.vel_ne: Vec2 = (vel[0], vel[1])
        self.accel_ne: Vec2 = (accel[0], accel[1])
        self.pos_up, self.vel_up, self.accel_up = pos[2], vel[2], accel[2]

    def run_to(self, point: Vec3, dt: float, speed: tuple[float, float, float], accel_xy: float, jerk_xy: float,
               accel_z: float, jerk_z: float) -> None:
        """Advance dt, then shape towards `point` within `speed` (horizontal, up, down) [m/s]."""
        self.pos_ne, self.vel_ne = advance_2d(self.pos_ne, self.vel_ne, self.accel_ne, dt)
        self.pos_up += self.vel_up * dt + 0.5 * self.accel_up * dt * dt
        self.vel_up += self.accel_up * dt
        way = (point[0] - self.pos_ne[0], point[1] - self.pos_ne[1], point[2] - self.pos_up)
        length = math.sqrt(way[0] ** 2 + way[1] ** 2 + way[2] ** 2)
        vel_xy = vel_z = 0.0
        if length > 0.0:
            limit = kinematic_limit(way, *speed)
            vel_xy = limit * math.hypot(way[0], way[1]) / length
            vel_z = abs(limit * way[2] / length)
        self.accel_ne = shape_pos_vel_accel_2d((point[0], point[1]), (0.0, 0.0), (0.0, 0.0), self.pos_ne, self.vel_ne,
                                               self.accel_ne, accel_xy, jerk_xy, dt, vel_xy)
        climb = vel_z if vel_z > 0.0 else math.inf  # (a limit of 0 is none, as ArduCopter's)
        self.accel_up = shape_pos_vel_accel(point[2], 0.0, 0.0, self.pos_up, self.vel_up, self.accel_up, -climb, climb,
                                            -min(accel_z, ACCEL_DOWN_MAX_M_S2), accel_z, jerk_z, dt)

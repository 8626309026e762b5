"""Collision avoidance's judgement of traffic, as ArduPilot's AP_Avoidance makes it (measured on
ArduCopter SITL, parity area adsb).

AVD_ENABLE switches it on and off while running (off again, it recovers as AVD_F_RCVRY 2 would:
RTL). Every 100 ms it takes the receiver's new reports as obstacles (at most AVD_OBS_MAX, the
oldest replaced by a newer one), then rates each, while the vehicle knows where it is and how it
moves:
- HIGH if, on the two tracks projected AVD_F_TIME seconds ahead (plus the report's age), they pass
  closer than AVD_F_DIST_XY; LOW if within AVD_W_TIME they pass closer than AVD_W_DIST_XY;
- then vertically: no threat if they pass more than AVD_W_DIST_Z apart, LOW rather than HIGH if
  more than AVD_F_DIST_Z; none at all for a report older than 5 s.
The most serious obstacle (highest level, then the soonest closest approach) sets the threat
level, which rises at once and falls only 2 s after its last change. While it is HIGH and
AVD_F_ACTION asks for more than a report, the vehicle acts (escape.py) every 100 ms; when it
falls from HIGH the vehicle recovers as AVD_F_RCVRY says.
COLLISION goes to every link for the most serious obstacle at most every 1.1 s (a report ages
past 1 s on 100 ms ticks); once a threat clears, for 5 s more, then no more. An obstacle that
never threatened is never reported.

ArduPilot's arithmetic is kept where it is odd: the vertical closest approach compares centimetres
of height with metres per second of climb.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from collections.abc import Callable
from typing import NamedTuple, Protocol

from ..location import Loc
from .traffic_list import Tracked

NONE, LOW, HIGH = 0, 1, 2  # MAV_COLLISION_THREAT_LEVEL
ACTION_NONE, ACTION_REPORT = 0, 1  # MAV_COLLISION_ACTION; more than REPORT acts (escape.py)
SRC_ADSB, SRC_GLOBAL_POSITION = 0, 1  # MAV_COLLISION_SRC: a COLLISION always says ADSB, as ArduPilot's
MAX_AGE_MS = 5000  # MAX_OBSTACLE_AGE_MS
RECOVERY_MS = 2000  # AP_AVOIDANCE_STATE_RECOVERY_TIME_MS
NOTIFY_MS = 1000  # _gcs_notify_interval
CLEARED_MS = 5000  # _gcs_cleared_messages_duration
RECOVER_RTL = 2  # AVD_F_RCVRY's RTL, the recovery when avoidance is switched off
UINT32 = 0xFFFFFFFF


@dataclass
class Obstacle:
    src: int
    src_id: int
    loc: Loc
    vel_ned: tuple[float, float, float]
    timestamp_ms: int
    threat_level: int = NONE
    closest_xy: float = 0.0
    closest_z: float = 0.0
    time_to_closest_s: float = 0.0
    reported_ms: int = 0  # the last COLLISION about it


class Collision(NamedTuple):
    """A COLLISION's fields."""
    src: int
    src_id: int
    action: int
    threat_level: int
    time_to_minimum_delta: float
    altitude_minimum_delta: float
    horizontal_minimum_delta: float


class Escape(Protocol):
    """What the vehicle does about a threat (escape.py)."""

    def act(self, threat: Obstacle, action: int) -> int: ...

    def recover(self, recovery: int) -> None: ...


def closest_xy(my_loc: Loc, my_vel, obstacle: Obstacle, horizon_s: int) -> float:
    """How close, horizontally, the two tracks come within the horizon [m]."""
    ov = obstacle.vel_ned
    wn, we = (ov[0] - my_vel[0]) * horizon_s, (ov[1] - my_vel[1]) * horizon_s
    pn, pe = obstacle.loc.ne_to(my_loc)
    l2 = wn * wn + we * we
    if l2 < 1.1920929e-07:  # FLT_EPSILON
        cn, ce = wn, we
    else:
        t = (pn * wn + pe * we) / l2
        cn, ce = (0.0, 0.0) if t <= 0 else (wn, we) if t >= 1 else (wn * t, we * t)
    return math.hypot(cn - pn, ce - pe)


def closest_z(my_loc: Loc, my_vel, obstacle: Obstacle, horizon_s: int) -> float:
    """AP_Avoidance's vertical closest approach [m], its units as they are."""
    dv = obstacle.vel_ned[2] - my_vel[2]
    dp = obstacle.loc.alt_cm - my_loc.alt_cm
    if dp >= 0 and dv >= 0:
        r = dp
    elif dp <= 0 and dv <= 0:
        r = abs(dp)
    else:
        r = abs(dp - dv * horizon_s)
    return r * 0.01


class Avoidance:
    def __init__(self, params, escape: Escape):
        self._params = params
        self._escape = escape
        self.on = False  # AVD_ENABLE has made it (ArduPilot allocates its obstacles then)
        # The AVOID_ADSB aux switch's word (True on, False off) until AVD_ENABLE is next set; None: none
        self.switched: bool | None = None
        self.obstacles: list[Obstacle] = []
        self._capacity = 0
        self.threat_level = NONE
        self._changed_ms = 0
        self.latest_action = ACTION_NONE
        self._cleared_first_ms = UINT32
        self._most_serious: Obstacle | None = None

    def _start(self) -> bool:
        """AP_Avoidance's check_startup: made when AVD_ENABLE is set, dropped (recovering) when not."""
        wanted = self._params["AVD_ENABLE"] if self.switched is None else self.switched
        if not wanted:
            if self.on:
                self.on, self.obstacles = False, []
                self._escape.recover(RECOVER_RTL)
            return False
        if not self.on:
            self.on, self.obstacles, self._capacity = True, [], max(0, int(self._params["AVD_OBS_MAX"]))
            self._changed_ms, self.threat_level = 0, NONE
            self._cleared_first_ms, self._most_serious = UINT32, None
        return True

    def _add_report(self, tracked: Tracked) -> None:
        r = tracked.report
        hdg = math.radians(r.heading_cdeg * 0.01)
        speed = r.hor_velocity_cms * 0.01
        vel = (speed * math.cos(hdg), speed * math.sin(hdg), -r.ver_velocity_cms * 0.01)
        self._add(SRC_ADSB, r.icao, r.location, vel, tracked.heard_ms)

    def position_heard(self, now_ms: int, system_id: int, where: Loc, vel_ned: tuple[float, float, float]) -> None:
        """Another system's GLOBAL_POSITION_INT (with DEV_OPTIONS bit 0): an obstacle too."""
        if self.on:
            self._add(SRC_GLOBAL_POSITION, system_id, where, vel_ned, now_ms)

    def _add(self, src: int, src_id: int, loc: Loc, vel: tuple[float, float, float], timestamp_ms: int) -> None:
        obstacles = self.obstacles
        oldest = None
        for o in obstacles:
            if o.src == src and o.src_id == src_id:
                o.loc, o.vel_ned, o.timestamp_ms = loc, vel, timestamp_ms
                return
            if oldest is None or o.timestamp_ms < oldest.timestamp_ms:
                oldest = o
        if len(obstacles) < self._capacity:
            obstacles.append(Obstacle(src, src_id, loc, vel, timestamp_ms))
        elif oldest is not None and oldest.timestamp_ms < timestamp_ms:
            oldest.src, oldest.src_id, oldest.loc, oldest.vel_ned, oldest.timestamp_ms = \
                src, src_id, loc, vel, timestamp_ms

    def update(self, now_ms: int, take_samples: Callable[[], list[Tracked]], my_loc: Loc | None,
               my_vel: tuple[float, float, float] | None) -> Collision | None:
        """The 10 Hz update, given the receiver's new reports and where the vehicle is and how it
        moves (None: not known); the COLLISION to send, if one is due."""
        if not self._start():
            return None
        for tracked in take_samples():
            self._add_report(tracked)
        if my_loc is not None and my_vel is not None:
            self._rate(now_ms, my_loc, my_vel)
        threat = self._most_serious
        self._handle_locally(now_ms, threat, my_loc)
        return self._notify(now_ms, threat)

    def _rate(self, now_ms: int, my_loc: Loc, my_vel) -> None:
        p = self._params
        fail_t, warn_t = int(p["AVD_F_TIME"]), int(p["AVD_W_TIME"])
        fail_xy, warn_xy = p["AVD_F_DIST_XY"], p["AVD_W_DIST_XY"]
        fail_z, warn_z = p["AVD_F_DIST_Z"], p["AVD_W_DIST_Z"]
        most = None
        obstacles = self.obstacles
        i = 0
        while i < len(obstacles):
            o = obstacles[i]
            age_ms = now_ms - o.timestamp_ms
            age_s = age_ms // 1000
            level = NONE
            xy = closest_xy(my_loc, my_vel, o, fail_t + age_s)
            if xy < fail_xy:
                level = HIGH
            else:
                xy = closest_xy(my_loc, my_vel, o, warn_t + age_s)
                if xy < warn_xy:
                    level = LOW
            z = closest_z(my_loc, my_vel, o, warn_t + age_s)
            if level != NONE:
                if z > warn_z:
                    level = NONE
                else:
                    z = closest_z(my_loc, my_vel, o, fail_t + age_s)
                    if z > fail_z:
                        level = LOW
            if age_ms > MAX_AGE_MS:
                level = NONE
            o.threat_level, o.closest_xy, o.closest_z = level, xy, z
            to_closest = my_loc.distance_to(o.loc) - xy
            closing = math.hypot(my_vel[0] - o.vel_ned[0], my_vel[1] - o.vel_ned[1])
            o.time_to_closest_s = to_closest / closing if to_closest != 0 and closing != 0 else 0.0
            if age_ms > MAX_AGE_MS:
                if i == len(obstacles) - 1:  # the list shrinks only from its end, as ArduPilot's
                    obstacles.pop()
                    break
                i += 1
                continue
            if most is None or o.threat_level > most.threat_level or \
                    (o.threat_level == most.threat_level and o.time_to_closest_s < most.time_to_closest_s):
                most = o
            i += 1
        self._most_serious = most

    def _handle_locally(self, now_ms: int, threat: Obstacle | None, my_loc: Loc | None) -> None:
        level, action = NONE, ACTION_NONE
        if threat is not None:
            level = threat.threat_level
            if level == HIGH:
                action = int(self._params["AVD_F_ACTION"])
                alt_min = self._params["AVD_F_ALT_MIN"]
                if action != ACTION_NONE and alt_min > 0 and my_loc is not None and my_loc.alt_cm * 0.01 < alt_min:
                    action = ACTION_REPORT  # near the ground it only reports
        if level != self.threat_level and (now_ms - self._changed_ms > RECOVERY_MS or level > self.threat_level):
            if self.threat_level == HIGH:
                self._escape.recover(int(self._params["AVD_F_RCVRY"]))
                self.latest_action = ACTION_NONE
            self._changed_ms, self.threat_level = now_ms, level
        if threat is not None and self.threat_level == HIGH and action > ACTION_REPORT:
            self.latest_action = self._escape.act(threat, action)

    def _notify(self, now_ms: int, threat: Obstacle | None) -> Collision | None:
        if threat is None:
            return None
        if threat.threat_level == NONE:
            if self._cleared_first_ms == 0:
                self._cleared_first_ms = now_ms
            if (now_ms - self._cleared_first_ms) & UINT32 > CLEARED_MS:
                return None
        else:
            self._cleared_first_ms = 0
        if now_ms - threat.reported_ms <= NOTIFY_MS:
            return None
        threat.reported_ms = now_ms
        return Collision(SRC_ADSB, threat.src_id, self.latest_action, threat.threat_level,
                         threat.time_to_closest_s, threat.closest_z, threat.closest_xy)

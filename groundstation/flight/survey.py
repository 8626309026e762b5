"""The flight's feed of the search controller, sans-IO: the vehicle's positions and its 10 Hz
temperature readings in, the controller's next move out.

Every GND_TEMP reading is paired with the vehicle's position at the reading's own timestamp
(LOCAL_POSITION_NED, interpolated); a reading that arrives before the position of its instant
waits for it. Readings taken below 80 % of the survey altitude (climbing, descending) are not used.

The decision-level episodes take one reading per 5 m of track or per second, and the belief's
resolution (3 x 3 sub-positions per cell, 3.3 m apart) was judged at that density. In flight the
sensor reads ten times a second; fed one by one, those readings multiply the small misfit of a fire
between two sub-positions tenfold, and on a straight pass that was seen to lock the belief,
confidently, on the mirror image of the fire across the track. So the controller gets one
observation per observation spacing (speed x sample interval) or per sample interval, as
evaluated: the mean of the readings taken over it, at their mean position, with the sensor's own
sigma (conservative: the mean is less noisy than that).

The controller is asked for its next move when it has something new to decide on: a new
observation, or the vehicle within arrival_m of its target (horizontally, and of the target's
height: a climb to look for further fires has one). The path counts climbs and descents too.
"""
from __future__ import annotations

import bisect
import math

from ..strategy import Geometry
from ..strategy.controller import Goto, SearchConfig, SearchController
from ..strategy.stopping import Declaration

ARRIVAL_M = 2.0
MIN_HEIGHT_SHARE = 0.8  # of the survey altitude: readings from lower down are not used
POSITIONS_KEPT = 400  # 40 s at 10 Hz: far more than a reading ever lags its position


class Survey:
    def __init__(self, geometry: Geometry, config: SearchConfig, arrival_m: float = ARRIVAL_M):
        self.geometry = geometry
        self.spacing_m = config.observation_spacing_m
        self.interval_ms = 1000.0 * config.sample_s
        self.arrival_m = arrival_m
        self.controller: SearchController | None = None
        self.positions: list = []  # (t_ms, n, e, d) sorted by time
        self.pending: list = []  # (t_ms, z) readings waiting for a later position
        self.bin: list = []  # (t_ms, n, e, height, z) not yet given to the controller
        self.track: list = []  # (n, e) of the readings used
        self.path_m = 0.0  # along the track, climbs and descents included
        self._last_point: tuple | None = None  # (n, e, height) of the last reading used
        self._goal_height_m = geometry.survey_alt_m  # of the last target
        self.readings = 0
        self.vehicle_t_ms = 0
        self._stepped_at = 0  # the controller's observation count at the last step
        self.on_observe = None  # called after each observation reaches the controller (a camera's cue)

    def start(self, controller: SearchController) -> None:
        """Feed `controller` from now on (readings before this moment are not used)."""
        self.controller = controller
        self.bin.clear()

    @property
    def active(self) -> bool:
        return self.controller is not None and self.controller.declared is None

    def here(self) -> tuple[float, float]:
        return self.positions[-1][1:3]

    def add_position(self, t_ms: int, n: float, e: float, d: float) -> None:
        self.vehicle_t_ms = max(self.vehicle_t_ms, t_ms)
        if self.positions and t_ms <= self.positions[-1][0]:
            return
        self.positions.append((t_ms, n, e, d))
        del self.positions[:-POSITIONS_KEPT]
        ready = [r for r in self.pending if r[0] <= t_ms]
        self.pending = [r for r in self.pending if r[0] > t_ms]
        for t, z in ready:
            self._use(t, z)

    def add_reading(self, t_ms: int, z: float) -> None:
        if not math.isfinite(z):
            return
        if self.positions and t_ms <= self.positions[-1][0]:
            self._use(t_ms, z)
        else:
            self.pending.append((t_ms, z))

    def position_at(self, t_ms: int):
        """Linear interpolation of the position track at a reading's time."""
        times = [p[0] for p in self.positions]
        k = bisect.bisect_left(times, t_ms)
        if k < len(times) and times[k] == t_ms:
            return self.positions[k][1:]  # a reading stamped at a position's instant: that position
        if k == 0:
            return self.positions[0][1:]
        if k >= len(times):
            return self.positions[-1][1:]
        (t0, *a), (t1, *b) = self.positions[k - 1], self.positions[k]
        w = (t_ms - t0) / (t1 - t0) if t1 > t0 else 0.0
        return tuple(x + w * (y - x) for x, y in zip(a, b))

    def _use(self, t_ms: int, z: float) -> None:
        if not self.positions or not self.active:
            return
        n, e, d = self.position_at(t_ms)
        height = -d
        if height < self.geometry.survey_alt_m * MIN_HEIGHT_SHARE:
            self.bin.clear()  # an observation averages only readings taken in one stretch
            return
        if self._last_point is not None:
            self.path_m += math.dist(self._last_point, (n, e, height))
        self._last_point = (n, e, height)
        self.track.append((n, e))
        self.readings += 1
        self.bin.append((t_ms, n, e, height, z))
        first = self.bin[0]
        if math.dist(first[1:3], (n, e)) >= self.spacing_m or t_ms - first[0] >= self.interval_ms:
            _, n, e, height, z = (sum(column) / len(self.bin) for column in zip(*self.bin))
            self.bin.clear()
            self.controller.observe(n, e, z, height)
            if self.on_observe is not None:
                self.on_observe()

    def next_move(self) -> Goto | Declaration | None:
        """The controller's answer if it has something new to decide on, else None (fly on)."""
        controller = self.controller
        if controller.declared is not None:
            return controller.declared
        here = self.here()
        height = -self.positions[-1][3]
        arrived = (controller.target is not None and math.dist(here, controller.target) <= self.arrival_m
                   and abs(height - self._goal_height_m) <= self.arrival_m)
        if controller.observations == self._stepped_at and not arrived:
            return None
        self._stepped_at = controller.observations
        move = controller.step(here, self.path_m, arrived)
        if isinstance(move, Goto):
            self._goal_height_m = self.geometry.survey_alt_m if move.height_m is None else move.height_m
        return move

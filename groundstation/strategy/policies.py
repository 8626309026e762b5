"""Policies: where to fly next. One small interface, the belief-driven planners and the baselines
of docs/strategy.md, each implemented to do its job as well as its idea allows.

    policy.reset(geometry, start, rng)         before an episode
    policy.observe(n, e, z)                    every reading (most policies ignore it)
    policy.next_waypoint(belief, position)     -> (n, e), or None when there is nothing more to do
    policy.wants_replan(readings_since)        re-decide before reaching the waypoint?
    policy.declaration(belief)                 -> (n, e) to report, or None for the belief's choice
    policy.uses_stopping_rule                  False: ignores the belief's confidence (pure coverage)

Policies:
  gig        information gain per distance (planner.py, d0 = 50 m), replanning every 4 readings
  infotaxis  information gain alone over the same candidates, re-deciding on arrival only: with no
             distance term, re-deciding every 4 readings made it chase a different far point each
             time, on the noise of the estimates, and circle mid-area (200 G episodes: 2178 m mean
             path, 83 % success; on arrival: about 900 m and 100 % on validation episodes)
  greedy     fly to the most likely cell (re-targeted every reading)
  lawnmower  boustrophedon lanes spaced for detection, switching to gig at the first strong reading
  zigzag     pure coverage, 30 m lanes, declares the cell of the hottest reading at the end
  random     random walk: straight legs of random heading
  gradient   run-and-tumble on the slope of the readings along each leg
All policies except zigzag declare by the same stopping rule on the same belief.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from .belief import Belief, Geometry
from .planner import Planner, PlannerConfig

GIG_REPLAN_EVERY = 4  # readings between re-decisions (20 m at 5 m/s and 1 reading/s)


class Policy:
    name = "policy"
    uses_stopping_rule = True
    replan_every: int | None = None
    # a thermal camera's ground rectangle (north, east) [m], set before reset(): the planners then
    # also score what a frame at each candidate would tell (planner.py, frame_gains)
    footprint_m: tuple | None = None

    def reset(self, geometry: Geometry, start, rng: np.random.Generator) -> None:
        self.geometry = geometry
        self.rng = rng

    def observe(self, n: float, e: float, z: float) -> None:
        pass

    def next_waypoint(self, belief: Belief, position) -> tuple[float, float] | None:
        raise NotImplementedError

    def wants_replan(self, readings_since_decision: int) -> bool:
        return self.replan_every is not None and readings_since_decision >= self.replan_every

    def declaration(self, belief: Belief) -> tuple[float, float] | None:
        return None

    def _clip(self, n: float, e: float) -> tuple[float, float]:
        a = self.geometry.area_m
        return (min(a, max(0.0, float(n))), min(a, max(0.0, float(e))))


class PlannerPolicy(Policy):
    """gig (d0 given) or infotaxis (d0 None) over the planner's candidates."""

    def __init__(self, name: str = "gig", config: PlannerConfig | None = None,
                 replan_every: int | None = GIG_REPLAN_EVERY):
        self.name = name
        self.config = config or PlannerConfig()
        self.replan_every = replan_every

    def reset(self, geometry, start, rng):
        super().reset(geometry, start, rng)
        self.planner = Planner(geometry, dataclasses.replace(self.config, footprint_m=self.footprint_m), rng)

    def next_waypoint(self, belief, position):
        return self.planner.choose(belief, position)


class Greedy(Policy):
    """Fly to the most likely cell; once there, to the most likely cell outside its 3 x 3 block."""
    name = "greedy"
    replan_every = 1

    def next_waypoint(self, belief, position):
        target, index = belief.most_likely()
        if math.hypot(target[0] - position[0], target[1] - position[1]) >= belief.cell_m / 2:
            return target
        grid = belief.probabilities()
        i, j = index
        grid[max(0, i - 1):i + 2, max(0, j - 1):j + 2] = -1.0
        k = int(np.argmax(grid))
        return self.geometry.centre_of(divmod(k, belief.size))


def lanes(area_m: float, spacing_m: float, start, east_m: tuple | None = None) -> list[tuple[float, float]]:
    """Boustrophedon waypoints: lanes along north, at most spacing_m apart, inset by half a spacing,
    beginning at whichever of the four lane-end corners is nearest to start; over the whole area,
    or over the strip east_m = (lo, hi) of it."""
    east_lo, east_hi = east_m or (0.0, area_m)
    count = max(1, math.ceil((east_hi - east_lo) / spacing_m - 1e-9))
    step = (east_hi - east_lo) / count
    east = [east_lo + (k + 0.5) * step for k in range(count)]
    lo, hi = min(step / 2, area_m / 2), max(area_m - step / 2, area_m / 2)
    best = None
    for east_order in (east, east[::-1]):
        for north_first in (lo, hi):
            pts, n0 = [], north_first
            for e in east_order:
                n1 = hi if n0 == lo else lo
                pts += [(n0, e), (n1, e)]
                n0 = n1
            d = math.hypot(pts[0][0] - start[0], pts[0][1] - start[1])
            if best is None or d < best[0]:
                best = (d, pts)
    return best[1]


def detection_radius(geometry: Geometry, weak_strength_k: float = 20.0, sigmas: float = 4.0) -> float:
    """Horizontal range within which a weak fire raises the reading by `sigmas` noise sigmas."""
    from firefly.sim.fire import kernel_value
    sigma = max(geometry.noise_k, 0.01)
    need = sigmas * sigma / weak_strength_k  # kernel value needed
    if need >= 1.0:
        return geometry.cell_size_m
    lo, hi = 0.0, 4.0 * geometry.area_m
    for _ in range(60):  # the kernels fall monotonically with distance
        mid = (lo + hi) / 2
        if kernel_value(geometry.kernel, mid * mid, geometry.survey_alt_m, geometry.plume_sigma_m) >= need:
            lo = mid
        else:
            hi = mid
    return max(lo, geometry.cell_size_m)


class Lawnmower(Policy):
    """Lanes spaced 2 x the detection radius of a weak (20 K) fire at 4 sigma, until a reading stands
    3 sigma above the running median of the readings so far; from then on, the gig planner.

    At 30 m and 1 K that radius is 60 m (R) and 45 m (G): lanes 100 m and 80 m apart over 400 m,
    routes of about 1.6 and 2.0 km. 30 m lanes would be a coverage survey (that is zigzag); wider
    ones could pass a weak fire by without a strong reading."""
    name = "lawnmower"

    def __init__(self, spacing_m: float | None = None, trigger_sigmas: float = 3.0, min_readings: int = 5,
                 config: PlannerConfig | None = None):
        self.spacing_m = spacing_m
        self.trigger_sigmas = trigger_sigmas
        self.min_readings = min_readings
        self.config = config or PlannerConfig()

    def reset(self, geometry, start, rng):
        super().reset(geometry, start, rng)
        spacing = self.spacing_m or 2.0 * detection_radius(geometry)
        self.lane_spacing_m = min(spacing, geometry.area_m)
        self.route = lanes(geometry.area_m, self.lane_spacing_m, start)
        self.next_index = 0
        self.readings: list[float] = []
        self.switched = False
        self.switch_pending = False
        self.replan_every = None
        self.planner = Planner(geometry, dataclasses.replace(self.config, footprint_m=self.footprint_m), rng)

    def observe(self, n, e, z):
        if not self.switched and len(self.readings) >= self.min_readings:
            if z > float(np.median(self.readings)) + self.trigger_sigmas * max(self.geometry.noise_k, 0.01):
                self.switched = self.switch_pending = True
                self.replan_every = GIG_REPLAN_EVERY
        self.readings.append(z)

    def wants_replan(self, readings_since_decision):
        if self.switch_pending:
            return True
        return super().wants_replan(readings_since_decision)

    def next_waypoint(self, belief, position):
        self.switch_pending = False
        if self.switched:
            return self.planner.choose(belief, position)
        if self.next_index >= len(self.route):
            # covered without a strong reading: let the belief finish the job
            self.switched, self.replan_every = True, GIG_REPLAN_EVERY
            return self.planner.choose(belief, position)
        wp = self.route[self.next_index]
        self.next_index += 1
        return wp


class Zigzag(Policy):
    """Pure coverage with lanes at most 30 m apart; declares the cell of the hottest reading."""
    name = "zigzag"
    uses_stopping_rule = False

    def __init__(self, spacing_m: float = 30.0):
        self.spacing_m = spacing_m

    def reset(self, geometry, start, rng):
        super().reset(geometry, start, rng)
        self.route = lanes(geometry.area_m, self.spacing_m, start)
        self.next_index = 0
        self.hottest = (-math.inf, start)

    def observe(self, n, e, z):
        if z > self.hottest[0]:
            self.hottest = (z, (n, e))

    def next_waypoint(self, belief, position):
        if self.next_index >= len(self.route):
            return None
        wp = self.route[self.next_index]
        self.next_index += 1
        return wp

    def declaration(self, belief):
        n, e = self.hottest[1]
        return self.geometry.centre_of(self.geometry.cell_of(n, e))


class RandomWalk(Policy):
    """Straight legs of random heading and length (uniform 25-75 m), kept inside the area."""
    name = "random"

    def __init__(self, leg_m: float = 50.0):
        self.leg_m = leg_m

    def next_waypoint(self, belief, position):
        for _ in range(20):
            heading = self.rng.uniform(0, 2 * math.pi)
            length = self.rng.uniform(0.5, 1.5) * self.leg_m
            n, e = self._clip(position[0] + length * math.cos(heading), position[1] + length * math.sin(heading))
            if math.hypot(n - position[0], e - position[1]) >= self.leg_m / 4:
                return n, e
        return self._clip(self.geometry.area_m / 2, self.geometry.area_m / 2)


class Gradient(Policy):
    """Run and tumble: fly legs of leg_m; after each, fit the slope of the readings against the
    distance flown along the leg. Rising: keep the heading (jittered by up to +-20 deg). Falling or
    flat: tumble to a random heading. Legs that would leave the area are turned back inside."""
    name = "gradient"

    def __init__(self, leg_m: float = 30.0, jitter_deg: float = 20.0):
        self.leg_m = leg_m
        self.jitter = math.radians(jitter_deg)

    def reset(self, geometry, start, rng):
        super().reset(geometry, start, rng)
        self.heading = None
        self.leg: list[tuple[float, float, float]] = []

    def observe(self, n, e, z):
        self.leg.append((n, e, z))

    def _slope(self) -> float:
        if len(self.leg) < 3:
            return 0.0
        arr = np.array(self.leg)
        s = (arr[:, 0] - arr[0, 0]) * math.cos(self.heading) + (arr[:, 1] - arr[0, 1]) * math.sin(self.heading)
        if np.ptp(s) <= 0:
            return 0.0
        return float(np.polyfit(s, arr[:, 2], 1)[0])

    def next_waypoint(self, belief, position):
        if self.heading is None or self._slope() <= 0:
            self.heading = self.rng.uniform(0, 2 * math.pi)
        else:
            self.heading += self.rng.uniform(-self.jitter, self.jitter)
        for _ in range(20):
            n = position[0] + self.leg_m * math.cos(self.heading)
            e = position[1] + self.leg_m * math.sin(self.heading)
            a = self.geometry.area_m
            if 0 <= n <= a and 0 <= e <= a:
                break
            self.heading = self.rng.uniform(0, 2 * math.pi)
        self.leg = self.leg[-1:]
        return self._clip(n, e)


POLICIES = {
    "gig": lambda: PlannerPolicy("gig", PlannerConfig()),
    "infotaxis": lambda: PlannerPolicy("infotaxis", PlannerConfig(d0_m=None), replan_every=None),
    "greedy": Greedy,
    "lawnmower": Lawnmower,
    "zigzag": Zigzag,
    "random": RandomWalk,
    "gradient": Gradient,
}


def make_policy(name: str) -> Policy:
    try:
        return POLICIES[name]()
    except KeyError:
        raise ValueError(f"unknown policy {name!r} (known: {', '.join(POLICIES)})") from None

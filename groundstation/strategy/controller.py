"""The search controller: the fire search's decisions as one sans-IO object, driven the same way by
the decision-level episodes (evaluation/episodes.py) and by the flight (flight/explore.py).

    controller = SearchController(geometry, policy, config, start, rng)  # resets the policy
    controller.observe(n, e, z, height_m)       every observation
    controller.step(position, path_m, arrived)  -> Goto(target, confirming) or a Declaration

In: observations (a position, its height above ground and a temperature) and, at each decision
point, where the vehicle is, how far it has flown and whether it has just reached its target.
Out: where to fly, or the declaration. The controller owns everything in between: the belief, the
stopping rule and its confirmation step, the policy (reset here, before any observation reaches it),
the count of observations since the last decision that a policy's replanning is measured in, the
policy's own declaration (zigzag reports its hottest reading) and the snapping of the declared point
to its cell's centre. The drivers own time, motion, the sensor and the link.

Declaring, in this order at every step:
  1. the belief is confident (stopping.py: 3 x 3 mass >= threshold, confirmed when confirm_m is
     set) -> declared "confident", unless the policy ignores the belief (zigzag);
  2. the path budget is spent, or the observations exceed what the budget allows four times over
     (a policy that never moves) -> declared "budget", the belief's best block;
  3. confident but not confirmed -> fly over the cell's centre; when the readings on the way
     overturn the belief, the policy takes over again;
  4. on arrival, or when the policy asks to replan, the policy names the next waypoint; a policy
     with nothing more to do ends the search -> declared "end".

Threshold 0.99 with confirmation within 10 m: a calibrated belief declared at mass t is wrong about
1 - t of the time, a little more in practice, as the declaration is taken at the first reading that
crosses the threshold. Measured with gig on validation episodes (seed 1, episodes 100-299, not the
reported ones): 0.95 alone was wrong in 3-4 % (R), 0.95 with confirmation in 0.5 % (R and G), 0.99
with confirmation never, for about 3 m more mean path than 0.95 with confirmation.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from .belief import Belief, Geometry
from .policies import Policy
from .stopping import Declaration, StoppingRule


@dataclass(frozen=True)
class SearchConfig:
    """What the search decides by; the defaults are the ones EVALUATION.md reports."""
    speed_m_s: float = 5.0          # survey speed
    sample_s: float = 1.0           # one observation per sample_s, i.e. per speed x sample_s metres
    threshold: float = 0.99         # 3 x 3 block mass that declares (the stopping rule's own default: 0.95)
    budget_m: float = 6000.0        # path flown before a forced declaration
    prior_strength_mean_k: float = 50.0
    prior_strength_sd_k: float = 25.0
    subcells: int = 3               # sub-positions per cell side in the belief
    confirm_m: float | None = 10.0  # declare after a reading this close to the cell's centre; None: at once
    outlier_rate: float = 0.02      # the belief's prior share of wild readings (belief.py, "Outliers")
    outlier_range_k: float = 100.0  # the span a wild reading may take anywhere in [K]

    def __post_init__(self):
        if not (self.speed_m_s > 0 and self.sample_s > 0):
            raise ValueError("speed and sample interval must be positive")
        if not self.budget_m > 0:
            raise ValueError("budget_m must be positive")

    @property
    def observation_spacing_m(self) -> float:
        """Track between two observations at the survey speed."""
        return self.speed_m_s * self.sample_s


@dataclass(frozen=True)
class Goto:
    target: tuple[float, float]  # (n, e) local metres
    confirming: bool             # flying over the cell the belief is confident about


class SearchController:
    def __init__(self, geometry: Geometry, policy: Policy, config: SearchConfig, start,
                 rng: np.random.Generator, timer: Callable[[], float] | None = None,
                 wind_ne_m_s: tuple = (0.0, 0.0)):
        """`timer`, if given (a clock in seconds), times every decision of the policy;
        `wind_ne_m_s`, the wind the vehicle reports (where the air goes, m/s): the plume leans with it."""
        self.geometry = geometry
        self.policy = policy
        self.config = config
        self.belief = Belief(geometry, config.prior_strength_mean_k, config.prior_strength_sd_k,
                             subcells=config.subcells, outlier_rate=config.outlier_rate,
                             outlier_range_k=config.outlier_range_k, wind_ne_m_s=wind_ne_m_s)
        self.rule = StoppingRule(config.threshold, 1, config.confirm_m)
        self.timer = timer
        self.max_observations = int(4 * config.budget_m / config.observation_spacing_m) + 100
        self.observations = 0
        self.decisions = 0
        self.decision_s: list[float] = []  # with a timer: the duration of every decision
        self.target: tuple[float, float] | None = None
        self.confirming = False
        self.declared: Declaration | None = None
        self._need_decision = True
        self._since_decision = 0
        policy.reset(geometry, (float(start[0]), float(start[1])), rng)

    def observe(self, n: float, e: float, z: float, height_m: float) -> None:
        """One observation: a temperature z at (n, e), height_m above ground. Ignored once declared."""
        if self.declared is not None:
            return
        self.belief.update(n, e, z, height_m)
        self.policy.observe(n, e, z)
        self.observations += 1
        self._since_decision += 1
        if not self._need_decision and self.policy.wants_replan(self._since_decision):
            self._need_decision = True

    def step(self, position, path_m: float, arrived: bool = False) -> Goto | Declaration:
        """Where to fly from `position` after `path_m` metres of search, or the declaration (then
        every later step returns it again). `arrived`: the vehicle has reached the last target."""
        if self.declared is not None:
            return self.declared
        if self.observations == 0:
            raise RuntimeError("step() before any observation: the search starts with a reading")
        if arrived:
            self._need_decision = True
        uses_belief = self.policy.uses_stopping_rule
        if uses_belief:
            found = self.rule.confident(self.belief)
            if found is not None:
                return self._declare(found, "confident")
        if path_m >= self.config.budget_m or self.observations >= self.max_observations:
            return self._declare(self.rule.force(self.belief, "budget"), "budget")
        if uses_belief and self.config.confirm_m is not None:
            check = self.rule.to_confirm(self.belief)
            if check is not None:  # confident but not yet flown over: go and look
                self.target, self.confirming, self._need_decision = check, True, False
            elif self.confirming:  # the readings on the way overturned it: back to the policy
                self.confirming, self._need_decision = False, True
        if self._need_decision:
            waypoint = self._decide(position)
            if waypoint is None:
                return self._declare(self.rule.force(self.belief, "end"), "end")
            self.target = waypoint
        return Goto(self.target, self.confirming)

    def _decide(self, position) -> tuple[float, float] | None:
        t0 = self.timer() if self.timer else 0.0
        waypoint = self.policy.next_waypoint(self.belief, position)
        if self.timer:
            self.decision_s.append(self.timer() - t0)
        self.decisions += 1
        self._since_decision, self._need_decision = 0, False
        if waypoint is None:
            return None
        n, e = float(waypoint[0]), float(waypoint[1])
        a = self.geometry.area_m
        if not (0 <= n <= a and 0 <= e <= a and math.isfinite(n) and math.isfinite(e)):
            raise RuntimeError(f"policy {self.policy.name} chose a waypoint outside the area: {(n, e)}")
        return n, e

    def _declare(self, found: Declaration, reason: str) -> Declaration:
        """The policy's own point if it has one, else the stopping rule's; snapped to its cell's centre."""
        own = self.policy.declaration(self.belief)
        point = found.position if own is None else (float(own[0]), float(own[1]))
        index = self.geometry.cell_of(*point)
        forced = reason == "budget" or (reason != "confident" and self.policy.uses_stopping_rule)
        self.declared = Declaration(self.geometry.centre_of(index), index, self.belief.mass_around(index, 1),
                                    forced, reason)
        return self.declared

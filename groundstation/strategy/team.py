"""Several vehicles, one search: a shared belief, one stopping rule, a target for every vehicle.

    team = TeamController(geometry, policy, config, starts, rng)
    team.observe(i, n, e, z, height_m)            every reading of vehicle i
    team.step(positions, paths, arrived)          -> a list of Goto (one per vehicle, None for a
                                                     vehicle out of the search) or the Declaration
    team.drop(i)                                  vehicle i has failed: the others go on

Every vehicle's readings, each with its own height, update the one belief; the stopping rule is the
team's, and the active vehicle nearest the cell it is confident about flies over it to confirm.
Vehicles fly at separated survey heights (ALTITUDE_STEP_M apart), which is what keeps them apart:
their tracks may cross. The joint planner also never gives two vehicles targets closer than
SEPARATION_M; the baselines do not look at each other's targets (independent planners may pick
the same one).

Team policies (the issue's planner and its two baselines):
  joint        sequential greedy allocation over the gig planner's candidates: one estimate of the
               information gain of a reading at every candidate, then vehicle by vehicle the best
               score (gain per distance, as gig), each candidate's gain discounted by how much of it
               the other vehicles' targets already take: x (1 - exp(-d^2 / 2 L^2)) per other target
               at distance d, L = FOOTPRINT_M. With one vehicle it is exactly gig.
  independent  k gig planners over the shared belief, each choosing as if alone
  strips       the area cut into k strips along east; each vehicle mows its own, switching to its
               own gig planner at its first strong reading (as the one-vehicle lawnmower does)
"""
from __future__ import annotations

import math
from typing import Callable

import numpy as np

from .belief import Belief, Geometry
from .controller import Goto, SearchConfig
from .planner import Planner, PlannerConfig
from .policies import GIG_REPLAN_EVERY, detection_radius, lanes
from .stopping import Declaration, StoppingRule

SEPARATION_M = 10.0    # the joint planner gives no two vehicles targets closer than this
ALTITUDE_STEP_M = 5.0  # vehicle i surveys this much higher than vehicle i - 1
# How far apart two readings still tell about the same cells. The plume's width (25 m) was the
# first guess; on the tuning seed (seed 1, 100 episodes, R, three vehicles from spread starts) it
# cost time: 42.2 s to declaration at 25 m, 40.7 s at 10 m, 40.5 s at 5 m (independent planners:
# 41.1 s). The shared belief already tells a vehicle what the others have read; a cell is 10 m.
FOOTPRINT_M = 10.0


def survey_heights(geometry: Geometry, k: int) -> list[float]:
    return [geometry.survey_alt_m + ALTITUDE_STEP_M * i for i in range(k)]


class TeamPolicy:
    name = "team"
    uses_stopping_rule = True

    def reset(self, geometry: Geometry, starts: list, rng: np.random.Generator) -> None:
        self.geometry, self.rng, self.k = geometry, rng, len(starts)

    def observe(self, i: int, n: float, e: float, z: float) -> None:
        pass

    def wants_replan(self, i: int, readings_since: int) -> bool:
        return readings_since >= GIG_REPLAN_EVERY

    def assign(self, belief: Belief, positions: list, targets: list, needs: list[int]) -> dict[int, tuple | None]:
        """New targets for the vehicles in `needs` (the others keep theirs, in `targets`)."""
        raise NotImplementedError


class JointGig(TeamPolicy):
    name = "joint"

    def __init__(self, config: PlannerConfig | None = None):
        self.config = config or PlannerConfig()

    def reset(self, geometry, starts, rng):
        super().reset(geometry, starts, rng)
        self.planners = [Planner(geometry, self.config, rng) for _ in starts]

    def assign(self, belief, positions, targets, needs):
        active = [i for i, t in enumerate(targets) if t is not None or i in needs]
        if len(active) == 1:  # one vehicle: the gig planner's own choice
            (i,) = needs
            return {i: self.planners[i].choose(belief, positions[i])}
        planner = self.planners[needs[0]]
        pts = np.unique(np.vstack([self.planners[i].candidates(belief, positions[i]) for i in needs]), axis=0)
        gains = planner.gains(belief, pts)  # one estimate for all: the vehicles compare alike futures
        held = {j: targets[j] for j in range(len(targets)) if j not in needs and targets[j] is not None}
        out = {}
        for i in needs:
            others = [np.asarray(t) for j, t in (held | out).items() if j != i]
            pos = np.asarray(positions[i], dtype=float)
            dist = np.hypot(pts[:, 0] - pos[0], pts[:, 1] - pos[1])
            discount = np.ones(len(pts))
            too_close = np.zeros(len(pts), dtype=bool)
            for t in others:
                d = np.hypot(pts[:, 0] - t[0], pts[:, 1] - t[1])
                discount *= 1.0 - np.exp(-d * d / (2.0 * FOOTPRINT_M ** 2))
                too_close |= d < SEPARATION_M
            # excluded after the discount: -inf times a candidate's zero discount is NaN, which
            # would make the best score NaN and leave the vehicle standing
            score = planner.score(gains, dist) * discount
            score[too_close] = -np.inf
            best = score.max()
            if not np.isfinite(best):  # boxed in by the others: stay
                out[i] = (float(pos[0]), float(pos[1]))
                continue
            tied = np.flatnonzero(score >= best - 1e-12 * max(1.0, abs(best)))
            k = int(tied[np.argmin(dist[tied])])
            own = self.planners[i]
            if own.target is not None and self.config.keep_target > 1.0:
                same = np.flatnonzero(np.all(np.abs(pts - own.target) < 1e-6, axis=1))
                if same.size and score[same[0]] * self.config.keep_target >= best:
                    k = int(same[0])
            own.target = pts[k].copy()
            out[i] = (float(pts[k, 0]), float(pts[k, 1]))
        return out


class IndependentGig(TeamPolicy):
    name = "independent"

    def reset(self, geometry, starts, rng):
        super().reset(geometry, starts, rng)
        self.planners = [Planner(geometry, PlannerConfig(), rng) for _ in starts]

    def assign(self, belief, positions, targets, needs):
        return {i: self.planners[i].choose(belief, positions[i]) for i in needs}


class Strips(TeamPolicy):
    name = "strips"
    TRIGGER_SIGMAS, MIN_READINGS = 3.0, 5

    def reset(self, geometry, starts, rng):
        super().reset(geometry, starts, rng)
        k, area = len(starts), geometry.area_m
        spacing = min(2.0 * detection_radius(geometry), area / k)
        self.routes = [lanes(area, spacing, starts[i], (area * i / k, area * (i + 1) / k)) for i in range(k)]
        self.next_index = [0] * k
        self.readings: list[list[float]] = [[] for _ in starts]
        self.switched = [False] * k
        self.switch_pending = [False] * k
        self.planners = [Planner(geometry, PlannerConfig(), rng) for _ in starts]

    def observe(self, i, n, e, z):
        seen = self.readings[i]
        if not self.switched[i] and len(seen) >= self.MIN_READINGS:
            if z > float(np.median(seen)) + self.TRIGGER_SIGMAS * max(self.geometry.noise_k, 0.01):
                self.switched[i] = self.switch_pending[i] = True
        seen.append(z)

    def wants_replan(self, i, readings_since):
        return self.switch_pending[i] or (self.switched[i] and readings_since >= GIG_REPLAN_EVERY)

    def assign(self, belief, positions, targets, needs):
        out = {}
        for i in needs:
            self.switch_pending[i] = False
            if not self.switched[i] and self.next_index[i] >= len(self.routes[i]):
                self.switched[i] = True  # its strip covered without a strong reading: the belief finishes
            if self.switched[i]:
                out[i] = self.planners[i].choose(belief, positions[i])
            else:
                out[i] = self.routes[i][self.next_index[i]]
                self.next_index[i] += 1
        return out


TEAM_POLICIES = {"joint": JointGig, "independent": IndependentGig, "strips": Strips}


def make_team_policy(name: str) -> TeamPolicy:
    return TEAM_POLICIES[name]()


class TeamController:
    """SearchController's one-fire search (controller.py) with a team: the same order of checks
    at every step (confident -> declare; budget -> forced; confident but unconfirmed -> the nearest
    vehicle flies over the cell; then new targets for the vehicles that need one)."""

    def __init__(self, geometry: Geometry, policy: TeamPolicy, config: SearchConfig, starts: list,
                 rng: np.random.Generator, timer: Callable[[], float] | None = None,
                 wind_ne_m_s: tuple = (0.0, 0.0)):
        if config.max_fires != 1:
            raise ValueError("a team searches for one fire (max_fires 1)")
        self.geometry, self.policy, self.config, self.timer = geometry, policy, config, timer
        self.k = len(starts)
        self.belief = Belief(geometry, config.prior_strength_mean_k, config.prior_strength_sd_k,
                             subcells=config.subcells, outlier_rate=config.outlier_rate,
                             outlier_range_k=config.outlier_range_k, wind_ne_m_s=wind_ne_m_s)
        self.rule = StoppingRule(config.threshold, 1, config.confirm_m)
        self.max_observations = self.k * (int(4 * config.budget_m / config.observation_spacing_m) + 100)
        self.observations = 0
        self.decisions = 0
        self.decision_s: list[float] = []
        self.active = [True] * self.k
        self.targets: list[tuple | None] = [None] * self.k
        self.need = [True] * self.k
        self.since = [0] * self.k
        self.confirmer: int | None = None  # the vehicle flying over the cell to confirm it
        self.declared: Declaration | None = None
        self.finished_by: str | None = None
        policy.reset(geometry, [(float(s[0]), float(s[1])) for s in starts], rng)

    def observe(self, i: int, n: float, e: float, z: float, height_m: float) -> None:
        if self.declared is not None or not self.active[i]:
            return
        self.belief.update(n, e, z, height_m)
        self.policy.observe(i, n, e, z)
        self.observations += 1
        self.since[i] += 1
        if not self.need[i] and self.policy.wants_replan(i, self.since[i]):
            self.need[i] = True

    def drop(self, i: int) -> None:
        """Vehicle i has failed (a motor, its battery, its link): no more targets for it."""
        self.active[i], self.targets[i], self.need[i] = False, None, False
        if self.confirmer == i:
            self.confirmer = None
        if not any(self.active):
            self.declared = self._declare(self.rule.force(self.belief, "budget"), "budget")

    def step(self, positions: list, paths: list, arrived: list) -> list[Goto | None] | Declaration:
        if self.declared is not None:
            return self.declared
        if self.observations == 0:
            raise RuntimeError("step() before any observation: the search starts with a reading")
        for i in range(self.k):
            if arrived[i] and self.active[i]:
                self.need[i] = True
        found = self.rule.confident(self.belief)
        if found is not None:
            return self._declare(found, "confident")
        if max(paths) >= self.config.budget_m or self.observations >= self.max_observations:
            return self._declare(self.rule.force(self.belief, "budget"), "budget")
        if self.config.confirm_m is not None:
            check = self.rule.to_confirm(self.belief)
            if check is not None:
                if self.confirmer is None:
                    self.confirmer = min((i for i in range(self.k) if self.active[i]),
                                         key=lambda i: math.dist(positions[i], check))
                self.targets[self.confirmer], self.need[self.confirmer] = check, False
            elif self.confirmer is not None:  # the readings on the way overturned it
                self.need[self.confirmer], self.confirmer = True, None
        needs = [i for i in range(self.k) if self.active[i] and self.need[i] and i != self.confirmer]
        if needs:
            chosen = self._decide(positions, needs)
            if any(t is None for t in chosen.values()):
                return self._declare(self.rule.force(self.belief, "end"), "end")
            for i, t in chosen.items():
                self.targets[i] = t
        return [Goto(self.targets[i], i == self.confirmer) if self.active[i] else None for i in range(self.k)]

    def _decide(self, positions: list, needs: list[int]) -> dict:
        t0 = self.timer() if self.timer else 0.0
        chosen = self.policy.assign(self.belief, positions, list(self.targets), needs)
        if self.timer:
            self.decision_s.append(self.timer() - t0)
        self.decisions += 1
        a = self.geometry.area_m
        for i, t in chosen.items():
            self.since[i], self.need[i] = 0, False
            if t is None:
                continue
            n, e = float(t[0]), float(t[1])
            if not (0 <= n <= a and 0 <= e <= a and math.isfinite(n) and math.isfinite(e)):
                raise RuntimeError(f"team policy {self.policy.name} chose a waypoint outside the area: {(n, e)}")
            chosen[i] = (n, e)
        return chosen

    def _declare(self, found: Declaration, reason: str) -> Declaration:
        index = self.geometry.cell_of(*found.position)
        self.declared = Declaration(self.geometry.centre_of(index), index, self.belief.mass_around(index, 1),
                                    reason != "confident", reason)
        self.finished_by = reason
        return self.declared

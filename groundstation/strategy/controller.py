"""The search controller: the fire search's decisions as one sans-IO object, driven the same way by
the decision-level episodes (evaluation/episodes.py) and by the flight (flight/explore.py).

    controller = SearchController(geometry, policy, config, start, rng)  # resets the policy
    controller.observe(n, e, z, height_m)       every observation
    controller.observe_lean(velocity, lean)     steady flight, when the search estimates the wind
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

Several fires (config.max_fires > 1; docs/strategy.md, "Several fires"): a confident block is a
find, not the end. The finds are kept (relocated with each other explained away, their hot spots
fitted to the readings), the vehicle flies a cross over the new one, and the search goes on over a
belief rebuilt with the finds known and a "no further fire" hypothesis; where the sensor sees
farther from higher up, it first climbs over the find to look for any other fire from above
(_climbing). max_fires None: the search is not told how many fires there are. It ends with
max_fires finds ("confident"), confident there is no other ("clear"), or at the budget or the
policy's end;
`declarations` then lists every find (a forced one only when there is none and it did not end
clear), `finished_by` says why it ended, and step() returns the first.

Wind (wind_estimate.py): the plume leans with the wind, and the belief with it. Told the wind
(wind_ne_m_s, e.g. from the vehicle's WIND message), the controller keeps it. Given None, it
estimates the wind from how the vehicle leans in steady flight (observe_lean): each time the estimate
moves by more than WIND_REBUILD_M_S the belief is rebuilt from every reading with the new wind (a
job, below), and while that rebuild runs or while the lean the estimate leaves open at the survey
height is more than half a cell, the search neither declares a fire nor ends "clear": it flies on
instead of naming a cell the lean may have moved.

Thinking spread over steps (issue 30, item 4: at most 150 ms a step): what costs more than a step
may think is a job (_jobs), a generator that a step works through JOB_CHUNKS_PER_STEP chunks of
(one in a step that has fitted or decided already, or with HEAVY_KNOWN fires known), each about
20 ms here: the belief rebuilt from
every reading with a new wind or with the finds as they are ("rebuild"), the finds refitted every
REFRESH_EVERY observations and the belief rebuilt if one moved ("refit"), and what a find changes
("find": the earlier finds relocated, the finds fitted together, then the rebuild). The belief in
use steers until its successor has every reading, those taken meanwhile too. Until a find's job
and the rebuild after a "rebuild" are done the search neither declares nor ends; a refit's finds
have only moved a little, and the search judges on. The vehicle holds over a find while its job
runs, at the end of the cross over it until the belief knows where it is, and over a confident
cell while the rebuild with the finds put right runs: flown on by the belief before, it went
after the fire it had just pinned down. decision_s times every step that thinks, whole (its fit,
its policy decision and its chunks); observe() costs one reading's update on top, measured apart.

Threshold 0.99 with confirmation within 10 m: a calibrated belief declared at mass t is wrong about
1 - t of the time, a little more in practice, as the declaration is taken at the first reading that
crosses the threshold. Measured with gig on validation episodes (seed 1, episodes 100-299, not the
reported ones): 0.95 alone was wrong in 3-4 % (R), 0.95 with confirmation in 0.5 % (R and G), 0.99
with confirmation never, for about 3 m more mean path than 0.95 with confirmation.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Iterator

import numpy as np

from .belief import PLUME_RISE_M_S, Belief, Geometry
from .frame import FrameObservation, frame_log_likelihood
from .policies import Policy
from .refine import FINAL_REACH_CELLS, REACH_CELLS, fit_hot_spots
from .stopping import Declaration, StoppingRule
from .wind_estimate import LeanWindEstimator


# Several fires: the finds' hot spots are refitted to the readings every REFRESH_EVERY observations
# and before a new find is accepted; the belief is rebuilt when one has moved more than REFRESH_M.
REFRESH_EVERY = 10
REFRESH_M = 1.0
# A find the joint fit gives less strength than this was another fire's tail, not a fire: it goes.
# Measured on two-fire worlds: such ghosts fitted at 0.6-1.2 K, the finds on fires at 12 K and more;
# the prior puts 96 % of fires above it.
GHOST_BELOW_K = 5.0
PIN_M = 30.0  # after a find with more to look for: a cross this far either way over it (_pin_pattern)
# ... and first, where the sensor sees farther from higher up, a climb over the find to this height
# (400 ft, the usual ceiling) with RULE_OUT_HOVER observations at the top: from there every corner
# of the area is in view, and a profile of readings at many heights tells a further fire, whose
# share grows with height, from the ambient, which does not change.
RULE_OUT_HEIGHT_M = 120.0
RULE_OUT_HOVER = 20
DROP_CLIMB_READINGS = True
# Estimating the wind: the belief is rebuilt with the estimate when it has moved this far from the
# wind the belief holds; the estimate is looked at every WIND_CHECK_EVERY lean samples.
WIND_REBUILD_M_S = 0.25
WIND_CHECK_EVERY = 5
# Bounded thinking: the belief's rebuilds and a find's relocations are jobs (_jobs) that a step
# works through a few chunks of, each about 20 ms here: JOB_ROWS readings of a rebuild's weighted
# pass (Belief.absorbing) or of the readings that came in meanwhile (Belief.update_together); with
# no known fire, PLAIN_UPDATES readings one by one (about 1 ms each)
JOB_CHUNKS_PER_STEP = 2  # ... or one in a step that has fitted, none in one the policy has decided in
# With this many known fires a chunk costs about twice as much (its fits have nine nuisance columns
# per hypothesis, 37 ms each): one chunk a step. Two such chunks took up to 161 ms (three fires).
HEAVY_KNOWN = 3
JOB_ROWS = 25
PLAIN_UPDATES = 10
# ... for this many hypotheses (a 40 x 40 grid of 3 x 3 sub-positions). A belief with known fires
# over several plume leans (a wind estimated) holds a multiple of them: its chunks have that many
# times fewer readings (with three leans a chunk of 25 took up to 490 ms), and as its fits cost as
# much more, a step works one of them.
REFERENCE_HYPOTHESES = 14_400
FRAME_CHUNK = 10  # thermal frames a rebuild's chunk adds (a frame's likelihood: about 1 ms per 14,400 hypotheses)


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
    max_fires: int | None = 1       # fires to look for; above 1 the search goes on after a find (below);
                                    # None: as many as there are (the search is not told)
    null_prior: float = 0.5         # with max_fires > 1: prior probability that there is no fire at all
    further_prior: float = 0.5      # ... and, once one is found, that there is no further one: the
                                    # balance between ruling a second fire out and missing one
                                    # (EVALUATION.md, "How many fires: the balance")
    clear_threshold: float = 0.98   # ... and the probability of none that ends the search ("clear")

    def __post_init__(self):
        if not (self.speed_m_s > 0 and self.sample_s > 0):
            raise ValueError("speed and sample interval must be positive")
        if not self.budget_m > 0:
            raise ValueError("budget_m must be positive")
        if self.max_fires is not None and (int(self.max_fires) != self.max_fires or self.max_fires < 1):
            raise ValueError(f"max_fires must be a positive whole number, got {self.max_fires!r}")
        if not 0.0 < self.clear_threshold <= 1.0:
            raise ValueError(f"clear_threshold must be within 0..1 (0 excluded), got {self.clear_threshold!r}")
        for name in ("null_prior", "further_prior"):
            if not 0.0 < getattr(self, name) < 1.0:
                raise ValueError(f"{name} must be within 0..1 (both excluded), got {getattr(self, name)!r}")

    @property
    def observation_spacing_m(self) -> float:
        """Track between two observations at the survey speed."""
        return self.speed_m_s * self.sample_s


@dataclass(frozen=True)
class Goto:
    target: tuple[float, float]  # (n, e) local metres
    confirming: bool             # flying over the cell the belief is confident about
    height_m: float | None = None  # above ground; None: the survey height


class SearchController:
    def __init__(self, geometry: Geometry, policy: Policy, config: SearchConfig, start,
                 rng: np.random.Generator, timer: Callable[[], float] | None = None,
                 wind_ne_m_s: tuple | None = (0.0, 0.0)):
        """`timer`, if given (a clock in seconds), times every decision of the policy;
        `wind_ne_m_s`, the wind the search is told (where the air goes, m/s): the plume leans with it;
        None: the search estimates it from observe_lean's samples."""
        self.geometry = geometry
        self.policy = policy
        self.config = config
        self.wind_estimator = LeanWindEstimator() if wind_ne_m_s is None else None
        self.wind_ne_m_s = (0.0, 0.0) if wind_ne_m_s is None else tuple(wind_ne_m_s)
        # the latest estimate's standard error (0 when told); the wind the belief holds may differ
        # from that estimate by up to WIND_REBUILD_M_S
        self.wind_sd_m_s = math.inf if wind_ne_m_s is None else 0.0
        self.wind_rebuilds = 0
        # the thinking spread over steps (_work): (kind, generator), kind "rebuild" (a belief with
        # the wind and finds as they are, which then steers), "refit" (the same after the periodic
        # fit of the finds, not waited for) or "find" (what a find changes)
        self._jobs: list[tuple[str, Iterator[None]]] = []
        self._thinking = False  # this step has thought: it is timed (decision_s)
        self._starved = False  # the last step had jobs and worked none of them
        self._decided = False  # ... and the policy has chosen a waypoint in it
        # (point, job kinds): the vehicle holds there while jobs of those kinds run (a find's, or
        # after the cross over it the rebuild with the finds put right: steered by the belief
        # before it, the policy flew off after the fire just pinned down)
        self._holding: tuple[tuple[float, float], tuple[str, ...]] | None = None
        self._ending: str | None = None  # the search ends at the next step, for this reason
        self._rejudging = False  # a confident belief's finds were put right: judge its rebuild as it is
        self.several = config.max_fires != 1
        self.found: list[tuple[Declaration, tuple]] = []  # several fires: (declaration, hot spot) of each find
        self.readings: list[tuple] = []  # every observation, to rebuild the belief from
        self.frames: list = []  # every thermal frame (frame.FrameObservation), ditto
        self.belief = self._belief(())
        self.rule = StoppingRule(config.threshold, 1, config.confirm_m, config.clear_threshold)
        self.timer = timer
        self.max_observations = int(4 * config.budget_m / config.observation_spacing_m) + 100
        self.observations = 0
        self.decisions = 0
        self.decision_s: list[float] = []  # with a timer: the duration of every step that thinks
        self.target: tuple[float, float] | None = None
        self.confirming = False
        self.declared: Declaration | None = None
        self.declarations: list[Declaration] = []  # every fire declared, once the search has ended
        self.finished_by: str | None = None        # why it ended: a Declaration's reason, or "clear"
        self._need_decision = True
        self._since_decision = 0
        self._pin: list[tuple[float, float]] = []  # several fires: the cross still to fly over the last find
        self._climb: list[tuple] | None = None  # several fires: the climb's legs still to fly, (n, e, height)
        self._top_from: int | None = None  # observations when the climb reached the top
        self._climbed = 0  # readings taken during the climb
        self.first_find_path_m: float | None = None  # path flown when the first fire was found
        policy.reset(geometry, (float(start[0]), float(start[1])), rng)

    def _belief(self, known: tuple, null: bool | None = None) -> Belief:
        """A belief over one (more) fire, the `known` hot spots explained away; with several fires to
        look for, it also weighs the hypothesis that there is none (unless null is False): none at
        all before a find, none further after one."""
        c = self.config
        none = c.further_prior if known else c.null_prior
        null_prior = none if (self.several if null is None else null) else 0.0
        return Belief(self.geometry, c.prior_strength_mean_k, c.prior_strength_sd_k, subcells=c.subcells,
                      outlier_rate=c.outlier_rate, outlier_range_k=c.outlier_range_k,
                      wind_ne_m_s=self.wind_ne_m_s, known=known, null_prior=null_prior)

    def observe(self, n: float, e: float, z: float, height_m: float) -> None:
        """One observation: a temperature z at (n, e), height_m above ground. Ignored once declared."""
        if self.declared is not None:
            return
        self.belief.update(n, e, z, height_m)
        self.readings.append((n, e, z, height_m))
        if self._climb is not None and height_m > self.geometry.survey_alt_m + 1.0:
            self._climbed += 1  # the climb's readings above the survey height come last
        self.policy.observe(n, e, z)
        self.observations += 1
        self._since_decision += 1
        if not self._need_decision and self.policy.wants_replan(self._since_decision):
            self._need_decision = True

    def observe_frame(self, frame: FrameObservation) -> None:
        """One thermal frame (frame.py), besides the point reading taken with it: its evidence
        joins the belief. Ignored once declared."""
        if self.declared is not None:
            return
        self.belief.add_frame(frame_log_likelihood(self.belief, frame), frame)
        self.frames.append(frame)

    def observe_lean(self, velocity_ne: tuple[float, float], lean_ne: tuple[float, float]) -> None:
        """One sample of steady flight for the wind estimate: the velocity over ground [m/s] and
        the lean (wind_estimate.lean_of_attitude). Ignored when the search was told the wind."""
        est = self.wind_estimator
        if est is None or self.declared is not None:
            return
        est.add(velocity_ne, lean_ne)
        if est.n % WIND_CHECK_EVERY:
            return
        found = est.estimate()
        if found is None:
            return
        self.wind_sd_m_s = found.sd_m_s
        held = self.wind_ne_m_s
        if math.hypot(found.air_ne_m_s[0] - held[0], found.air_ne_m_s[1] - held[1]) > WIND_REBUILD_M_S:
            self.wind_ne_m_s = found.air_ne_m_s
            self._rebuild()
            self.wind_rebuilds += 1

    # ----- thinking spread over steps ------------------------------------------------------------
    def _rebuild(self, judged: bool = True) -> None:
        """Rebuild the belief from every reading with the wind and finds as they are now, a few
        chunks per step (_work); it replaces any rebuild queued or under way, whose inputs are stale.
        Until it is done the belief in use steers, and unless `judged` is False (the finds have only
        moved a little: a "refit") the search neither declares nor ends until it has judged this one."""
        pending = [job for job in self._jobs if job[0] in ("rebuild", "refit")]
        kind = "rebuild" if judged or any(job[0] == "rebuild" for job in pending) else "refit"
        self._jobs = [job for job in self._jobs if job not in pending] + [(kind, self._rebuilt())]

    def _rebuilt(self) -> Iterator[None]:
        belief = self._belief(tuple(spot for _, spot in self.found))
        yield from self._fed(belief)
        self.belief = belief

    def _fed(self, belief: Belief) -> Iterator[None]:
        """Give a new `belief` every reading, yielding between chunks: those there are now at once
        (Belief.absorbing), then those that came in meanwhile, a chunk at a time; then every thermal
        frame, FRAME_CHUNK a chunk, until it has all of both."""
        readings = list(self.readings)
        known = len(belief.known) > 0
        rows = max(1, min(JOB_ROWS, JOB_ROWS * REFERENCE_HYPOTHESES // belief.hyp_n.size)) if known else PLAIN_UPDATES
        yield from belief.absorbing(readings, rows)
        fed = len(readings)
        while fed < len(self.readings):
            yield  # the absorb's end, or the chunk before, was a chunk of its own
            upto = min(len(self.readings), fed + rows)
            if known:
                belief.update_together(self.readings[fed:upto])
            else:  # one by one, as the filter would: cheap without known fires
                for n, e, z, height_m in self.readings[fed:upto]:
                    belief.update(n, e, z, height_m)
            fed = upto
        framed = 0
        while framed < len(self.frames) or fed < len(self.readings):
            yield  # (the chunk before was one of its own)
            for frame in self.frames[framed:framed + FRAME_CHUNK]:
                belief.add_frame(frame_log_likelihood(belief, frame), frame)
            framed = min(len(self.frames), framed + FRAME_CHUNK)
            if fed < len(self.readings):  # taken meanwhile: a few
                if known:
                    belief.update_together(self.readings[fed:])
                else:
                    for n, e, z, height_m in self.readings[fed:]:
                        belief.update(n, e, z, height_m)
                fed = len(self.readings)

    def _work(self, chunks: int) -> None:
        """Work through `chunks` chunks of the jobs, oldest first: a step's thinking is bounded by
        the chunks, not by the readings so far."""
        while self._jobs and chunks:
            self._thinking = True
            job = self._jobs[0]
            chunks -= 1  # the call that ends a job works too (a rebuild's evidence, a find's fit)
            try:
                next(job[1])
            except StopIteration:
                self._jobs.remove(job)  # by identity: a job may have queued others

    def lean_known(self) -> bool:
        """The wind is known well enough that the plume's lean at the survey height is uncertain by
        at most half a cell (always, when told)."""
        if any(kind == "rebuild" for kind, _ in self._jobs):
            return False  # the belief in use may still hold the previous wind
        slowest_rise = min(PLUME_RISE_M_S)
        return self.wind_sd_m_s * self.geometry.survey_alt_m / slowest_rise <= 0.5 * self.geometry.cell_size_m

    def step(self, position, path_m: float, arrived: bool = False) -> Goto | Declaration:
        """Where to fly from `position` after `path_m` metres of search, or the declaration (then
        every later step returns it again). `arrived`: the vehicle has reached the last target."""
        if self.declared is not None:
            return self.declared
        if self.observations == 0:
            raise RuntimeError("step() before any observation: the search starts with a reading")
        t0 = self.timer() if self.timer else 0.0
        self._thinking = self._decided = False
        move = self._step(position, path_m, arrived)
        if self._jobs and self.declared is None:  # after the step: it judges what they have built so far
            chunks = self._chunks_allowed()
            self._starved = chunks == 0
            self._work(chunks)
        if self.timer and self._thinking:  # the whole step: its fits, decision and jobs' chunks
            self.decision_s.append(self.timer() - t0)
        return move

    def _chunks_allowed(self) -> int:
        """The jobs' chunks this step may work, after what it has thought already."""
        if self._decided:
            # none in a step the policy decided in, unless the step before worked none either: a
            # policy that decides at every observation (greedy) starved a rebuild for good, and the
            # search, never judging the rebuilt belief, flew on to its budget (a third of flights)
            return 1 if self._starved else 0
        heavy = len(self.found) >= HEAVY_KNOWN or (self.found and self.belief.hyp_n.size > REFERENCE_HYPOTHESES)
        return 1 if self._thinking or heavy else JOB_CHUNKS_PER_STEP

    def _step(self, position, path_m: float, arrived: bool) -> Goto | Declaration:
        if self._ending is not None:
            return self._finish(self._ending)
        if arrived:
            self._need_decision = True
        uses_belief = self.policy.uses_stopping_rule
        if self._holding is not None:
            if self._spent(path_m):
                return self._finish("budget")
            point, kinds = self._holding
            if any(kind in kinds for kind, _ in self._jobs):
                self.target = point
                return Goto(point, True)
            self._holding = None
        if self._climb is not None:
            move = self._climbing(path_m, arrived)
            if move is not None:
                return move
        if self._pin:  # several fires: pinning the last find down before looking on
            if self._spent(path_m):
                return self._finish("budget")
            if arrived:
                self._pin.pop(0)
            if self._pin:
                self.target = self._pin[0]
                return Goto(self.target, True)
            self._refresh(always=True)
            self._need_decision = True
            self._holding = (self.target, ("rebuild",))
            return Goto(self.target, True)
        if self.found and self.observations % REFRESH_EVERY == 0 and not self._jobs:
            self._jobs.append(("refit", self._refitting()))
        if uses_belief and not any(kind in ("find", "rebuild") for kind, _ in self._jobs) and self.lean_known():
            found = self.rule.confident(self.belief)
            rejudging, self._rejudging = self._rejudging, False
            if found is not None and self.found and not rejudging and self._refresh():
                # re-judged once the belief is rebuilt with the finds put right: over the cell, as
                # the step before would have declared it (flown on, the vehicle often came back)
                self._rejudging = True
                self._holding = ((float(position[0]), float(position[1])), ("rebuild",))
                return Goto(self._holding[0], True)
            elif found is not None:
                if self.first_find_path_m is None:
                    self.first_find_path_m = path_m
                if not self.several:
                    return self._declare(found, "confident")
                self._found(found, position)
                return self._step(position, path_m, False)  # over the find while its job runs
            elif self.several and self.rule.clear(self.belief):
                return self._finish("clear")
        if self._spent(path_m):
            return self._finish("budget")
        if uses_belief and self.config.confirm_m is not None:
            check = self.rule.to_confirm(self.belief)
            if check is not None:  # confident but not yet flown over: go and look
                self.target, self.confirming, self._need_decision = check, True, False
            elif self.confirming:  # the readings on the way overturned it: back to the policy
                self.confirming, self._need_decision = False, True
        if self._need_decision:
            waypoint = self._decide(position)
            if waypoint is None:
                return self._finish("end")
            self.target = waypoint
        return Goto(self.target, self.confirming)

    def _spent(self, path_m: float) -> bool:
        """The path budget is flown, or the observations exceed what it allows four times over."""
        return path_m >= self.config.budget_m or self.observations >= self.max_observations

    def _decide(self, position) -> tuple[float, float] | None:
        waypoint = self.policy.next_waypoint(self.belief, position)
        self._thinking = self._decided = True
        self.decisions += 1
        self._since_decision, self._need_decision = 0, False
        if waypoint is None:
            return None
        n, e = float(waypoint[0]), float(waypoint[1])
        a = self.geometry.area_m
        if not (0 <= n <= a and 0 <= e <= a and math.isfinite(n) and math.isfinite(e)):
            raise RuntimeError(f"policy {self.policy.name} chose a waypoint outside the area: {(n, e)}")
        return n, e

    # ----- several fires ---------------------------------------------------------------------------
    def _climbing(self, path_m: float, arrived: bool) -> Goto | Declaration | None:
        """The climb after a find: over its hot spot and up the plume's axis to RULE_OUT_HEIGHT_M,
        RULE_OUT_HOVER observations at the top, ending "clear" as soon as the belief is confident
        there is no other fire. None when it is over and not clear (the cross over the find comes
        next, at the survey height)."""
        if self._spent(path_m):
            return self._finish("budget")
        # no refit of the finds up here: seen from above every fire adds to every reading, and
        # refitted every REFRESH_EVERY readings a find walked, a cell at a time, to another fire
        if self.lean_known() and self.rule.clear(self.belief):
            return self._finish("clear")
        if arrived:
            if self._top_from is None and self._climb[0][2] == RULE_OUT_HEIGHT_M:
                self._top_from = self.observations
            if self._top_from is None or self.observations - self._top_from >= RULE_OUT_HOVER:
                self._climb.pop(0)
                self._top_from = None
        if not self._climb:
            # not clear: the climb's readings go before the cross's end rebuilds the belief. They
            # decide whether to stop; the search below is the one measured at the survey height
            if DROP_CLIMB_READINGS:
                del self.readings[len(self.readings) - self._climbed:]
                if self._jobs:  # a rebuild under way may hold readings gone now: from the start
                    self._rebuild(judged=False)
            self._climb, self._climbed = None, 0
            return None
        n, e, height = self._climb[0]
        self.target = (n, e)
        return Goto((n, e), False, height)

    def _found(self, found: Declaration, position) -> None:
        """A confident find with more fires to look for: keep it as a hot spot to explain away, and
        start its job (_after_find); the vehicle holds over it meanwhile."""
        self.found.append((found, self.belief.hot_spot(found.index)))
        self.confirming, self._need_decision = False, True
        self._holding = (found.position, ("find",))
        self._jobs = [job for job in self._jobs if job[0] != "refit"]  # the find's rebuild supersedes it
        self._jobs.append(("find", self._after_find(found, position)))
        self._thinking = True
        self.decisions += 1  # a decision too (what to believe)

    def _after_find(self, found: Declaration, position) -> Iterator[None]:
        """Put every earlier find right now that this one explains part of the readings (relocate)
        and fit the finds together; then, with more to look for, go on over a belief rebuilt from
        all readings with the finds known, after the climb and the cross."""
        yield from self._relocating()
        yield
        self._move_spots(self._fit())
        if len(self.found) == self.config.max_fires:
            self._ending = "confident"
            return
        self._rebuild()
        self._pin = self._pin_pattern(found.position, position)
        # (not when the fit has just dropped this find as a ghost: there is nothing to climb over)
        kept = bool(self.found) and self.found[-1][0] is found
        if self.geometry.reach_grows_with_height and self.belief.upright and kept:
            # up the plume's axis over the fitted hot spot: right over a fire its kernel is the same
            # at every height, and a profile there that grows with height is another fire's. Not
            # in wind: the rise speed is unknown, so the axis at the top is uncertain by tens of
            # metres (4 m/s: 64-120 m of lean at 120 m), and a profile off the axis falls with
            # height as another fire's grows: on a windy world the climb ended in ghost finds
            n, e, tn, te = self.found[-1][1]
            axis = lambda h: (min(a, max(0.0, n + h * tn)), min(a, max(0.0, e + h * te)))  # noqa: E731
            a, h0 = self.geometry.area_m, self.geometry.survey_alt_m
            self._climb = [(*axis(h0), None), (*axis(RULE_OUT_HEIGHT_M), RULE_OUT_HEIGHT_M)]

    def _refresh(self, always: bool = False) -> bool:
        """Fit the finds' hot spots to every reading so far; when one has moved more than
        REFRESH_M (or always), rebuild the belief with them where they now are, and judge that one
        (_rebuild). True if it will."""
        self._thinking = True
        if not self._refitted(always):
            return False
        self._rebuild()
        return True

    def _refitting(self) -> Iterator[None]:
        """_refresh every REFRESH_EVERY observations, as a job (the fit, then the rebuild) whose
        belief the search need not judge before it goes on: the finds have only moved a little."""
        if self._refitted(False):
            yield
            yield from self._rebuilt()

    def _refitted(self, always: bool) -> bool:
        """The finds where the fit puts them if one has moved more than REFRESH_M, or a ghost goes
        (or always); True if they have moved."""
        spots = [spot for _, spot in self.found]
        fitted, strengths = self._fit()
        moved = max((math.hypot(a[0] - b[0], a[1] - b[1]) for a, b in zip(spots, fitted)), default=0.0)
        if moved <= REFRESH_M and not always and min(strengths, default=math.inf) >= GHOST_BELOW_K:
            return False
        self._move_spots((fitted, strengths))
        self.decisions += 1
        return True

    def _fit(self, reach_cells: float = REACH_CELLS) -> tuple[list[tuple], list[float]]:
        """The finds' hot spots fitted together to every reading so far, and their strengths (refine.py)."""
        return fit_hot_spots(self.geometry, self.readings, [spot for _, spot in self.found],
                             self.belief.s2 ** 0.5, reach_cells)

    def _move_spots(self, fit: tuple[list[tuple], list[float]]) -> None:
        """The finds to where the fit puts them, less any it gives under GHOST_BELOW_K: a find
        declared where two fires' tails add up, explained once both are found."""
        spots, strengths = fit
        self.found = [(d, spot) for (d, _), spot, k in zip(self.found, spots, strengths) if k >= GHOST_BELOW_K]

    def _pin_pattern(self, centre, position) -> list[tuple[float, float]]:
        """A cross over a find, PIN_M either way along north and east, nearest end first: one
        pass seldom tells how far the fire lies to its side, two crossing passes do."""
        a, (n, e) = self.geometry.area_m, centre
        clip = lambda v: min(a, max(0.0, v))
        legs = [[(clip(n - PIN_M), e), (clip(n + PIN_M), e)], [(n, clip(e - PIN_M)), (n, clip(e + PIN_M))]]
        here = (float(position[0]), float(position[1]))
        near = lambda p: math.hypot(p[0] - here[0], p[1] - here[1])
        first = min(legs, key=lambda leg: min(near(leg[0]), near(leg[1])))
        second = legs[1] if first is legs[0] else legs[0]
        first = sorted(first, key=near)
        second = sorted(second, key=lambda p: math.hypot(p[0] - first[1][0], p[1] - first[1][1]))
        return first + second

    def _relocating(self) -> Iterator[None]:
        """Each earlier find again, with the others explained away: a find that a later one explains
        (one declared between two fires, or pulled towards a second one by its readings) moves
        to where the belief, given the others, is now confident of it. One pass over the finds."""
        for i in range(len(self.found) - 1):  # the newest was found with the others known already
            others = tuple(spot for k, (_, spot) in enumerate(self.found) if k != i)
            belief = self._belief(others, null=False)
            yield from self._fed(belief)
            yield
            moved = self.rule.candidate(belief)
            if moved is not None and moved[1] != self.found[i][0].index:
                position, index, mass = moved
                self.found[i] = (Declaration(position, index, mass, False, "confident"),
                                 belief.hot_spot(index))

    def _finish(self, reason: str) -> Declaration:
        """End the search. One fire: the declaration (forced unless confident). Several: every
        find; a forced declaration only when there is none and the search did not end clear."""
        self._jobs, self._holding, self._ending = [], None, None
        if self.several and self.found:
            self._move_spots(self._fit(FINAL_REACH_CELLS))
        if not self.several or not self.found:
            if reason == "clear":
                self.declarations, self.finished_by = [], "clear"
                self.declared = self.rule.force(self.belief, "clear")
                return self.declared
            return self._declare(self.rule.force(self.belief, reason), reason)
        self.declarations = [self._placed(d, spot) for d, spot in self.found]
        self.declared, self.finished_by = self.declarations[0], reason
        return self.declared

    def _placed(self, found: Declaration, spot: tuple) -> Declaration:
        """The find declared at the cell its fitted hot spot lies in."""
        index = self.geometry.cell_of(spot[0], spot[1])
        return Declaration(self.geometry.centre_of(index), index, found.mass, found.forced, found.reason)

    def _declare(self, found: Declaration, reason: str) -> Declaration:
        """The policy's own point if it has one, else the stopping rule's; snapped to its cell's centre."""
        own = self.policy.declaration(self.belief)
        point = found.position if own is None else (float(own[0]), float(own[1]))
        index = self.geometry.cell_of(*point)
        forced = reason == "budget" or (reason != "confident" and self.policy.uses_stopping_rule)
        self.declared = Declaration(self.geometry.centre_of(index), index, self.belief.mass_around(index, 1),
                                    forced, reason)
        self.declarations, self.finished_by = [self.declared], reason
        return self.declared

"""Information gain per unit of travel (docs/strategy.md, "Choosing where to fly").

Candidates: a coarse lattice over the area, points around the current position at a few radii and
directions, and the most likely cell's centre; all clipped to the area. For each candidate x the
expected drop of the belief's entropy from one reading at x,
    gain(x) = H(now) - E_z[ H(belief after z at x) ],
is estimated from M = 8 predicted readings drawn from the belief's predictive mixture
sum_c p_c N(mean_c(x), var_c(x)): M cells by systematic resampling (importance-weighted toward the
cells whose prediction at x stands out from the mixture's mean, see _draws), each paired with a fixed
normal quantile. The systematic offset and the quantiles are shared by all candidates of a decision
(common random numbers), so candidates are compared on alike hypothetical futures.

The score is gain / (1 + distance / d0); 1 + distance alone would be d0 = 1 m. d0 is the
distance whose flight costs as much as the reading's information is worth (a candidate d0 away is
worth half of the same information at the vehicle). Our sensor samples all the way (a reading per
5 m in the episodes), so flying is never wasted and the choice is a trade-off between heading for
the best place and gathering on the way. Measured on validation episodes (seed 1, not the reported
ones; gig, corner start, 1 K; mean path to declaration):
    G, episodes 100-299: d0 = 1 / 5 / 15 / 50 m -> 719 / 785 / 763 / 785 m
    G, episodes 300-499: d0 = 1 / 50 m          -> 806 / 789 m
    R, episodes 100-299: d0 = 1 / 5 / 15 / 50 m -> 463 / 459 / 457 / 457 m
    (earlier version, replanning every 2 readings, G 100-199: d0 = 25 / 50 / 100 / 200 m ->
     804 / 816 / 910 / 1045 m)
i.e. flat from 1 to 50 m within the noise (about +-35 m on G) and worse beyond. We keep d0 = 50 m,
the long end of the flat range: it lets the coarse lattice compete when one distant place is clearly
the most informative. d0 = None drops the distance term (infotaxis, same candidates).

Steadiness: the estimates are noisy (8 samples), so the previous waypoint stays a candidate and is
kept unless the best candidate scores 1.3x more (keep_target), and the policy re-decides every 4
readings (20 m) rather than every reading: both cut the wiggles that noisy choices put in the path.
Importance sampling (below) matters most: plain mixture sampling gave 1032 m mean path on G against
782 m with it (validation episodes 100-299).

Among equally informative candidates the nearer one wins (explicit tie-break on distance). Only cells
holding all but 1e-9 of the belief are considered in the predictions (the rest cannot change an
entropy estimate at that precision), and
candidates are processed in blocks of up to 100,000 candidate x sample x cell elements (800 kB per
temporary). Blocks of 12,000, sized to stay in cache, left one candidate per block while the belief
spans all 1,600 cells, and the per-call overhead of a hundred small blocks then doubled a decision:
on this machine, 50-55 ms against 25-28 ms mean over the first episodes of the default world, the
choices identical.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from statistics import NormalDist

import numpy as np

from .belief import Belief, Geometry


@dataclass(frozen=True)
class PlannerConfig:
    lattice_m: float = 40.0               # spacing of the coarse lattice of candidates ...
    lattice_max: int = 10                 # ... widened so that no more than this many lie along a side
    radii_m: tuple = (10.0, 25.0, 50.0)   # rings of candidates around the vehicle
    directions: int = 8                   # candidates per ring
    samples: int = 8                      # predicted readings per candidate
    importance: float = 0.5               # share of the draws steered to cells that change the reading
    d0_m: float | None = 50.0             # travel scale of the cost 1 + d/d0; None: no distance term
    min_move_m: float = 5.0               # candidates nearer than this are not a move
    support_mass: float = 1.0 - 1e-9      # belief mass considered in the predictions
    include_most_likely: bool = True
    keep_target: float = 1.3              # keep the previous waypoint unless the best scores this much more
    block_elements: int = 100_000          # candidates x samples x cells per vectorised block
    max_cells: int = 1600                 # more cells in the support are pooled into blocks (see coarse_support)
    footprint_m: tuple | None = None      # a thermal camera's ground rectangle (north, east) [m]: each
                                          # candidate also scores what a frame there tells (frame_gains)


class Planner:
    def __init__(self, geometry: Geometry, config: PlannerConfig = PlannerConfig(),
                 rng: np.random.Generator | None = None):
        self.geometry = geometry
        self.config = config
        self.rng = rng if rng is not None else np.random.default_rng(0)
        area = geometry.area_m
        k = min(max(1, int(round(area / config.lattice_m))), config.lattice_max)
        ticks = (np.arange(k) + 0.5) * (area / k)
        ln, le = np.meshgrid(ticks, ticks, indexing="ij")
        self.lattice = np.column_stack([ln.ravel(), le.ravel()])
        angles = 2 * math.pi * np.arange(config.directions) / max(1, config.directions)
        self.offsets = np.array([(r * math.cos(a), r * math.sin(a)) for r in config.radii_m for a in angles]
                                ).reshape(-1, 2)
        m = config.samples
        self.quantiles = np.array([NormalDist().inv_cdf((j + 0.5) / m) for j in range(m)])
        self.target: np.ndarray | None = None

    # ----- candidates ------------------------------------------------------------------------------
    def candidates(self, belief: Belief, position) -> np.ndarray:
        """(K, 2) candidate waypoints, all inside [0, area]^2, none within min_move_m of position."""
        area = self.geometry.area_m
        pos = np.asarray(position, dtype=float)
        parts = [self.lattice, pos + self.offsets]
        if self.config.include_most_likely and belief.n:
            parts.append(np.array([belief.most_likely()[0]]))
        if self.target is not None:
            parts.append(self.target[None, :])
        pts = np.clip(np.vstack(parts), 0.0, area)
        d = np.hypot(pts[:, 0] - pos[0], pts[:, 1] - pos[1])
        keep = d >= self.config.min_move_m
        if keep.any():
            pts = pts[keep]
        return np.unique(np.round(pts, 6), axis=0)

    # ----- expected information ------------------------------------------------------------------------
    def gains(self, belief: Belief, points: np.ndarray) -> np.ndarray:
        """Expected entropy drop [nats] of one reading at each of the (K, 2) points."""
        points = np.asarray(points, dtype=float).reshape(-1, 2)
        if belief.n == 0:
            return np.zeros(len(points))  # one reading alone says nothing under a flat ambient prior
        cells = belief.support(self.config.support_mass)
        p = belief.p[cells]
        logp = None  # the belief's own, per cell
        if len(cells) > self.config.max_cells:
            cells, p = coarse_support(belief, cells, self.config.max_cells)
            logp = np.log(np.maximum(p, 1e-300))
        p = p / p.sum()
        h_now = float(-(p * np.log(np.maximum(p, 1e-300))).sum())
        m = self.config.samples
        u = (np.arange(m) + self.rng.random()) / m          # systematic: one offset for all candidates
        xi = self.rng.permutation(self.quantiles)           # normal quantiles, paired at random
        out = np.empty(len(points))
        # blocks large enough that numpy's per-call overhead does not dominate (module docstring)
        step = max(1, self.config.block_elements // (len(cells) * m))
        for k0 in range(0, len(points), step):
            blk = points[k0:k0 + step]
            mean, var = belief.predictive(blk[:, 0], blk[:, 1], None, cells)
            draw, weight = self._draws(p, mean, u)
            rows = np.arange(len(blk))[:, None]
            z = mean[rows, draw] + np.sqrt(var[rows, draw]) * xi  # (B, M) predicted readings
            h_after = belief.entropy_after(blk[:, 0], blk[:, 1], z, None, cells, mean, var, logp)
            out[k0:k0 + step] = h_now - (weight * h_after).sum(axis=1) / weight.sum(axis=1)
        out = np.maximum(out, 0.0)
        if self.config.footprint_m is not None:
            out += self.frame_gains(belief, points)
        return out

    def frame_gains(self, belief: Belief, points: np.ndarray) -> np.ndarray:
        """Expected entropy drop [nats] of one thermal frame at each point: with probability m (the
        mass of the cells whose centre the frame sees) it shows the fire, whose cell it then pins
        down (entropy about 0); else those cells are ruled out and the rest renormalised:
            gain = H - (1 - m) H_rest,  H_rest = (H + sum_in p log p) / (1 - m) + log(1 - m),
        the sums over the cells in view read off integral images, O(cells + candidates)."""
        size, c = belief.size, belief.cell_m
        p = belief.p.reshape(size, size)
        plogp = p * belief.log_p.reshape(size, size)
        h_now = float(-plogp.sum())
        integral = np.zeros((2, size + 1, size + 1))
        integral[0, 1:, 1:] = p.cumsum(0).cumsum(1)
        integral[1, 1:, 1:] = plogp.cumsum(0).cumsum(1)
        extent = self.config.footprint_m or (0.0, 0.0)
        half_n, half_e = 0.5 * extent[0], 0.5 * extent[1]
        # cells whose centre (k + 0.5) c lies within [x - half, x + half]: k from lo to hi - 1
        lo_n = np.clip(np.ceil((points[:, 0] - half_n) / c - 0.5), 0, size).astype(int)
        hi_n = np.clip(np.floor((points[:, 0] + half_n) / c - 0.5) + 1, 0, size).astype(int)
        lo_e = np.clip(np.ceil((points[:, 1] - half_e) / c - 0.5), 0, size).astype(int)
        hi_e = np.clip(np.floor((points[:, 1] + half_e) / c - 0.5) + 1, 0, size).astype(int)
        hi_n, hi_e = np.maximum(hi_n, lo_n), np.maximum(hi_e, lo_e)
        sums = integral[:, hi_n, hi_e] - integral[:, lo_n, hi_e] - integral[:, hi_n, lo_e] + integral[:, lo_n, lo_e]
        m, plogp_in = np.clip(sums[0], 0.0, 1.0), sums[1]
        rest = 1.0 - m
        with np.errstate(divide="ignore", invalid="ignore"):
            h_rest = np.where(rest > 1e-12, (h_now + plogp_in) / rest + np.log(np.maximum(rest, 1e-300)), 0.0)
        return np.maximum(h_now - rest * h_rest, 0.0)

    def _draws(self, p: np.ndarray, mean: np.ndarray, u: np.ndarray):
        """Per candidate (row of mean), M cells drawn by systematic resampling of the proposal
        pi = (1 - a) p + a p |mean - mixture mean| / norm, and their importance weights p / pi.

        Plain mixture sampling (a = 0) rarely draws the few cells that would make a reading at the
        candidate stand out, yet those outcomes carry most of the information (a fire near an
        unexplored point); the proposal gives them a share a of the draws and the weights (<= 1/(1-a))
        keep the estimate consistent."""
        a = self.config.importance
        rows = mean.shape[0]
        if a > 0:
            dev = p * np.abs(mean - mean @ p[:, None])
            norm = dev.sum(axis=1, keepdims=True)
            pi = (1.0 - a) * p + a * np.divide(dev, norm, out=np.tile(p, (rows, 1)), where=norm > 0)
        else:
            pi = np.tile(p, (rows, 1))
        cum = np.cumsum(pi, axis=1)
        cum /= cum[:, -1:]
        offsets = np.arange(rows)[:, None]
        flat = (cum + 2.0 * offsets).ravel()  # rows made disjoint so one searchsorted serves all
        draw = np.searchsorted(flat, (u + 2.0 * offsets).ravel(), side="right").reshape(rows, -1)
        draw = np.minimum(draw - offsets * p.size, p.size - 1)
        draw = np.maximum(draw, 0)
        weight = p[draw] / np.take_along_axis(pi, draw, axis=1)
        return draw, weight

    # ----- the choice --------------------------------------------------------------------------------
    def score(self, gains: np.ndarray, distances: np.ndarray) -> np.ndarray:
        if self.config.d0_m is None:
            return gains.copy()
        return gains / (1.0 + distances / self.config.d0_m)

    def choose(self, belief: Belief, position) -> tuple[float, float]:
        """The candidate with the best score; the nearest among (numerically) equal best scores."""
        pts = self.candidates(belief, position)
        pos = np.asarray(position, dtype=float)
        dist = np.hypot(pts[:, 0] - pos[0], pts[:, 1] - pos[1])
        if belief.n == 0:
            centre = self.geometry.area_m / 2
            return centre, centre
        gains = self.gains(belief, pts)
        score = self.score(gains, dist)
        best = score.max()
        tied = np.flatnonzero(score >= best - 1e-12 * max(1.0, abs(best)))
        k = int(tied[np.argmin(dist[tied])])
        if self.target is not None and self.config.keep_target > 1.0:
            # hysteresis: stay with the previous waypoint (scored on the same predicted readings)
            # unless the best candidate is clearly better; this stops the path from wiggling on
            # the sampling noise of the gain estimates
            same = np.flatnonzero(np.all(np.abs(pts - self.target) < 1e-6, axis=1))
            if same.size and score[same[0]] * self.config.keep_target >= best:
                k = int(same[0])
        self.target = pts[k].copy()
        return float(pts[k, 0]), float(pts[k, 1])


def coarse_support(belief: Belief, cells: np.ndarray, max_cells: int) -> tuple[np.ndarray, np.ndarray]:
    """The support pooled into f x f blocks of cells (f the smallest that leaves at most max_cells
    blocks): per block its likeliest cell, standing for the block, and the block's mass. A belief
    spread over a large area (the start of a search on an 800 m world: 6,400 cells) is then
    planned on as a coarser grid, which is all its spread can tell apart; once it has narrowed to
    max_cells cells the planner sees every cell again."""
    size = belief.size
    f = 2
    while (math.ceil(size / f)) ** 2 > max_cells and f < size:
        f += 1
    i, j = np.divmod(cells, size)
    block = (i // f) * math.ceil(size / f) + (j // f)
    p = belief.p[cells]
    order = np.lexsort((-p, block))  # by block, likeliest first within each
    block_sorted = block[order]
    first = np.flatnonzero(np.r_[True, block_sorted[1:] != block_sorted[:-1]])
    mass = np.add.reduceat(p[order], first)
    return cells[order[first]], mass

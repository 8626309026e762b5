"""The belief: a probability per cell that it holds the fire, with the unknown ambient b and fire
strength A integrated out exactly (docs/strategy.md, "Belief").

Reading model for the hypothesis "the fire is at point q":
    z = b + A * g_q(x) + eps,   eps ~ N(0, sigma^2),
g_q(x) the world's kernel (sim.fire.kernel_value) at the horizontal distance from the reading's
position x to q, and the reading's height. Priors: b flat (improper), so the belief is exactly
invariant to an offset of all readings; A ~ N(mu_A, sd_A^2).

Per hypothesis we keep S_g = sum g, S_gg = sum g^2, S_gz = sum g*z, and globally n, S_z, S_zz. With
s2 = sigma^2 and sA2 = sd_A^2 the evidence of hypothesis q is the 2x2 Gaussian integral over (b, A):
    Lambda = [[n/s2, S_g/s2], [S_g/s2, 1/sA2 + S_gg/s2]],  eta = [S_z/s2, mu_A/sA2 + S_gz/s2],
    log p(z | q) = const + 0.5 eta^T Lambda^-1 eta - 0.5 log det Lambda.
We evaluate it in its equivalent centred form (Schur complement on the b block), which is the same
number up to a hypothesis-independent constant and loses no precision to cancellation:
    P = 1/sA2 + (S_gg - S_g^2/n)/s2,  h = mu_A/sA2 + (S_gz - S_g S_z/n)/s2,
    log p(z | q) = const + 0.5 h^2 / P - 0.5 log P
(det Lambda = (n/s2) P and eta^T Lambda^-1 eta = S_z^2/(n s2) + h^2/P). Readings are stored relative
to the first one, which the flat prior on b makes harmless and which keeps the sums small.

Hypotheses and cells. With subcells = 1 the hypotheses are the cell centres (the plain model). A
real fire is anywhere in its cell, and a point-at-the-centre model is then wrong by up to 0.7 cell:
near the fire, where the kernel is steep, that misfit is several noise sigmas, and when the readings
leave a direction poorly constrained (one straight pass) the belief can lock, confidently, onto
whichever distant cell centre happens to lie on the ridge of good fits. With subcells = k each cell
holds k x k equally likely sub-positions and its evidence is their average,
    p(z | cell) = mean over q in cell of p(z | q),
the exact marginal for a fire uniform on that sub-grid: the misfit shrinks k-fold and the mass
spreads along a ridge instead of piling on one centre. The episodes use k = 3.

Outliers (heavy tail). A reading is, with prior probability w (outlier_rate), an outlier: a value
anywhere in a range of outlier_range_k kelvin, whatever the fire, rather than the Gaussian model
above. With w > 0 the exact evidence is a sum over which readings are outliers (2^n terms), so it
is replaced by:
  - a burn-in, exact: over the first BURN_IN (6) readings the evidence is marginalised exactly over
    which of them are outliers, up to two (22 Gaussian marginals per hypothesis, each closed-form);
  - then assumed-density filtering: each new reading's evidence is its predictive density under
    the hypothesis, the mixture (1 - w) N(z; m, v) + w / range, m and v the Gaussian model's
    prediction from the readings so far; the reading then enters that hypothesis's sums with
    weight r = the posterior probability that it is not an outlier (a fractional reading: its
    noise variance s2 / r).
A single reading can then move a hypothesis's log evidence by at most about
log((1 - w) / (w sqrt(2 pi s2) / range)): one or two wild readings cannot make the belief certain.
The burn-in matters because the flat ambient prior makes the first readings define the level the
later ones are judged against; judging them one at a time would let an outlier among the first
two set a wrong level under every hypothesis. With w = 0 both steps are the exact marginal above
(the chain rule of the same Gaussian), up to a constant common to all hypotheses.
The sums are then kept per hypothesis (the weights differ from one hypothesis to the next).

Wind. A plume leans downwind: its hot spot is at q + h (wind / rise), rise the speed its gases
rise at. The vehicle reports the wind (the WIND message) but nobody knows the rise, so each
sub-position holds one hypothesis per rise speed in PLUME_RISE_M_S and the cell's evidence is the
average over them too: the marginal over a lean known in direction, uncertain in size.

The belief knows only what the strategy may know: the area, the cell size, the kernel, the plume
sigma and the sensor noise (Geometry). It never sees the true fire, ambient or strength.
Every update and query is vectorised: O(cells x subcells^2).
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from sim.fire import KERNELS, kernel_value


@dataclass(frozen=True)
class Geometry:
    """What the strategy may know about the world (never the fires, the ambient or the strengths)."""
    area_m: float = 400.0
    cell_m: float = 10.0
    survey_alt_m: float = 30.0
    kernel: str = "R"
    noise_k: float = 1.0
    plume_sigma_m: float = 25.0

    @classmethod
    def from_world(cls, world) -> "Geometry":
        return cls(area_m=world.area_m, cell_m=world.cell_m, survey_alt_m=world.survey_alt_m,
                   kernel=world.kernel, noise_k=world.noise_k, plume_sigma_m=world.plume_sigma_m)

    @property
    def cells_per_side(self) -> int:
        return max(1, int(round(self.area_m / self.cell_m)))

    @property
    def cell_size_m(self) -> float:
        """The grid's actual cell size: area / cells_per_side (= cell_m when it divides the area)."""
        return self.area_m / self.cells_per_side

    def cell_of(self, n: float, e: float) -> tuple[int, int]:
        k, c = self.cells_per_side, self.cell_size_m
        return (min(k - 1, max(0, int(math.floor(n / c)))), min(k - 1, max(0, int(math.floor(e / c)))))

    def centre_of(self, index) -> tuple[float, float]:
        c = self.cell_size_m
        return ((index[0] + 0.5) * c, (index[1] + 0.5) * c)


MIN_SIGMA_K = 0.01  # the belief needs a positive noise level even for a noiseless sensor
# How fast a fire's hot gases may rise [m/s]: the plume leans by wind / rise metres per metre of
# height, and the belief marginalises over these (a fire's rise speed is not known to the search).
# From one survey height the lean and the fire's position along the wind cannot be told apart (the
# readings only place the hot spot), so this prior's width is how far along the wind the fire stays
# uncertain: 4-7.5 m/s puts it within about a cell either way in a 4 m/s wind at 30 m. Chosen on
# the tuning episodes (seed 1); EVALUATION.md measures rise speeds outside it.
PLUME_RISE_M_S = (4.0, 5.5, 7.5)
CALM_M_S = 0.5  # below this wind the plume is taken as upright


def plume_tilts(wind_ne_m_s: tuple, rise_m_s: tuple = PLUME_RISE_M_S) -> list[tuple[float, float]]:
    """The plume leans the belief considers, as (north, east) metres per metre of height."""
    wn, we = float(wind_ne_m_s[0]), float(wind_ne_m_s[1])
    if math.hypot(wn, we) < CALM_M_S:
        return [(0.0, 0.0)]
    return [(wn / rise, we / rise) for rise in rise_m_s]


def entropy_of_log_weights(logw: np.ndarray) -> np.ndarray:
    """Entropy [nats] of the normalised distribution exp(logw) along the last axis."""
    top = logw.max(axis=-1, keepdims=True)
    shifted = logw - top
    w = np.exp(shifted)
    total = w.sum(axis=-1)
    return np.log(total) - np.einsum("...i,...i->...", w, shifted) / total


BURN_IN = 6  # readings whose evidence is marginalised exactly over their outliers before filtering starts
BURN_IN_OUTLIERS = 2  # ... counting the cases of up to this many outliers among them


class Belief:
    """Probability per cell that it holds the fire; see the module docstring for the model.

    Cells are indexed (i, j): i along north, j along east; cell (i, j) has its centre at
    ((i + 0.5) c, (j + 0.5) c), c the cell size. Flat per-cell arrays use index i * cells_per_side + j;
    hypothesis h belongs to cell h // per_cell (subcells^2 sub-positions x plume tilts).
    """

    def __init__(self, geometry: Geometry, strength_mean_k: float = 50.0, strength_sd_k: float = 25.0,
                 sigma_k: float | None = None, subcells: int = 1, outlier_rate: float = 0.0,
                 outlier_range_k: float = 100.0, wind_ne_m_s: tuple = (0.0, 0.0),
                 plume_rise_m_s: tuple = PLUME_RISE_M_S):
        if geometry.kernel not in KERNELS:
            raise ValueError(f"kernel must be one of {', '.join(KERNELS)}, got {geometry.kernel!r}")
        if not strength_sd_k > 0:
            raise ValueError("strength_sd_k must be positive")
        if int(subcells) != subcells or subcells < 1:
            raise ValueError("subcells must be a positive integer")
        if not 0.0 <= outlier_rate < 1.0:
            raise ValueError("outlier_rate must be within 0..1 (1 excluded)")
        if not outlier_range_k > 0:
            raise ValueError("outlier_range_k must be positive")
        self.geometry = geometry
        self.size = geometry.cells_per_side
        self.cell_m = geometry.cell_size_m
        self.subcells = int(subcells)
        self.tilts = plume_tilts(wind_ne_m_s, plume_rise_m_s)  # (n, e) metres per metre of height
        self.per_cell = self.subcells ** 2 * len(self.tilts)
        centres = (np.arange(self.size) + 0.5) * self.cell_m
        cn, ce = np.meshgrid(centres, centres, indexing="ij")
        self.centres_n = cn.ravel()
        self.centres_e = ce.ravel()
        offsets = ((np.arange(self.subcells) + 0.5) / self.subcells - 0.5) * self.cell_m
        on, oe = np.meshgrid(offsets, offsets, indexing="ij")
        # hypotheses: cell x sub-position x plume tilt, in that order (a cell's are contiguous)
        per_cell_n = np.repeat(on.ravel(), len(self.tilts))
        per_cell_e = np.repeat(oe.ravel(), len(self.tilts))
        self.hyp_n = (self.centres_n[:, None] + per_cell_n).ravel()
        self.hyp_e = (self.centres_e[:, None] + per_cell_e).ravel()
        tilted = any(t != (0.0, 0.0) for t in self.tilts)
        self.hyp_tilt = (np.tile([t[0] for t in self.tilts], self.centres_n.size * self.subcells ** 2),
                         np.tile([t[1] for t in self.tilts], self.centres_n.size * self.subcells ** 2)) \
            if tilted else None
        self.kernel = geometry.kernel
        self.plume_sigma_m = geometry.plume_sigma_m
        sigma = geometry.noise_k if sigma_k is None else sigma_k
        self.s2 = max(float(sigma), MIN_SIGMA_K) ** 2
        self.mu_a = float(strength_mean_k)
        self.sa2 = float(strength_sd_k) ** 2
        self.outlier_rate = float(outlier_rate)
        # log of an outlier's density, and of a reading's prior odds of being one
        self._log_outlier = (math.log(self.outlier_rate) - math.log(outlier_range_k)) if outlier_rate > 0 else -math.inf
        self._log_inlier = math.log1p(-self.outlier_rate)
        hyps = self.hyp_n.size
        self.n = 0
        self.z_ref = 0.0
        # per hypothesis: the (weighted) readings' sums, and the log evidence once filtering
        self.w_sum = np.zeros(hyps)
        self.s_z = np.zeros(hyps)
        self.s_zz = np.zeros(hyps)
        self.s_g = np.zeros(hyps)
        self.s_gg = np.zeros(hyps)
        self.s_gz = np.zeros(hyps)
        self.log_ev = np.zeros(hyps)
        self._burn_in: list[tuple[np.ndarray, float]] = []  # (g, y) of the first readings
        self.closest_r2 = np.full(self.centres_n.size, np.inf)  # per cell: nearest reading, squared [m^2]
        self._cache = None

    # ----- updates ---------------------------------------------------------------------------------
    def kernel_at(self, n, e, height_m: float, hyps: np.ndarray | None = None) -> np.ndarray:
        """g_q at point(s) (n, e) for every hypothesis (or those in hyps): shape (H,) for a scalar
        point, (K, H) for K points."""
        qn = self.hyp_n if hyps is None else self.hyp_n[hyps]
        qe = self.hyp_e if hyps is None else self.hyp_e[hyps]
        if self.hyp_tilt is not None:  # the hot spot is downwind of the fire by tilt x height
            tn, te = self.hyp_tilt if hyps is None else (self.hyp_tilt[0][hyps], self.hyp_tilt[1][hyps])
            qn, qe = qn + height_m * tn, qe + height_m * te
        n = np.asarray(n, dtype=float)
        e = np.asarray(e, dtype=float)
        r2 = (n[..., None] - qn) ** 2 + (e[..., None] - qe) ** 2
        return kernel_value(self.kernel, r2, height_m, self.plume_sigma_m)

    def update(self, n: float, e: float, z: float, height_m: float) -> None:
        """Add one reading z taken at (n, e) and height_m above ground."""
        if not math.isfinite(z):
            raise ValueError(f"reading must be finite, got {z!r}")
        g = self.kernel_at(n, e, height_m)
        if self.n == 0:
            self.z_ref = float(z)
        y = float(z) - self.z_ref
        self.n += 1
        if self.n <= BURN_IN:
            self._add(g, y, 1.0)
            self._burn_in.append((g, y))
            if self.n == BURN_IN:
                self._end_burn_in()
        else:
            self._filter(g, y)
        np.minimum(self.closest_r2, (self.centres_n - n) ** 2 + (self.centres_e - e) ** 2, out=self.closest_r2)
        self._cache = None

    def _add(self, g: np.ndarray, y: float, weight) -> None:
        self.w_sum += weight
        self.s_z += weight * y
        self.s_zz += weight * (y * y)
        wg = weight * g
        self.s_g += wg
        self.s_gg += wg * g
        self.s_gz += wg * y

    def _gaussian_log_marginal(self, w, s_z, s_zz, s_g, s_gg, s_gz) -> np.ndarray:
        """log p(readings | q) of the Gaussian model for (weighted) sums, b and A integrated out,
        up to a constant that depends on neither the hypothesis nor the number of readings."""
        g_bar = s_g / w
        precision = 1.0 / self.sa2 + np.maximum(s_gg - s_g * g_bar, 0.0) / self.s2
        h = self.mu_a / self.sa2 + (s_gz - g_bar * s_z) / self.s2
        szz_c = np.maximum(s_zz - s_z * s_z / w, 0.0)
        return (0.5 * h * h / precision - 0.5 * np.log(precision) - 0.5 * szz_c / self.s2
                - 0.5 * (w - 1.0) * math.log(2.0 * math.pi * self.s2) - 0.5 * np.log(w))

    def _burn_in_cases(self) -> tuple[np.ndarray, list[tuple[int, ...]]]:
        """log p(readings, case | q) for each case of which burn-in readings are outliers (none,
        one or two of them), and the cases (tuples of reading indices)."""
        sums = (self.w_sum, self.s_z, self.s_zz, self.s_g, self.s_gg, self.s_gz)
        m = len(self._burn_in)
        cases = [()]
        if self.outlier_rate > 0.0:
            cases += [c for k in range(1, min(BURN_IN_OUTLIERS, m - 1) + 1)
                      for c in itertools.combinations(range(m), k)]
        rows = []
        for case in cases:
            minus = list(sums)
            for k in case:
                g, y = self._burn_in[k]
                for i, part in enumerate((1.0, y, y * y, g, g * g, g * y)):
                    minus[i] = minus[i] - part
            prior = (m - len(case)) * self._log_inlier + (len(case) * self._log_outlier if case else 0.0)
            rows.append(prior + self._gaussian_log_marginal(*minus))
        return np.stack(rows), cases

    @staticmethod
    def _log_total(cases: np.ndarray) -> np.ndarray:
        top = cases.max(axis=0)
        return top + np.log(np.exp(cases - top).sum(axis=0))

    def _end_burn_in(self) -> None:
        """Evidence of the first readings over which of them (none, one or two) are outliers;
        each then stays in the sums weighted by its probability of not being one."""
        rows, cases = self._burn_in_cases()
        self.log_ev = self._log_total(rows)
        posterior = np.exp(rows - self.log_ev)
        for k, (g, y) in enumerate(self._burn_in):
            p_outlier = sum(posterior[c] for c, case in enumerate(cases) if k in case)
            if not isinstance(p_outlier, int):  # in at least one case
                self._add(g, y, -p_outlier)
        self._burn_in = []

    def _filter(self, g: np.ndarray, y: float) -> None:
        """A reading after the burn-in: its predictive density (the mixture) joins the evidence,
        and it joins the sums weighted by its probability of being no outlier."""
        w = self.w_sum
        g_bar = self.s_g / w
        precision = 1.0 / self.sa2 + np.maximum(self.s_gg - self.s_g * g_bar, 0.0) / self.s2
        a_mean = (self.mu_a / self.sa2 + (self.s_gz - g_bar * self.s_z) / self.s2) / precision
        dg = g - g_bar
        mean = self.s_z / w + a_mean * dg
        var = self.s2 * (1.0 + 1.0 / w) + dg * dg / precision
        log_in = self._log_inlier - 0.5 * np.log(2.0 * math.pi * var) - 0.5 * (y - mean) ** 2 / var
        if self.outlier_rate > 0.0:
            both = np.logaddexp(log_in, self._log_outlier)
            weight = np.exp(log_in - both)
        else:
            both, weight = log_in, 1.0
        self.log_ev += both
        self._add(g, y, weight)

    # ----- the posterior over cells ----------------------------------------------------------------
    def _stats(self):
        """Cached until the next update: per hypothesis (log evidence, A precision P, A posterior
        mean, mean g), per cell (p, log p, representative hypothesis = the cell's most likely)."""
        if self._cache is None:
            cells = self.centres_n.size
            if self.n == 0:
                self._cache = (np.zeros(self.hyp_n.size), None, None, None, np.full(cells, 1.0 / cells),
                               np.full(cells, -math.log(cells)), np.arange(cells) * self.per_cell, None, None)
            else:
                weight = self.w_sum
                g_bar = self.s_g / weight
                sgg_c = np.maximum(self.s_gg - self.s_g * g_bar, 0.0)
                sgz_c = self.s_gz - g_bar * self.s_z
                precision = 1.0 / self.sa2 + sgg_c / self.s2
                h = self.mu_a / self.sa2 + sgz_c / self.s2
                if self.n < BURN_IN:  # all readings in with weight 1; "none or one an outlier", exactly
                    log_ev = self._log_total(self._burn_in_cases()[0])
                else:
                    log_ev = self.log_ev
                top = log_ev.max()
                sub = np.exp(log_ev - top).reshape(cells, self.per_cell)
                rep = np.argmax(sub, axis=1) + np.arange(cells) * self.per_cell
                w = sub.sum(axis=1)
                total = w.sum()
                p = w / total
                with np.errstate(divide="ignore"):
                    logp = np.log(w) - math.log(total)
                # cells whose every sub-position underflowed: recompute their log mass exactly
                bad = ~np.isfinite(logp)
                if bad.any():
                    le = log_ev.reshape(cells, self.per_cell)[bad]
                    mx = le.max(axis=1)
                    logp[bad] = mx + np.log(np.exp(le - mx[:, None]).sum(axis=1)) - top - math.log(total)
                self._cache = (log_ev, precision, h / precision, g_bar, p, logp, rep, self.s_z / weight, weight)
        return self._cache

    @property
    def p(self) -> np.ndarray:
        """Probabilities as a flat array over cells (read-only view; do not modify)."""
        return self._stats()[4]

    @property
    def log_p(self) -> np.ndarray:
        return self._stats()[5]

    def probabilities(self) -> np.ndarray:
        """Probabilities as a (cells_per_side, cells_per_side) array indexed [i_north, j_east]."""
        return self.p.reshape(self.size, self.size).copy()

    def entropy(self) -> float:
        """Entropy [nats] of the distribution over cells."""
        p, logp = self.p, self.log_p
        return float(-(p * logp).sum())

    def most_likely(self) -> tuple[tuple[float, float], tuple[int, int]]:
        """((n, e) of the most likely cell's centre, (i, j) its index)."""
        k = int(np.argmax(self.p))
        index = divmod(k, self.size)
        return self.geometry.centre_of(index), index

    def mass_around(self, index, radius_cells: int = 1) -> float:
        """Belief mass in the (2r+1) x (2r+1) block of cells around index (clipped at the edges)."""
        i, j = index
        grid = self.p.reshape(self.size, self.size)
        return float(grid[max(0, i - radius_cells):i + radius_cells + 1,
                          max(0, j - radius_cells):j + radius_cells + 1].sum())

    def block_masses(self, radius_cells: int = 1) -> np.ndarray:
        """mass_around() of every cell at once, a (cells_per_side, cells_per_side) array: O(cells)."""
        r, k = radius_cells, self.size
        c = np.zeros((k + 1, k + 1))
        c[1:, 1:] = self.p.reshape(k, k).cumsum(0).cumsum(1)
        lo = np.clip(np.arange(k) - r, 0, k)
        hi = np.clip(np.arange(k) + r + 1, 0, k)
        return c[hi][:, hi] - c[lo][:, hi] - c[hi][:, lo] + c[lo][:, lo]

    def best_block(self, radius_cells: int = 1) -> tuple[tuple[int, int], float]:
        """The cell whose (2r+1) x (2r+1) block holds the most mass, and that mass; among blocks
        holding the same mass (to 1e-9), the one centred on the likeliest cell."""
        blocks = self.block_masses(radius_cells).ravel()
        tied = np.flatnonzero(blocks >= blocks.max() - 1e-9)
        k = int(tied[np.argmax(self.p[tied])])
        return divmod(k, self.size), float(blocks[k])

    def closest_reading_m(self, index) -> float:
        """Horizontal distance from the cell's centre to the nearest reading so far (inf if none)."""
        return math.sqrt(self.closest_r2[index[0] * self.size + index[1]])

    def support(self, mass: float = 1.0 - 1e-9) -> np.ndarray:
        """Indices of the most likely cells that together hold at least `mass` of the belief."""
        p = self.p
        if mass >= 1.0:
            return np.arange(p.size)
        order = np.argsort(p)[::-1]
        cum = np.cumsum(p[order])
        k = int(np.searchsorted(cum, mass)) + 1
        return order[:min(k, p.size)]

    # ----- predictions (for planning) --------------------------------------------------------------
    def predictive(self, n, e, height_m: float | None = None, cells: np.ndarray | None = None):
        """Predictive mean and variance of a reading at point(s) (n, e), per cell.

        Given hypothesis q and the readings so far (weighted as the hypothesis weighs them, W their
        total weight), A ~ N(h/P, 1/P) and b | A ~ N(mean(z) - A mean(g), s2/W), so a new reading with
        kernel value g has mean  mean(z) + E[A] (g - mean(g))  and variance s2 (1 + 1/W) + (g - mean(g))^2 / P;
        an outlier is not predicted (the planner asks what a good reading would tell). A cell is represented by its most likely sub-position (its
        centre when subcells = 1). Shapes: (cells,) for a scalar point, (K, cells) for K points.
        """
        if self.n == 0:
            raise ValueError("no reading yet: the flat ambient prior makes the prediction improper")
        height = self.geometry.survey_alt_m if height_m is None else height_m
        _, precision, a_mean, g_bar, _, _, rep, z_bar, w = self._stats()
        hyps = rep if cells is None else rep[cells]
        dg = self.kernel_at(n, e, height, hyps) - g_bar[hyps]
        mean = self.z_ref + z_bar[hyps] + a_mean[hyps] * dg
        var = self.s2 * (1.0 + 1.0 / w[hyps]) + dg * dg / precision[hyps]
        return mean, var

    def entropy_after(self, n, e, z, height_m: float | None = None, cells: np.ndarray | None = None,
                      mean: np.ndarray | None = None, var: np.ndarray | None = None,
                      logp: np.ndarray | None = None) -> np.ndarray:
        """Posterior entropy over cells after hypothetical reading(s) z at point(s) (n, e); the belief
        is unchanged.

        The posterior after a reading is p_c N(z; mean_c, var_c) normalised (the update the running
        sums would make, with each cell represented as in predictive()). n, e: scalars or shape (K,);
        z: shape (..., M) per point, i.e. (M,) for a scalar point or (K, M) for K points. Returns
        entropies of shape z.shape. With `cells`, only those cells are considered (renormalised): used
        to skip negligible mass. `mean`/`var` may be passed when already computed by predictive()."""
        if mean is None or var is None:
            mean, var = self.predictive(n, e, height_m, cells)
        if logp is None:  # (given: the cells stand for pooled blocks of that mass)
            logp = self.log_p if cells is None else self.log_p[cells]
        z = np.asarray(z, dtype=float)
        base = logp - 0.5 * np.log(var)  # (..., C)
        inv2v = 0.5 / var
        logw = base[..., None, :] - (z[..., None] - mean[..., None, :]) ** 2 * inv2v[..., None, :]
        return entropy_of_log_weights(logw)

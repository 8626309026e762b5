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

The belief knows only what the strategy may know: the area, the cell size, the kernel, the plume
sigma and the sensor noise (Geometry). It never sees the true fire, ambient or strength.
Every update and query is vectorised: O(cells x subcells^2).
"""
from __future__ import annotations

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


def entropy_of_log_weights(logw: np.ndarray) -> np.ndarray:
    """Entropy [nats] of the normalised distribution exp(logw) along the last axis."""
    top = logw.max(axis=-1, keepdims=True)
    shifted = logw - top
    w = np.exp(shifted)
    total = w.sum(axis=-1)
    return np.log(total) - np.einsum("...i,...i->...", w, shifted) / total


class Belief:
    """Probability per cell that it holds the fire; see the module docstring for the model.

    Cells are indexed (i, j): i along north, j along east; cell (i, j) has its centre at
    ((i + 0.5) c, (j + 0.5) c), c the cell size. Flat per-cell arrays use index i * cells_per_side + j;
    hypothesis h belongs to cell h // subcells^2.
    """

    def __init__(self, geometry: Geometry, strength_mean_k: float = 50.0, strength_sd_k: float = 25.0,
                 sigma_k: float | None = None, subcells: int = 1):
        if geometry.kernel not in KERNELS:
            raise ValueError(f"kernel must be one of {', '.join(KERNELS)}, got {geometry.kernel!r}")
        if not strength_sd_k > 0:
            raise ValueError("strength_sd_k must be positive")
        if int(subcells) != subcells or subcells < 1:
            raise ValueError("subcells must be a positive integer")
        self.geometry = geometry
        self.size = geometry.cells_per_side
        self.cell_m = geometry.cell_size_m
        self.subcells = int(subcells)
        self.per_cell = self.subcells ** 2
        centres = (np.arange(self.size) + 0.5) * self.cell_m
        cn, ce = np.meshgrid(centres, centres, indexing="ij")
        self.centres_n = cn.ravel()
        self.centres_e = ce.ravel()
        offsets = ((np.arange(self.subcells) + 0.5) / self.subcells - 0.5) * self.cell_m
        on, oe = np.meshgrid(offsets, offsets, indexing="ij")
        self.hyp_n = (self.centres_n[:, None] + on.ravel()).ravel()
        self.hyp_e = (self.centres_e[:, None] + oe.ravel()).ravel()
        self.kernel = geometry.kernel
        self.plume_sigma_m = geometry.plume_sigma_m
        sigma = geometry.noise_k if sigma_k is None else sigma_k
        self.s2 = max(float(sigma), MIN_SIGMA_K) ** 2
        self.mu_a = float(strength_mean_k)
        self.sa2 = float(strength_sd_k) ** 2
        hyps = self.hyp_n.size
        self.n = 0
        self.z_ref = 0.0
        self.s_z = 0.0
        self.s_zz = 0.0
        self.s_g = np.zeros(hyps)
        self.s_gg = np.zeros(hyps)
        self.s_gz = np.zeros(hyps)
        self.closest_r2 = np.full(self.centres_n.size, np.inf)  # per cell: nearest reading, squared [m^2]
        self._cache = None

    # ----- updates ---------------------------------------------------------------------------------
    def kernel_at(self, n, e, height_m: float, hyps: np.ndarray | None = None) -> np.ndarray:
        """g_q at point(s) (n, e) for every hypothesis (or those in hyps): shape (H,) for a scalar
        point, (K, H) for K points."""
        qn = self.hyp_n if hyps is None else self.hyp_n[hyps]
        qe = self.hyp_e if hyps is None else self.hyp_e[hyps]
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
        self.s_z += y
        self.s_zz += y * y
        self.s_g += g
        self.s_gg += g * g
        self.s_gz += g * y
        np.minimum(self.closest_r2, (self.centres_n - n) ** 2 + (self.centres_e - e) ** 2, out=self.closest_r2)
        self._cache = None

    # ----- the posterior over cells ----------------------------------------------------------------
    def _stats(self):
        """Cached until the next update: per hypothesis (log evidence, A precision P, A posterior
        mean, mean g), per cell (p, log p, representative hypothesis = the cell's most likely)."""
        if self._cache is None:
            cells = self.centres_n.size
            if self.n == 0:
                self._cache = (np.zeros(self.hyp_n.size), None, None, None, np.full(cells, 1.0 / cells),
                               np.full(cells, -math.log(cells)), np.arange(cells) * self.per_cell)
            else:
                g_bar = self.s_g / self.n
                sgg_c = np.maximum(self.s_gg - self.s_g * g_bar, 0.0)
                sgz_c = self.s_gz - g_bar * self.s_z
                precision = 1.0 / self.sa2 + sgg_c / self.s2
                h = self.mu_a / self.sa2 + sgz_c / self.s2
                log_ev = 0.5 * h * h / precision - 0.5 * np.log(precision)
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
                self._cache = (log_ev, precision, h / precision, g_bar, p, logp, rep)
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

        Given hypothesis q and the readings so far, A ~ N(h/P, 1/P) and b | A ~ N(mean(z) - A mean(g),
        s2/n), so a new reading with kernel value g has mean  mean(z) + E[A] (g - mean(g))  and variance
        s2 (1 + 1/n) + (g - mean(g))^2 / P. A cell is represented by its most likely sub-position (its
        centre when subcells = 1). Shapes: (cells,) for a scalar point, (K, cells) for K points.
        """
        if self.n == 0:
            raise ValueError("no reading yet: the flat ambient prior makes the prediction improper")
        height = self.geometry.survey_alt_m if height_m is None else height_m
        _, precision, a_mean, g_bar, _, _, rep = self._stats()
        hyps = rep if cells is None else rep[cells]
        dg = self.kernel_at(n, e, height, hyps) - g_bar[hyps]
        mean = self.z_ref + self.s_z / self.n + a_mean[hyps] * dg
        var = self.s2 * (1.0 + 1.0 / self.n) + dg * dg / precision[hyps]
        return mean, var

    def entropy_after(self, n, e, z, height_m: float | None = None, cells: np.ndarray | None = None,
                      mean: np.ndarray | None = None, var: np.ndarray | None = None) -> np.ndarray:
        """Posterior entropy over cells after hypothetical reading(s) z at point(s) (n, e); the belief
        is unchanged.

        The posterior after a reading is p_c N(z; mean_c, var_c) normalised (the update the running
        sums would make, with each cell represented as in predictive()). n, e: scalars or shape (K,);
        z: shape (..., M) per point, i.e. (M,) for a scalar point or (K, M) for K points. Returns
        entropies of shape z.shape. With `cells`, only those cells are considered (renormalised): used
        to skip negligible mass. `mean`/`var` may be passed when already computed by predictive()."""
        if mean is None or var is None:
            mean, var = self.predictive(n, e, height_m, cells)
        logp = self.log_p if cells is None else self.log_p[cells]
        z = np.asarray(z, dtype=float)
        base = logp - 0.5 * np.log(var)  # (..., C)
        inv2v = 0.5 / var
        logw = base[..., None, :] - (z[..., None] - mean[..., None, :]) ** 2 * inv2v[..., None, :]
        return entropy_of_log_weights(logw)

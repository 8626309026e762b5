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
rise at. The vehicle reports the wind (the WIND message, zero unless its EKF fuses the rotors'
drag) but nobody knows the rise, so each
sub-position holds one hypothesis per rise speed in PLUME_RISE_M_S and the cell's evidence is the
average over them too: the marginal over a lean known in direction, uncertain in size.

Rebuilding (absorb). The search rebuilds its belief from every reading when what it holds fixed
changes: a fire found and explained away, a find refitted, a new wind estimate. Replaying the
readings through the filter above costs a full update per reading, over a second with a known fire
and a hundred readings. A new belief instead takes them all at once, jointly: a round of
expectation-maximisation over which readings are outliers, per hypothesis (the least-squares fit of
ambient, strength and known fires to every reading; each reading's probability of being no outlier
from its residual; the sums again with those weights), then the evidence of the weighted sums
with the outlier terms of the variational bound,
    log p(z | q) ~ log N-marginal(weighted sums) + sum_i [r_i log(1 - w) + (1 - r_i) log(w / range) + H(r_i)].
Without outliers (every r_i = 1, or w = 0) that is the exact marginal, as the filter's is; with
them, the joint fit sees every reading at once where the filter judges each against those before it
(hence no burn-in here). Later readings go through the filter as before. Without a known fire a
rebuild replays the filter instead, which is then the cheaper.

Several fires. Fires found earlier can be `known`: their kernels, and the kernels' slopes along
north and east (a hot spot is placed only to a few metres), join the ambient as nuisances with
flat priors, projected out per hypothesis like the ambient; cells within EXCLUDED_CELLS of a known
fire get no prior mass. With null_prior > 0 one more hypothesis, kernel zero everywhere, says there
is no further fire; p_fire is the probability there is one (docs/strategy.md, "Several fires").

Thermal frames (frame.py, issue 32): a downward camera's frame is independent of the point readings
given the fire, so its log likelihood per hypothesis is summed apart (frame_ev, add_frame) and added
to the readings' evidence wherever the posterior is formed; a rebuild adds every frame again.

The belief knows only what the strategy may know: the area, the cell size, the kernel, the plume
sigma and the sensor noise (Geometry). It never sees the true fire, ambient or strength.
Every update and query is vectorised: O(cells x subcells^2).
"""
from __future__ import annotations

import dataclasses
import itertools
import math
from dataclasses import dataclass
from typing import Iterator

import numpy as np
from scipy.special import expit, xlogy

from firefly.sim.fire import KERNELS, kernel_value


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
    def reach_grows_with_height(self) -> bool:
        """Higher up the sensor sees farther (R: g = h^2 / (h^2 + r^2) flattens as h grows); the
        G plume's width does not change with height."""
        return self.kernel == "R"

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
R_FLOOR = 1e-6  # the least weight a rebuild gives a reading (absorb)
ABSORB_ROUNDS = 1  # expectation-maximisation rounds of a rebuild (absorb) over which readings are outliers
ABSORB_CHUNK = 100  # readings of the weighted pass that absorbing() works through between two
# yields (as fast as one pass at once: a 500-reading rebuild took 335-352 ms against 379-505 ms) ...
KERNEL_PASS_CHUNKS = 2  # ... and of the kernels' pass this many times as many (half the cost per
PLAIN_PASS_CHUNKS = 8  # reading), of the plain sums' this many (an eighth): chunks cost about alike
RIDGE = 1e-9  # keeps the known fires' normal equations invertible before the readings pin their strengths
EXCLUDED_LOG_PRIOR = -1e4  # a cell next to a known fire: no prior mass (finite, so 0 x log 0 stays 0)
EXCLUDED_CELLS = 2  # ... within this many cells (Chebyshev) of the known fire's
KNOWN_SHIFT_M = 2.0  # the step of a known fire's slopes (a central difference over 2 x this)


def symmetric_inverse(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Inverses and determinants of a stack of symmetric positive definite matrices (H, m, m): in
    closed form for m = 3 (one known fire: a batched LAPACK call costs ten times more), else by
    Cholesky, element by element across the stack (_cholesky_inverse)."""
    if a.shape[-1] != 3:
        return _cholesky_inverse(a)
    a00, a01, a02, a11, a12, a22 = a[:, 0, 0], a[:, 0, 1], a[:, 0, 2], a[:, 1, 1], a[:, 1, 2], a[:, 2, 2]
    c00 = a11 * a22 - a12 * a12
    c01 = a02 * a12 - a01 * a22
    c02 = a01 * a12 - a02 * a11
    c11 = a00 * a22 - a02 * a02
    c12 = a01 * a02 - a00 * a12
    c22 = a00 * a11 - a01 * a01
    det = a00 * c00 + a01 * c01 + a02 * c02
    inv = np.stack([c00, c01, c02, c01, c11, c12, c02, c12, c22], axis=-1).reshape(a.shape) / det[:, None, None]
    return inv, det


def _cholesky_inverse(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """symmetric_inverse for any m: A = L L^T, then A^-1 = L^-T L^-1, each entry of L and of its
    inverse one vector operation over the H matrices. A batched LAPACK call pays per matrix: with
    two known fires (m = 6) over 14,400 hypotheses it took 29 ms, and every reading needs one.
    The inverse comes as an (H, m, m) view of (m, m, H) memory: entry (i, j) contiguous over H."""
    m = a.shape[-1]
    entries = a.transpose(1, 2, 0)  # (m, m, H)
    low = [[None] * m for _ in range(m)]
    for j in range(m):
        acc = entries[j, j].copy()
        for k in range(j):
            acc -= low[j][k] * low[j][k]
        low[j][j] = np.sqrt(acc)
        reciprocal = 1.0 / low[j][j]
        for i in range(j + 1, m):
            acc = entries[i, j].copy()
            for k in range(j):
                acc -= low[i][k] * low[j][k]
            acc *= reciprocal
            low[i][j] = acc
    inv_low = [[None] * m for _ in range(m)]  # L^-1, lower triangular too
    for i in range(m):
        inv_low[i][i] = 1.0 / low[i][i]
        for j in range(i):
            acc = low[i][j] * inv_low[j][j]
            for k in range(j + 1, i):
                acc += low[i][k] * inv_low[k][j]
            acc *= -inv_low[i][i]
            inv_low[i][j] = acc
    inv = np.empty((m, m, a.shape[0]))
    for i in range(m):
        for j in range(i + 1):
            acc = inv_low[i][i] * inv_low[i][j]
            for k in range(i + 1, m):
                acc += inv_low[k][i] * inv_low[k][j]
            inv[i, j] = acc
            inv[j, i] = acc
    det = low[0][0] * low[0][0]
    for j in range(1, m):
        det = det * low[j][j] * low[j][j]
    return inv.transpose(2, 0, 1), det


class Sums:
    """The weighted sums of the readings, per hypothesis, that the evidence needs: with u = (1, k),
    k the known fires' kernels at the reading (the nuisance regressors), and g the hypothesis's,
    w = sum 1, z, zz, g, gg, gz, and for the known fires k, kk, kg, kz."""
    FIELDS = ("w", "z", "zz", "g", "gg", "gz", "k", "kk", "kg", "kz")

    def __init__(self, hyps: int, known: int):
        self.fields = self.FIELDS if known else self.FIELDS[:6]  # the known fires' terms only with some
        for name in self.FIELDS[:6]:
            setattr(self, name, np.zeros(hyps))
        self.k, self.kg, self.kz = (np.zeros((hyps, known)) for _ in range(3))
        self.kk = np.zeros((hyps, known, known))

    @staticmethod
    def parts(g: np.ndarray, k: np.ndarray, y: float) -> tuple:
        """One reading's terms, in FIELDS order (g per hypothesis, k per known fire)."""
        if not k.size:
            return (1.0, y, y * y, g, g * g, g * y)
        return (1.0, y, y * y, g, g * g, g * y, k, np.outer(k, k), g[:, None] * k, k * y)

    def add(self, parts: tuple, weight) -> None:
        """Add a reading's terms with a weight (a number, or one per hypothesis)."""
        if np.ndim(weight) == 0:
            for name, part in zip(self.fields, parts):
                arr = getattr(self, name)
                arr += part if weight == 1.0 else weight * part
            return
        for name, part in zip(self.fields, parts):
            arr = getattr(self, name)
            arr += weight.reshape(weight.shape + (1,) * (arr.ndim - 1)) * part

    def without(self, readings: list[tuple]) -> tuple:
        """The sums (in FIELDS order) with these readings' terms taken out."""
        out = list(self.as_tuple())
        for parts in readings:
            for i, p in enumerate(parts):
                out[i] = out[i] - p
        return tuple(out)

    def as_tuple(self) -> tuple:
        return tuple(getattr(self, name) for name in self.fields)


@dataclass
class Fit:
    """Per hypothesis, the readings' fit with the nuisances (the ambient and the known fires'
    strengths, flat priors) projected out: what the evidence and the prediction of a reading need."""
    w: np.ndarray       # total weight of the readings
    g_bar: np.ndarray   # weighted means of g and z
    z_bar: np.ndarray
    k_bar: np.ndarray   # (H, m) weighted means of the known fires' kernels (None without known fires)
    kk_inv: np.ndarray  # (H, m, m) inverse of their centred Gram matrix (None ...)
    a_g: np.ndarray     # (H, m) regression of g on the centred k (None ...)
    a_z: np.ndarray     # (H, m) regression of z on the centred k (None ...)
    gg: np.ndarray      # residual sums after projecting out (1, k): g.g, g.z, z.z
    gz: np.ndarray
    zz: np.ndarray
    logdet: np.ndarray  # log det of the nuisances' Gram matrix

    @classmethod
    def of(cls, w, z, zz, g, gg, gz, k=None, kk=None, kg=None, kz=None, evidence: bool = True) -> "Fit":
        """The fit of sums in Sums.FIELDS order (without the known fires' when there are none);
        evidence=False leaves out zz and logdet, which only the evidence needs (then None)."""
        g_bar, z_bar = g / w, z / w
        gg_c = np.maximum(gg - g * g_bar, 0.0)
        gz_c = gz - g_bar * z
        zz_c = np.maximum(zz - z * z_bar, 0.0) if evidence else None
        logdet = np.log(w) if evidence else None
        k_bar = None
        if k is not None:
            m = k.shape[-1]
            k_bar = k / w[:, None]
            kk_c = kk - k_bar[:, :, None] * k[:, None, :] + RIDGE * np.eye(m)
            kg_c = kg - k_bar * g[:, None]
            kz_c = kz - k_bar * z[:, None]
            kk_inv, det = symmetric_inverse(kk_c)
            a_g = np.einsum("hij,hj->hi", kk_inv, kg_c)
            a_z = np.einsum("hij,hj->hi", kk_inv, kz_c)
            gg_c = np.maximum(gg_c - (kg_c * a_g).sum(1), 0.0)
            gz_c = gz_c - (kg_c * a_z).sum(1)
            if evidence:
                zz_c = np.maximum(zz_c - (kz_c * a_z).sum(1), 0.0)
                logdet = logdet + np.log(det)
        else:
            kk_inv = a_g = a_z = None
        return cls(w, g_bar, z_bar, k_bar, kk_inv, a_g, a_z, gg_c, gz_c, zz_c, logdet)

    def fitted(self, a_mean: np.ndarray, g: np.ndarray, k: np.ndarray) -> np.ndarray:
        """The fit's value at readings with kernels g (N, H) and known fires' k (N, m), strength
        a_mean per hypothesis: ambient + A g + the known fires' terms, (N, H)."""
        base = self.z_bar - a_mean * self.g_bar
        if self.a_g is None:
            return base + a_mean * g
        c = self.a_z - a_mean[:, None] * self.a_g  # (H, m) the known fires' coefficients
        return base - (self.k_bar * c).sum(1) + a_mean * g + k @ c.T

    def take(self, hyps: np.ndarray) -> "Fit":
        values = (getattr(self, f.name) for f in dataclasses.fields(self))
        return Fit(*(None if v is None else v[hyps] for v in values))

    def strength(self, mu_a: float, sa2: float, s2: float) -> tuple[np.ndarray, np.ndarray]:
        """The fire strength's posterior precision P and mean h / P (prior N(mu_a, sa2)), as (P, h)."""
        return 1.0 / sa2 + self.gg / s2, mu_a / sa2 + self.gz / s2

    def at(self, g: np.ndarray, k: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """For a new reading with kernels g (..., H) and k (..., m): the nuisances' fit of z there,
        g's residual after the same projection, and the reading's leverage x^T (U^T U)^-1 x."""
        if self.a_g is None:
            return self.z_bar, g - self.g_bar, 1.0 / self.w
        m = k.shape[-1]
        # per known-fire column, contiguous (..., H) arrays: cheaper than batched tiny matrices
        dk = [k[..., i, None] - self.k_bar[:, i] for i in range(m)]
        fit_z = self.z_bar + sum(d * self.a_z[:, i] for i, d in enumerate(dk))
        dg = g - self.g_bar - sum(d * self.a_g[:, i] for i, d in enumerate(dk))
        leverage = 1.0 / self.w
        for i in range(m):  # the quadratic form dk^T kk_inv dk, its upper triangle twice
            row = dk[i] * self.kk_inv[:, i, i]
            for j in range(i + 1, m):
                row = row + 2.0 * dk[j] * self.kk_inv[:, i, j]
            leverage = leverage + row * dk[i]
        return fit_z, dg, leverage


def _add_sums(total: tuple | None, part: tuple) -> tuple:
    """_weighted_sums of two sets of readings added: the sums of both."""
    return part if total is None else tuple(a + b for a, b in zip(total, part))


def _weighted_sums(r: np.ndarray | None, g: np.ndarray, k: np.ndarray, y: np.ndarray) -> tuple:
    """Sums.FIELDS of readings y (N,) with kernels g (N, H), known fires' k (N, m) and weights r
    (N, H; None: all 1): the sums Sums.add would reach adding them one by one with those weights.
    Each family of sums is one matrix product over the readings."""
    n, m = len(y), k.shape[1]
    powers = np.stack([np.ones(n), y, y * y])  # (3, N)
    rg = g if r is None else r * g
    if r is None:
        w, z, zz = np.full(g.shape[1], float(n)), np.full(g.shape[1], float(y.sum())), np.full(g.shape[1], float(y @ y))
    else:
        w, z, zz = powers @ r
    g_sum, gz = powers[:2] @ rg
    out = (w, z, zz, g_sum, (rg * g).sum(0), gz)
    if not m:
        return out
    regressors = np.concatenate([k, (k[:, :, None] * k[:, None, :]).reshape(n, m * m), k * y[:, None]], axis=1)
    known = regressors.T @ r if r is not None else np.repeat(regressors.sum(0)[:, None], g.shape[1], axis=1)
    known = known.T  # (H, m + m^2 + m)
    return out + (known[:, :m], known[:, m:m + m * m].reshape(-1, m, m), (k.T @ rg).T, known[:, m + m * m:])


class Belief:
    """Probability per cell that it holds the fire; see the module docstring for the model.

    Cells are indexed (i, j): i along north, j along east; cell (i, j) has its centre at
    ((i + 0.5) c, (j + 0.5) c), c the cell size. Flat per-cell arrays use index i * cells_per_side + j;
    hypothesis h belongs to cell h // per_cell (subcells^2 sub-positions x plume tilts).

    Several fires (docs/strategy.md, "Several fires"): `known` fires, as hot spots (n, e, tilt_n,
    tilt_e) found earlier, join the ambient as nuisances with flat priors on their strengths, so the
    belief is over one more fire with those explained away; cells within EXCLUDED_CELLS of a known
    fire hold no prior mass (a fire there is the known one). With null_prior > 0 one more hypothesis says
    there is no further fire (its kernel is zero everywhere): p_fire is then the probability that
    there is one, and p the distribution of where, given that there is.
    """

    def __init__(self, geometry: Geometry, strength_mean_k: float = 50.0, strength_sd_k: float = 25.0,
                 sigma_k: float | None = None, subcells: int = 1, outlier_rate: float = 0.0,
                 outlier_range_k: float = 100.0, wind_ne_m_s: tuple = (0.0, 0.0),
                 plume_rise_m_s: tuple = PLUME_RISE_M_S, known: tuple = (), null_prior: float = 0.0):
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
        if not 0.0 <= null_prior < 1.0:
            raise ValueError("null_prior must be within 0..1 (1 excluded)")
        self.geometry = geometry
        self.size = geometry.cells_per_side
        self.cell_m = geometry.cell_size_m
        self.subcells = int(subcells)
        self.tilts = plume_tilts(wind_ne_m_s, plume_rise_m_s)  # (n, e) metres per metre of height
        self.upright = self.tilts == [(0.0, 0.0)]  # calm: the plume rises straight up
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
        self.known = np.asarray(known, dtype=float).reshape(-1, 4)
        self.null_prior = float(null_prior)
        self.cell_log_prior = np.zeros(self.centres_n.size)
        for fire_n, fire_e, _, _ in self.known:  # the block around a known fire is that fire
            i, j = geometry.cell_of(fire_n, fire_e)
            block = np.zeros((self.size, self.size), dtype=bool)
            r = EXCLUDED_CELLS
            block[max(0, i - r):i + r + 1, max(0, j - r):j + r + 1] = True
            self.cell_log_prior[block.ravel()] = EXCLUDED_LOG_PRIOR
        self.cells_allowed = int((self.cell_log_prior == 0).sum())
        hyps = self.hyp_n.size + (1 if self.null_prior > 0 else 0)  # the last: no further fire
        self.n = 0
        self.z_ref = 0.0
        self.sums = Sums(hyps, 3 * len(self.known))  # per hypothesis: the (weighted) readings' sums
        self.log_ev = np.zeros(hyps)             # ... and the log evidence once filtering
        self.frame_ev = np.zeros(hyps)           # the thermal frames' log likelihoods (add_frame), summed
        self.frames = 0
        self._burn_in: list[tuple] = []          # the first readings' terms (Sums.parts)
        self.closest_r2 = np.full(self.centres_n.size, np.inf)  # per cell: nearest reading, squared [m^2]
        self._cache = None
        self._cells_cache = None  # (the _stats it was taken from, the cells array, _cells_fit's answer)

    # ----- updates ---------------------------------------------------------------------------------
    def kernel_at(self, n, e, height_m: float, hyps: np.ndarray | None = None) -> np.ndarray:
        """g_q at point(s) (n, e) for every cell hypothesis (or those in hyps): shape (H,) for a
        scalar point, (K, H) for K points."""
        qn = self.hyp_n if hyps is None else self.hyp_n[hyps]
        qe = self.hyp_e if hyps is None else self.hyp_e[hyps]
        if self.hyp_tilt is not None:  # the hot spot is downwind of the fire by tilt x height
            tn, te = self.hyp_tilt if hyps is None else (self.hyp_tilt[0][hyps], self.hyp_tilt[1][hyps])
            qn, qe = qn + height_m * tn, qe + height_m * te
        n = np.asarray(n, dtype=float)
        e = np.asarray(e, dtype=float)
        r2 = (n[..., None] - qn) ** 2 + (e[..., None] - qe) ** 2
        return kernel_value(self.kernel, r2, height_m, self.plume_sigma_m)

    def known_kernels_at(self, n, e, height_m: float) -> np.ndarray:
        """The nuisance regressors of the known fires at point(s) (n, e): per fire its kernel and the
        kernel's change when the fire moves by KNOWN_SHIFT_M north and east (see below); shape
        (3m,), or (K, 3m) for K points.

        A known fire's hot spot is fitted, not exact: a few metres off, its kernel leaves a two-lobed
        residual beside it that a search for the next fire would take for one. To first order a shift
        d of the hot spot adds A (d . grad_q g), linear in the unknown A d: so the two slopes join the
        nuisances with flat priors, and the position error is integrated out with the strength."""
        if not len(self.known):
            return np.zeros(np.shape(n) + (0,))
        n = np.asarray(n, dtype=float)[..., None]
        e = np.asarray(e, dtype=float)[..., None]
        kn = self.known[:, 0] + height_m * self.known[:, 2]
        ke = self.known[:, 1] + height_m * self.known[:, 3]
        d = KNOWN_SHIFT_M

        def g(dn, de):
            return kernel_value(self.kernel, (n - kn - dn) ** 2 + (e - ke - de) ** 2, height_m, self.plume_sigma_m)
        columns = (g(0.0, 0.0), g(d, 0.0) - g(-d, 0.0), g(0.0, d) - g(0.0, -d))
        return np.stack(columns, axis=-1).reshape(n.shape[:-1] + (3 * len(self.known),))

    def hot_spot(self, index) -> tuple[float, float, float, float]:
        """The likeliest hypothesis of cell `index` as a known fire: (n, e, tilt_n, tilt_e)."""
        hyp = int(self._stats()[4][index[0] * self.size + index[1]])
        tn, te = (0.0, 0.0) if self.hyp_tilt is None else (self.hyp_tilt[0][hyp], self.hyp_tilt[1][hyp])
        return float(self.hyp_n[hyp]), float(self.hyp_e[hyp]), float(tn), float(te)

    def update(self, n: float, e: float, z: float, height_m: float) -> None:
        """Add one reading z taken at (n, e) and height_m above ground."""
        if not math.isfinite(z):
            raise ValueError(f"reading must be finite, got {z!r}")
        g = self.kernel_at(n, e, height_m)
        if self.null_prior > 0:
            g = np.append(g, 0.0)
        k = self.known_kernels_at(n, e, height_m)
        if self.n == 0:
            self.z_ref = float(z)
        parts = Sums.parts(g, k, float(z) - self.z_ref)
        self.n += 1
        if self.n <= BURN_IN:
            self.sums.add(parts, 1.0)
            self._burn_in.append(parts)
            if self.n == BURN_IN:
                self._end_burn_in()
        else:
            self._filter(parts, k)
        np.minimum(self.closest_r2, (self.centres_n - n) ** 2 + (self.centres_e - e) ** 2, out=self.closest_r2)
        self._cache = None

    def add_frame(self, log_likelihood: np.ndarray, frame) -> None:
        """A thermal frame's evidence (frame.py: its log likelihood per hypothesis, the null's
        last); the cells whose centre it saw count as looked at from right above (closest_r2).
        Independent of the point readings given the fire, so the two multiply."""
        if log_likelihood.shape != self.frame_ev.shape or not np.all(np.isfinite(log_likelihood)):
            raise ValueError("a frame's log likelihood needs one finite value per hypothesis")
        self.frame_ev += log_likelihood
        self.frames += 1
        self.closest_r2[frame.contains(self.centres_n, self.centres_e)] = 0.0
        self._cache = None

    def update_together(self, readings: list[tuple]) -> None:
        """update() for several readings at once, each judged against the belief as it was before
        them (not against the others): one fit and one pass for all, at a rebuild's cost per reading
        where one by one, with known fires, a reading costs ten to twenty times more (as the rebuild
        catches up with the readings taken while it ran). Past the burn-in only."""
        if self.n < BURN_IN or not readings:
            for n, e, z, height_m in readings:
                self.update(n, e, z, height_m)
            return
        data = np.asarray(readings, dtype=float)
        if not np.isfinite(data).all():
            raise ValueError("readings must be finite")
        north, east, z, height = data.T
        g, k = self._kernel_rows(north, east, height)
        y = z - self.z_ref
        both, weight = self._judged(g, k, y[:, None])
        self.log_ev += both.sum(axis=0)
        for name, value in zip(self.sums.fields, _weighted_sums(weight, g, k, y)):
            getattr(self.sums, name)[...] += value
        self.n += len(data)
        self._note_positions(north, east)
        self._cache = None

    def _kernel_rows(self, north: np.ndarray, east: np.ndarray, height: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Per reading the kernels of every hypothesis, the null's a zero (R, H), and the known
        fires' regressors (R, m)."""
        g = np.zeros((len(north), self.sums.w.size))
        g[:, :self.hyp_n.size] = [self.kernel_at(a, b, h) for a, b, h in zip(north, east, height)]
        k = np.array([self.known_kernels_at(a, b, h) for a, b, h in zip(north, east, height)]).reshape(len(north), -1)
        return g, k

    def _note_positions(self, north: np.ndarray, east: np.ndarray, rows: int = 200) -> None:
        """closest_r2 with readings at these positions, `rows` at a time (one array per block, not
        per reading: a thousand readings took 10-15 ms one by one)."""
        for a in range(0, len(north), rows):
            n, e = north[a:a + rows, None], east[a:a + rows, None]
            nearest = ((self.centres_n - n) ** 2 + (self.centres_e - e) ** 2).min(axis=0)
            np.minimum(self.closest_r2, nearest, out=self.closest_r2)

    def absorb(self, readings: list[tuple]) -> None:
        """Add readings (n, e, z, height_m) to a belief that has none yet, all at once (the module
        docstring, "Rebuilding"): the same belief the filter would reach, up to how it judges
        outliers, in one pass over the readings instead of one per reading."""
        for _ in self.absorbing(readings):
            pass

    def absorbing(self, readings: list[tuple], chunk: int = ABSORB_CHUNK) -> Iterator[None]:
        """absorb, a chunk at a time: yields after each chunk of each pass over the readings, so
        that a caller can spread a rebuild over several steps. A chunk is `chunk` readings of the
        weighted pass (or of the updates one by one), KERNEL_PASS_CHUNKS and PLAIN_PASS_CHUNKS times
        as many of the other two. The belief is whole only once the generator is done; the sums
        are the same up to rounding."""
        if self.n or len(readings) <= BURN_IN or not len(self.known):
            # without a known fire the filter's own update is the cheaper: its fit needs no Gram
            # matrix per hypothesis, and the joint round's N x H passes then cost more
            for i, (n, e, z, height_m) in enumerate(readings, 1):
                self.update(n, e, z, height_m)
                if i % chunk == 0:
                    yield
            return
        data = np.asarray(readings, dtype=float)
        if not np.isfinite(data).all():
            raise ValueError("readings must be finite")
        north, east, z, height = data.T
        chunks, kernel_chunks, plain_chunks = ([slice(a, a + rows) for a in range(0, len(data), rows)] for rows in
                                               (chunk, KERNEL_PASS_CHUNKS * chunk, PLAIN_PASS_CHUNKS * chunk))
        hyps = self.hyp_n.size + (1 if self.null_prior > 0 else 0)
        gs = np.zeros((len(data), hyps))  # (N, hypotheses): the null's kernel stays zero
        ks = np.empty((len(data), 3 * len(self.known)))
        for part in kernel_chunks:
            gs[part], ks[part] = self._kernel_rows(north[part], east[part], height[part])
            yield
        self.z_ref = float(z[0])
        y = z - self.z_ref
        sums = None
        for part in plain_chunks:
            sums = _add_sums(sums, _weighted_sums(None, gs[part], ks[part], y[part]))
            yield
        bound = None
        if self.outlier_rate > 0:
            # log odds of inlier over outlier at a residual of 0: the density ratio of the two
            level = self._log_inlier - 0.5 * math.log(2.0 * math.pi * self.s2) - self._log_outlier
            for _ in range(ABSORB_ROUNDS):
                fit = Fit.of(*sums, evidence=False)
                precision, h = fit.strength(self.mu_a, self.sa2, self.s2)
                sums, bound = None, np.zeros(hyps)
                for part in chunks:
                    # per reading and hypothesis: the probability it is no outlier. Single
                    # precision: the weights and the bound's terms need no more, and the
                    # exponentials over N x H entries are most of a rebuild's time
                    residual = (y[part, None] - fit.fitted(h / precision, gs[part], ks[part])).astype(np.float32)
                    residual *= residual
                    residual *= np.float32(-0.5 / self.s2)
                    residual += np.float32(level)
                    r = expit(residual)
                    # a hypothesis that calls every reading wild would be left with no weight at all
                    np.maximum(r, np.float32(R_FLOOR), out=r)
                    sums = _add_sums(sums, _weighted_sums(r, gs[part], ks[part], y[part]))
                    # per reading r log(1 - w) + (1 - r) log(w / range) + H(r)
                    #   = log(w / range) + r (log(1 - w) - log(w / range)) - r log r - (1 - r) log(1 - r)
                    terms = r * np.float32(self._log_inlier - self._log_outlier)
                    terms -= xlogy(r, r)
                    terms -= xlogy(1 - r, 1 - r)
                    bound += terms.sum(axis=0, dtype=np.float64)
                    yield
        for name, value in zip(self.sums.fields, sums):
            getattr(self.sums, name)[...] = value
        self.log_ev = self._log_marginal(Fit.of(*sums))
        if bound is not None:
            self.log_ev += len(data) * self._log_outlier + bound
        self.n = len(data)
        self._burn_in = []
        self._note_positions(north, east)
        self._cache = None

    def _log_marginal(self, fit: Fit) -> np.ndarray:
        """log p(readings | q) of the Gaussian model for (weighted) sums, the nuisances (ambient, known
        fires' strengths) and A integrated out, up to a constant that depends on neither the
        hypothesis nor the number of readings."""
        precision, h = fit.strength(self.mu_a, self.sa2, self.s2)
        nuisances = 1 + 3 * len(self.known)
        return (0.5 * h * h / precision - 0.5 * np.log(precision) - 0.5 * fit.zz / self.s2
                - 0.5 * (fit.w - nuisances) * math.log(2.0 * math.pi * self.s2) - 0.5 * fit.logdet)

    def _gaussian_log_marginal(self, *sums) -> np.ndarray:
        """_log_marginal of sums given in Sums.FIELDS order."""
        return self._log_marginal(Fit.of(*sums))

    def _burn_in_cases(self) -> tuple[np.ndarray, list[tuple[int, ...]]]:
        """log p(readings, case | q) for each case of which burn-in readings are outliers (none,
        one or two of them), and the cases (tuples of reading indices)."""
        m = len(self._burn_in)
        cases = [()]
        if self.outlier_rate > 0.0:
            cases += [c for k in range(1, min(BURN_IN_OUTLIERS, m - 1) + 1)
                      for c in itertools.combinations(range(m), k)]
        rows = []
        for case in cases:
            prior = (m - len(case)) * self._log_inlier + (len(case) * self._log_outlier if case else 0.0)
            rows.append(prior + self._gaussian_log_marginal(*self.sums.without([self._burn_in[k] for k in case])))
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
        for k, parts in enumerate(self._burn_in):
            p_outlier = sum(posterior[c] for c, case in enumerate(cases) if k in case)
            if not isinstance(p_outlier, int):  # in at least one case
                self.sums.add(parts, -p_outlier)
        self._burn_in = []

    def _filter(self, parts: tuple, k: np.ndarray) -> None:
        """A reading after the burn-in: its predictive density (the mixture) joins the evidence,
        and it joins the sums weighted by its probability of being no outlier."""
        both, weight = self._judged(parts[3], k, parts[1])
        self.log_ev += both
        self.sums.add(parts, 1.0 if self.outlier_rate <= 0.0 else weight)

    def _judged(self, g: np.ndarray, k: np.ndarray, y) -> tuple[np.ndarray, np.ndarray]:
        """Readings y (a number, or (R, 1)) with kernels g (..., H) and known fires' k (..., m)
        against the belief as it is: per hypothesis the log of each one's predictive density (the
        mixture with the outliers), and its probability of being no outlier."""
        fit = Fit.of(*self.sums.as_tuple(), evidence=False)
        precision, h = fit.strength(self.mu_a, self.sa2, self.s2)
        fit_z, dg, leverage = fit.at(g, k)
        mean = fit_z + (h / precision) * dg
        var = self.s2 * (1.0 + leverage) + dg * dg / precision
        log_in = self._log_inlier - 0.5 * np.log(2.0 * math.pi * var) - 0.5 * (y - mean) ** 2 / var
        if self.outlier_rate > 0.0:
            both = np.logaddexp(log_in, self._log_outlier)
            return both, np.exp(log_in - both)
        return log_in, np.ones_like(log_in)

    # ----- the posterior over cells ----------------------------------------------------------------
    def _stats(self):
        """Cached until the next update: the Fit per hypothesis (None before any reading), the log
        evidence per hypothesis, per cell (p, log p, representative hypothesis = the cell's most
        likely) and the probability that there is a (further) fire."""
        if self._cache is None:
            cells = self.centres_n.size
            cell_hyps = cells * self.per_cell
            if self.n == 0:
                fit, log_ev = None, np.zeros(self.sums.w.size)
            else:
                fit = Fit.of(*self.sums.as_tuple(), evidence=False)
                # before the burn-in ends all readings are in with weight 1: its cases, exactly
                log_ev = self._log_total(self._burn_in_cases()[0]) if self.n < BURN_IN else self.log_ev
            if self.frames:
                log_ev = log_ev + self.frame_ev
            cell_ev = log_ev[:cell_hyps] + np.repeat(self.cell_log_prior, self.per_cell)
            top = cell_ev.max()
            sub = np.exp(cell_ev - top).reshape(cells, self.per_cell)
            rep = np.argmax(sub, axis=1) + np.arange(cells) * self.per_cell
            w = sub.sum(axis=1)
            total = w.sum()
            p = w / total
            with np.errstate(divide="ignore"):
                logp = np.log(w) - math.log(total)
            # cells whose every sub-position underflowed: recompute their log mass exactly
            bad = ~np.isfinite(logp)
            if bad.any():
                le = cell_ev.reshape(cells, self.per_cell)[bad]
                mx = le.max(axis=1)
                logp[bad] = mx + np.log(np.exp(le - mx[:, None]).sum(axis=1)) - top - math.log(total)
            p_fire = 1.0
            if self.null_prior > 0:  # a fire's evidence is the mean over the allowed cells' hypotheses
                log_fire = top + math.log(total) - math.log(self.cells_allowed * self.per_cell) \
                    + math.log1p(-self.null_prior)
                log_none = log_ev[-1] + math.log(self.null_prior)
                p_fire = float(1.0 / (1.0 + math.exp(min(700.0, log_none - log_fire))))
            self._cache = (fit, log_ev, p, logp, rep, p_fire)
        return self._cache

    @property
    def p_fire(self) -> float:
        """Probability that there is a (further) fire: 1 without a null hypothesis."""
        return self._stats()[5]

    @property
    def p(self) -> np.ndarray:
        """Probabilities as a flat array over cells (read-only view; do not modify)."""
        return self._stats()[2]

    @property
    def log_p(self) -> np.ndarray:
        return self._stats()[3]

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
    def _cells_fit(self, cells: np.ndarray | None):
        """The representative hypotheses of `cells` (all when None), their Fit and strength's
        mean and precision: kept while the belief and the cells asked about stay the same (a
        planner asks about the same cells for every block of candidates)."""
        stats = self._stats()
        kept = self._cells_cache
        if kept is not None and kept[0] is stats and kept[1] is cells:
            return kept[2]
        fit, rep = stats[0], stats[4]
        hyps = rep if cells is None else rep[cells]
        fit = fit.take(hyps)
        precision, h = fit.strength(self.mu_a, self.sa2, self.s2)
        answer = (hyps, fit, h / precision, precision)
        self._cells_cache = (stats, cells, answer)
        return answer

    def predictive(self, n, e, height_m: float | None = None, cells: np.ndarray | None = None):
        """Predictive mean and variance of a reading at point(s) (n, e), per cell.

        Given hypothesis q and the readings so far (weighted as the hypothesis weighs them, W their
        total weight), A ~ N(h/P, 1/P) and b | A ~ N(mean(z) - A mean(g), s2/W), so a new reading with
        kernel value g has mean  mean(z) + E[A] (g - mean(g))  and variance s2 (1 + 1/W) + (g - mean(g))^2 / P
        (with known fires, the same after projecting out all nuisances: Fit.at); an outlier is not
        predicted (the planner asks what a good reading would tell). A cell is represented by its most likely sub-position (its
        centre when subcells = 1). Shapes: (cells,) for a scalar point, (K, cells) for K points.
        """
        if self.n == 0:
            raise ValueError("no reading yet: the flat ambient prior makes the prediction improper")
        height = self.geometry.survey_alt_m if height_m is None else height_m
        hyps, fit, a_mean, precision = self._cells_fit(cells)
        k = self.known_kernels_at(n, e, height)
        fit_z, dg, leverage = fit.at(self.kernel_at(n, e, height, hyps), k)
        mean = self.z_ref + fit_z + a_mean * dg
        var = self.s2 * (1.0 + leverage) + dg * dg / precision
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

"""A thermal frame as evidence for the belief (issue 32, item 5): the likelihood of what a downward
camera saw, for every hypothesis of belief.py, "the fire is at sub-position q".

What a frame tells. The camera (sim/thermal_camera.py, docs/thermal_camera.md) resolves the burning
layer itself: a fire in view is a hot spot a couple of metres wide that peaks at ambient + strength,
tens of kelvin, where the readout noise is 0.05 K. So a frame is reduced to two figures and its
ground rectangle (FrameObservation): the peak excess E over the frame's own baseline (a low
percentile of the frame: the camera's absolute calibration is not trusted, and the baseline is
its own nuisance per frame) and, when E reaches DETECT_K, where the peak is. The likelihood of
that, per hypothesis, with the fire's strength A ~ the belief's prior N(mu_A, sd_A^2) kept positive:

  - the peak lands where the fire's hot spot is, or at the nearest point of the frame when the hot
    spot is outside it: for a fire uniform on q's tile (the square of side cell / subcells around q
    that its sub-position stands for), the peak's position along each axis is that uniform,
    clipped to the frame (a point mass at the frame's edge for the part outside), blurred by
    EDGE_SIGMA_M (pixels, optics); along north and east independently (a level nadir frame at
    yaw 0 is an axis-aligned rectangle on the ground);
  - E = A g(d), d the distance from q's hot spot to the frame, g the world's kernel at the camera's
    burning layer (emission height): A itself when the hot spot is in view, the kernel's tail at
    the frame's edge when it is just outside;
  - no peak (E < DETECT_K): the probability that A g(d) < DETECT_K: small for a hypothesis in view,
    about 1 for one far away;
  - a frame is, with prior probability FRAME_OUTLIER_RATE, wild: its (peak, E) uniform over the
    frame and OUTLIER_RANGE_K whatever the fire, as belief.py's wild readings. One frame can then
    move a hypothesis's odds only so far: from a flat belief over 1,600 cells one frame's fire
    takes about 0.4 of the mass (its cell about 1,000 times as likely as before against a far
    one); a fire is declared from one glimpse only where the point readings already point to it.

Every hypothesis far from the frame gets the same likelihood (the model's part is 0 with a peak, 1
without), so cells outside every frame keep their odds against each other: a frame moves mass
between the cells it sees (and those just beside it, whose fire would show at its edge) and the
rest, never among the rest. The cost is a few vector operations over the hypotheses per frame, none
per pixel: the frame's reduction is one percentile and one argmax over its pixels.

A frame from a flying vehicle is tilted (the lean of its flight) and turned (its heading): its
footprint is a quadrilateral, not an axis-aligned rectangle. reduce_footprint judges such a frame on
the largest axis-aligned rectangle of the footprint's own proportions, centred on it, that lies
inside it, and on the pixels whose ground points fall in that rectangle: it claims to have seen less
than it did, never more, so a frame's "nothing here" covers only ground it saw. A level frame at
yaw 0 (the decision-level episodes') is its whole self.

Not modelled: several fires in one frame (the hottest wins), frames above the sky line.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from scipy.special import log_ndtr, ndtr

from firefly.sim.fire import kernel_value

DETECT_K = 5.0             # a peak this far above the frame's baseline is a hot spot (100 x the NETD)
BASELINE_PERCENTILE = 5.0  # the frame's own ambient: a kernel's tail lifts most pixels a little
EDGE_SIGMA_M = 0.3         # the peak's position blur: pixel (0.2 m at 30 m), optics, the layer's parallax
FRAME_OUTLIER_RATE = 0.01  # prior share of wild frames
OUTLIER_RANGE_K = 100.0    # the span a wild frame's peak may take
AXIS_TOLERANCE = 1e-6      # how far from axis-aligned (relative) a frame's corners may be
# Several fires: a frame keeps its hottest PEAKS hot spots, each the hottest pixel more than
# PEAK_APART_M from the hotter ones; a belief that knows a fire passes over the peaks within
# KNOWN_MASK_M of it (a strong fire's tail stays above DETECT_K out to 8 m) and judges the frame by
# the hottest of the rest: a frame over a find still rules out a further fire elsewhere in view.
PEAKS = 3
PEAK_APART_M = 12.0
KNOWN_MASK_M = 12.0


@dataclass(frozen=True)
class FrameObservation:
    """A frame reduced to what the belief needs: its ground rectangle, its peak excess over its own
    baseline and where the peak is (None below DETECT_K), and the camera's burning-layer height."""
    n_lo: float
    n_hi: float
    e_lo: float
    e_hi: float
    excess_k: float
    peak: tuple[float, float] | None
    emission_height_m: float = 2.0
    others: tuple = ()  # the next hot spots, (n, e, excess_k), PEAK_APART_M from the hotter ones

    def judged(self, known: np.ndarray) -> "FrameObservation":
        """The frame as a belief with these known fires' hot spots (n, e rows) judges it: its
        hottest peak away from all of them, or none; the frame itself when there are none."""
        if not len(known) or self.peak is None:
            return self
        for n, e, excess in ((*self.peak, self.excess_k), *self.others):
            if np.min(np.hypot(known[:, 0] - n, known[:, 1] - e)) > KNOWN_MASK_M:
                return dataclasses.replace(self, excess_k=excess, peak=(n, e), others=())
        rest = max((x for _, _, x in self.others), default=0.0)
        return dataclasses.replace(self, excess_k=min(rest, DETECT_K * 0.999), peak=None, others=())

    @property
    def area_m2(self) -> float:
        return (self.n_hi - self.n_lo) * (self.e_hi - self.e_lo)

    def contains(self, n, e) -> np.ndarray:
        n, e = np.asarray(n, dtype=float), np.asarray(e, dtype=float)
        return (n >= self.n_lo) & (n <= self.n_hi) & (e >= self.e_lo) & (e <= self.e_hi)


def reduce_frame(image: np.ndarray, north: np.ndarray, east: np.ndarray, corners: np.ndarray,
                 emission_height_m: float = 2.0) -> FrameObservation:
    """A frame (deg C per pixel), its pixels' ground points and its outer corners (the camera's
    footprint and footprint_corners) as a FrameObservation. Raises ValueError for a frame that
    sees sky or is not an axis-aligned rectangle on the ground."""
    corners = np.asarray(corners, dtype=float)
    if not np.isfinite(corners).all() or not np.isfinite(image).all():
        raise ValueError("a frame must see only ground, with finite readings")
    n_lo, n_hi = float(corners[:, 0].min()), float(corners[:, 0].max())
    e_lo, e_hi = float(corners[:, 1].min()), float(corners[:, 1].max())
    scale = max(n_hi - n_lo, e_hi - e_lo, 1e-9)
    for v in corners:  # every corner on the bounding box's corners: axis-aligned
        if min(abs(v[0] - n_lo), abs(v[0] - n_hi)) > AXIS_TOLERANCE * scale or \
                min(abs(v[1] - e_lo), abs(v[1] - e_hi)) > AXIS_TOLERANCE * scale:
            raise ValueError("the frame's footprint must be an axis-aligned rectangle (level, nadir, yaw 0)")
    values = np.asarray(image, dtype=float)
    excess = (values - np.percentile(values, BASELINE_PERCENTILE)).ravel()
    north, east = np.asarray(north).ravel(), np.asarray(east).ravel()
    k = int(np.argmax(excess))
    top = float(excess[k])
    if top < DETECT_K:
        return FrameObservation(n_lo, n_hi, e_lo, e_hi, top, None, emission_height_m)
    peaks = [(float(north[k]), float(east[k]), top)]
    left = excess.copy()
    for _ in range(PEAKS - 1):  # the next hot spots, away from those taken
        n, e, _ = peaks[-1]
        left[np.hypot(north - n, east - e) <= PEAK_APART_M] = -np.inf
        k = int(np.argmax(left))
        if not left[k] >= DETECT_K:
            break
        peaks.append((float(north[k]), float(east[k]), float(left[k])))
    return FrameObservation(n_lo, n_hi, e_lo, e_hi, top, peaks[0][:2], emission_height_m, tuple(peaks[1:]))


def reduce_footprint(image: np.ndarray, north: np.ndarray, east: np.ndarray, corners: np.ndarray,
                     emission_height_m: float = 2.0) -> FrameObservation:
    """reduce_frame of the part of a frame inside the largest axis-aligned rectangle of its
    footprint (its four ground corners) that keeps the bounding box's proportions and centre: the
    whole frame when it is already axis-aligned."""
    corners = np.asarray(corners, dtype=float)
    if not np.isfinite(corners).all():
        raise ValueError("a frame must see only ground, with finite readings")
    if _axis_aligned(corners):
        return reduce_frame(image, north, east, corners, emission_height_m)
    rect = inner_rectangle(corners)
    n_lo, n_hi, e_lo, e_hi = rect
    north, east = np.asarray(north, dtype=float), np.asarray(east, dtype=float)
    inside = (north >= n_lo) & (north <= n_hi) & (east >= e_lo) & (east <= e_hi)
    if not inside.any():
        raise ValueError("the frame's footprint holds no axis-aligned rectangle with a pixel in it")
    box = np.array([[n_lo, e_lo], [n_lo, e_hi], [n_hi, e_hi], [n_hi, e_lo]])
    return reduce_frame(np.asarray(image)[inside], north[inside], east[inside], box, emission_height_m)


def _axis_aligned(corners: np.ndarray) -> bool:
    n_lo, n_hi = corners[:, 0].min(), corners[:, 0].max()
    e_lo, e_hi = corners[:, 1].min(), corners[:, 1].max()
    scale = max(n_hi - n_lo, e_hi - e_lo, 1e-9)
    return all(min(abs(v[0] - n_lo), abs(v[0] - n_hi)) <= AXIS_TOLERANCE * scale
               and min(abs(v[1] - e_lo), abs(v[1] - e_hi)) <= AXIS_TOLERANCE * scale for v in corners)


def inner_rectangle(corners: np.ndarray) -> tuple[float, float, float, float]:
    """(n_lo, n_hi, e_lo, e_hi): the largest rectangle with the corners' bounding box's centre and
    proportions inside the convex quadrilateral they make (a footprint's ground corners, any order)."""
    corners = np.asarray(corners, dtype=float)
    centre = corners.mean(axis=0)
    ring = corners[np.argsort(np.arctan2(corners[:, 1] - centre[1], corners[:, 0] - centre[0]))]
    half = 0.5 * np.ptp(corners, axis=0)
    # Each edge a.x <= b (inside): a box corner c + s h stays inside for s <= (b - a.c) / (a.h),
    # the worst of its four corners; the largest s is the least over the edges.
    scale = 1.0
    for p, q in zip(ring, np.roll(ring, -1, axis=0)):
        normal = np.array([q[1] - p[1], -(q[0] - p[0])])  # outward or inward: fixed by the centre's side
        if normal @ (centre - p) > 0:
            normal = -normal
        room = normal @ (p - centre)  # > 0: the centre is inside
        reach = abs(normal[0]) * half[0] + abs(normal[1]) * half[1]
        if reach > 0:
            scale = min(scale, room / reach)
    scale = max(scale, 0.0)
    return (float(centre[0] - scale * half[0]), float(centre[0] + scale * half[0]),
            float(centre[1] - scale * half[1]), float(centre[1] + scale * half[1]))


def _log_axis_density(x: float, centre: np.ndarray, half: float, lo: float, hi: float) -> np.ndarray:
    """log density at x of the peak's position along one axis for a fire uniform on
    [centre - half, centre + half]: that uniform clipped to the frame's [lo, hi] (the parts outside
    as point masses at the edges), blurred by EDGE_SIGMA_M."""
    s = EDGE_SIGMA_M
    a, b = centre - half, centre + half
    inner_lo, inner_hi = np.clip(a, lo, hi), np.clip(b, lo, hi)
    width = 2.0 * half
    # the uniform part inside the frame: (Phi((x - lo') / s) - Phi((x - hi') / s)) / width
    inside = (ndtr((x - inner_lo) / s) - ndtr((x - inner_hi) / s)) / width
    gauss = math.exp(-0.5 * ((x - lo) / s) ** 2) / (s * math.sqrt(2.0 * math.pi)), \
        math.exp(-0.5 * ((x - hi) / s) ** 2) / (s * math.sqrt(2.0 * math.pi))
    below = np.clip(lo - a, 0.0, width) / width  # the tile's share beyond each edge
    above = np.clip(b - hi, 0.0, width) / width
    return np.log(np.maximum(inside + below * gauss[0] + above * gauss[1], 1e-300))


class StrengthPrior:
    """The fire strength's prior, the belief's N(mu, sd^2) kept positive."""

    def __init__(self, mean_k: float, sd_k: float):
        self.mean, self.sd = float(mean_k), float(sd_k)
        self.log_mass = float(log_ndtr(self.mean / self.sd))  # P(A > 0)

    def log_pdf(self, a: np.ndarray) -> np.ndarray:
        u = (a - self.mean) / self.sd
        out = -0.5 * u * u - math.log(self.sd * math.sqrt(2.0 * math.pi)) - self.log_mass
        return np.where(a > 0, out, -np.inf)

    def cdf(self, a: np.ndarray) -> np.ndarray:
        """P(A < a) for a >= 0."""
        lower = ndtr(-self.mean / self.sd)
        return np.clip((ndtr((a - self.mean) / self.sd) - lower) / math.exp(self.log_mass), 0.0, 1.0)


def frame_log_likelihood(belief, frame: FrameObservation) -> np.ndarray:
    """log p(frame | hypothesis) for every hypothesis of `belief` (its null, if it has one, last:
    no fire anywhere), up to a constant common to all; judged past the hot spots of the fires the
    belief knows (FrameObservation.judged)."""
    hn, he = belief.hyp_n, belief.hyp_e
    h = frame.emission_height_m
    known = belief.known
    frame = frame.judged(np.column_stack([known[:, 0] + h * known[:, 2], known[:, 1] + h * known[:, 3]]))
    if belief.hyp_tilt is not None:  # the hot spot leans downwind by tilt x the layer's height
        hn, he = hn + h * belief.hyp_tilt[0], he + h * belief.hyp_tilt[1]
    dn = np.maximum(np.maximum(frame.n_lo - hn, hn - frame.n_hi), 0.0)
    de = np.maximum(np.maximum(frame.e_lo - he, he - frame.e_hi), 0.0)
    g = kernel_value(belief.kernel, dn * dn + de * de, h, belief.plume_sigma_m)
    prior = StrengthPrior(belief.mu_a, math.sqrt(belief.sa2))
    w = FRAME_OUTLIER_RATE
    if frame.peak is None:
        # P(A g < DETECT_K): g > 0 always (the kernels never vanish), tiny g gives 1
        model = prior.cdf(DETECT_K / np.maximum(g, 1e-300))
        outlier = DETECT_K / OUTLIER_RANGE_K
        ll = np.log((1.0 - w) * model + w * outlier)
        null = math.log((1.0 - w) + w * outlier)
    else:
        half = 0.5 * belief.cell_m / belief.subcells
        log_where = (_log_axis_density(frame.peak[0], hn, half, frame.n_lo, frame.n_hi)
                     + _log_axis_density(frame.peak[1], he, half, frame.e_lo, frame.e_hi))
        gs = np.maximum(g, 1e-300)
        log_e = prior.log_pdf(frame.excess_k / gs) - np.log(gs)  # E = A g: the density of E
        log_model = math.log(1.0 - w) + log_where + log_e
        log_outlier = math.log(w) - math.log(max(frame.area_m2, 1e-9)) - math.log(OUTLIER_RANGE_K)
        ll = np.logaddexp(log_model, log_outlier)
        null = log_outlier
    if belief.sums.w.size > hn.size:  # the null hypothesis: no fire, so no peak unless wild
        ll = np.append(ll, null)
    return ll

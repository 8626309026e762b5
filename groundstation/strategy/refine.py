"""Where exactly the fires found so far are: a joint least-squares fit of their hot spots to every
reading (docs/strategy.md, "Several fires").

A find's hot spot comes from the belief's grid (sub-positions a third of a cell apart), and a
second search explains that fire away with the hot spot held fixed. Near the fire the kernel is
steep: a hot spot 3 m off leaves a two-lobed residual of several kelvin beside it, which the next
search would take for another fire. So before each new search the found hot spots are fitted,
continuously and together, to all readings: the positions by scipy's least_squares (trust region),
the ambient and the strengths as linear terms, with a soft-L1 loss so that the rare wild reading
does not pull them. Each hot spot stays within REACH_CELLS of where the grid put it, and keeps the
plume lean of its hypothesis.

The same fit, with FINAL_REACH_CELLS, places the finds when the search ends. Each find was
declared by a belief that held the others fixed (the slopes let them move only a little), so two
fires close together push each other's finds apart: with twin fires 40 m apart the second was
declared 15-20 m beyond its fire in one tuning episode in nine. Fitted together, both land on
their fires.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.optimize import least_squares

from firefly.sim.fire import kernel_value

from .belief import Geometry

REACH_CELLS = 1.0  # how far the fit may move a hot spot from the grid's choice during the search
FINAL_REACH_CELLS = 3.0  # ... and at its end
# Evaluations of the residuals the fit may spend: most fits took 8-18, and the rare one past 50
# (179 in 70 fits, 191 ms) crept along the bound of its reach, a thinking step's worth alone
MAX_EVALUATIONS = 30


def fit_hot_spots(geometry: Geometry, readings: list[tuple], spots: list[tuple], noise_k: float,
                  reach_cells: float = REACH_CELLS) -> tuple[list[tuple], list[float]]:
    """The hot spots (n, e, tilt_n, tilt_e) moved to fit the readings (n, e, z, height) jointly,
    each by at most reach_cells, and each fire's fitted strength [K] (infinite while there are
    too few readings to fit)."""
    if not spots or len(readings) < 3 * len(spots) + 3:
        return list(spots), [math.inf] * len(spots)
    data = np.asarray(readings, dtype=float)
    n, e, z, height = data.T
    tilts = np.array([s[2:] for s in spots])
    start = np.array([s[:2] for s in spots]).ravel()
    reach = reach_cells * geometry.cell_size_m

    def kernels(positions):
        q = positions.reshape(-1, 2)
        qn = q[:, 0] + height[:, None] * tilts[:, 0]
        qe = q[:, 1] + height[:, None] * tilts[:, 1]
        r2 = (n[:, None] - qn) ** 2 + (e[:, None] - qe) ** 2
        return kernel_value(geometry.kernel, r2, height[:, None], geometry.plume_sigma_m)

    def residual(params):
        positions, linear = params[:start.size], params[start.size:]
        return (linear[0] + kernels(positions) @ linear[1:] - z) / noise_k

    design = np.column_stack([np.ones_like(z), kernels(start)])
    linear0 = np.linalg.lstsq(design, z, rcond=None)[0]
    lo = np.concatenate([start - reach, np.full(linear0.size, -np.inf)])
    hi = np.concatenate([start + reach, np.full(linear0.size, np.inf)])
    fit = least_squares(residual, np.concatenate([start, linear0]), bounds=(lo, hi), loss="soft_l1", f_scale=3.0,
                        max_nfev=MAX_EVALUATIONS)
    positions = fit.x[:start.size].reshape(-1, 2)
    strengths = [float(k) for k in fit.x[start.size + 1:]]
    return [(float(p[0]), float(p[1]), float(t[0]), float(t[1])) for p, t in zip(positions, tilts)], strengths

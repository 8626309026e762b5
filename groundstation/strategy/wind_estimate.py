"""The wind, estimated from how the vehicle leans: what the companion can know when the vehicle's
WIND message says nothing (ArduCopter sends zero wind unless its EKF fuses the rotors' drag).

A multicopter flying at a steady velocity v through air moving at w tilts its thrust until the
thrust's horizontal share balances the drag of the air going past. With drag linear in the air
speed, k (v - w), and the thrust's vertical share holding the weight m g:

    lean = thrust_horizontal / thrust_vertical = c (v - w),   c = k / (m g)

`lean` is a horizontal (north, east) vector the companion reads from ATTITUDE (lean_of_attitude),
v from the vehicle's velocity. Neither c (the airframe's drag over its weight) nor w is known, but
the relation is linear in (c, d = -c w): lean = c v + d. Least squares over samples at two or more
different velocities (hovering, then one leg, is enough; the search's legs in many directions are
better) gives c and d, and w = -d / c, with its uncertainty from the residuals (delta method).

Only steady samples belong here: while the vehicle accelerates its lean also pushes it along. The
flight keeps samples whose velocity has been steady (flight/lean_samples.py); the decision-level
episodes model steady legs (evaluation/episodes.py).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

MIN_SAMPLES = 6       # before this many samples there is no estimate
MIN_SPEED_SPREAD = 1.0  # m/s: the velocities must differ by this much (rms about their mean) to separate c from w
MIN_LEAN_SD = 1e-3    # the residual's floor (a noiseless model must not claim an exact wind)
# A sample whose worse axis is off the first fit by more than this many times 1.4826 x the median
# of that worse-axis residual is left out of the second fit. The median of the worse of two axes
# is about 1.05 sigma, so the cut falls near 6 sigma of one axis: only gross errors go.
OUTLIER_SDS = 4.0


@dataclass(frozen=True)
class WindEstimate:
    air_ne_m_s: tuple[float, float]  # where the air goes, (north, east) m/s
    sd_m_s: float                    # standard error along the estimate's worst direction
    drag_per_weight: float           # c, per m/s
    lean_sd: float                   # the samples' spread about the fitted relation


def lean_of_attitude(roll: float, pitch: float, yaw: float) -> tuple[float, float]:
    """The thrust's horizontal share over its vertical share, as (north, east), from the attitude
    (radians, ZYX Euler as ATTITUDE sends it): where the vehicle leans to."""
    cr, sr, cp, sp, cy, sy = math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch), math.cos(yaw), math.sin(yaw)
    # the body's down axis in NED; the thrust points the other way
    down_n = cr * sp * cy + sr * sy
    down_e = cr * sp * sy - sr * cy
    down_d = cr * cp
    return -down_n / down_d, -down_e / down_d


class LeanWindEstimator:
    """Least squares of lean = c v + d over steady samples (the module docstring), robust: a sample
    the first fit leaves more than OUTLIER_SDS robust deviations off (a gust, a sample the link
    paired with the wrong instant) does not enter the second."""

    def __init__(self):
        self._rows: list[tuple[float, float, float, float]] = []  # (vn, ve, lean_n, lean_e)

    @property
    def n(self) -> int:
        return len(self._rows)

    def add(self, velocity_ne: tuple[float, float], lean_ne: tuple[float, float]) -> None:
        """One steady sample: the vehicle's velocity over ground [m/s] and its lean (lean_of_attitude)."""
        row = (float(velocity_ne[0]), float(velocity_ne[1]), float(lean_ne[0]), float(lean_ne[1]))
        if all(math.isfinite(x) for x in row):  # a sample the link mangled says nothing
            self._rows.append(row)

    def estimate(self) -> WindEstimate | None:
        """The wind, once the samples separate the drag from the wind; else None."""
        if self.n < MIN_SAMPLES:
            return None
        rows = np.array(self._rows)
        first = _fit(rows)
        if first is None:
            return None
        residual = np.abs(rows[:, 2:] - _predict(first[0], rows)).max(axis=1)
        spread = max(1.4826 * float(np.median(residual)), MIN_LEAN_SD)
        second = _fit(rows[residual <= OUTLIER_SDS * spread])
        return (second or first)[1]


def _predict(x: np.ndarray, rows: np.ndarray) -> np.ndarray:
    return x[0] * rows[:, :2] + x[1:]


def _fit(rows: np.ndarray) -> tuple[np.ndarray, WindEstimate] | None:
    """The least-squares (c, d_n, d_e) of the rows and the wind it gives, or None if the rows do not
    separate the drag from the wind."""
    v = rows[:, :2]
    n = len(rows)
    if n < MIN_SAMPLES or float(((v - v.mean(axis=0)) ** 2).sum(axis=1).mean()) < MIN_SPEED_SPREAD ** 2:
        return None
    # normal equations of x = (c, d_n, d_e) over both axes' rows
    ata = np.array([[float((v * v).sum()), v[:, 0].sum(), v[:, 1].sum()],
                    [v[:, 0].sum(), n, 0.0],
                    [v[:, 1].sum(), 0.0, n]])
    atb = np.array([float((v * rows[:, 2:]).sum()), rows[:, 2].sum(), rows[:, 3].sum()])
    try:
        inv = np.linalg.inv(ata)
    except np.linalg.LinAlgError:
        return None
    x = inv @ atb
    c, d = float(x[0]), x[1:]
    s2 = max(float(((rows[:, 2:] - _predict(x, rows)) ** 2).sum()) / (2 * n - 3), MIN_LEAN_SD ** 2)
    cov_x = s2 * inv
    if not c > 3.0 * math.sqrt(cov_x[0, 0]):
        return None  # the drag is not yet told from nothing (or the samples say it is negative)
    w = -d / c
    jac = np.array([[d[0] / c ** 2, -1.0 / c, 0.0], [d[1] / c ** 2, 0.0, -1.0 / c]])
    worst = float(np.linalg.eigvalsh(jac @ cov_x @ jac.T)[-1])
    return x, WindEstimate((float(w[0]), float(w[1])), math.sqrt(max(worst, 0.0)), c, math.sqrt(s2))

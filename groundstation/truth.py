"""How a fire search's declarations are judged against the world's true fires: a declared point
succeeds when its cell is within one cell (Chebyshev) of a fire's.

The truth belongs to no one layer: the episodes (evaluation/) judge with it and so does the
flight's truth report (flight/), which is why it lives below both.
"""
from __future__ import annotations

import math

from firefly.sim.fire import FireWorld

from .strategy.belief import Geometry


def within_one_cell(a: tuple[int, int], b: tuple[int, int]) -> bool:
    """Cells a and b are the same or neighbours (Chebyshev distance at most 1): how a declaration is judged."""
    return max(abs(a[0] - b[0]), abs(a[1] - b[1])) <= 1


def fires_found(world: FireWorld, declared: list[tuple[float, float]]) -> int:
    """How many of the world's fires have a declared point whose cell is within one cell of theirs
    (a point between two fires, more than a cell from each, finds neither)."""
    geometry = Geometry.from_world(world)
    cells = [geometry.cell_of(n, e) for n, e in declared]
    return sum(any(within_one_cell(c, geometry.cell_of(f.n_m, f.e_m)) for c in cells) for f in world.fires)


def judge(world: FireWorld, n: float, e: float) -> tuple[float, bool]:
    """Distance from a declared point to the nearest fire, and success: the declared cell within
    one cell (Chebyshev) of a fire's cell."""
    geometry = Geometry.from_world(world)
    declared = geometry.cell_of(n, e)
    errors = [math.hypot(n - f.n_m, e - f.e_m) for f in world.fires]
    within = any(within_one_cell(declared, geometry.cell_of(f.n_m, f.e_m)) for f in world.fires)
    return (min(errors) if errors else math.nan), within


def judge_all(world: FireWorld, declared: list[tuple[float, float]]) -> tuple[float, bool, list[bool]]:
    """judge() over several declared points: the worst error, success when there is at least one
    and every one is on a fire (a point between two fires is a failure, whatever the others), and
    each point's own verdict."""
    verdicts = [judge(world, n, e) for n, e in declared]
    ok = [v[1] for v in verdicts]
    if not verdicts:
        return math.nan, False, ok
    return max(v[0] for v in verdicts), all(ok), ok

"""A probe's result: named facts, each compared with the recording exactly or within a tolerance.

A fact is a value a client can observe (an ACK result, a mode, a text, a rate, a distance). Its
tolerance travels with the probe that measures it, and says why: the recording holds only values.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field


@dataclass(frozen=True)
class Tol:
    """How far a measured number may be from the reference's: |got - want| <= abs + rel*|want|."""
    abs: float = 0.0
    rel: float = 0.0
    why: str = ""

    def accepts(self, want: float, got: float) -> bool:
        return abs(got - want) <= self.abs + self.rel * abs(want)


@dataclass(frozen=True)
class PathTol:
    """How far a flown track, a list of [north, east] points, may be from the reference's: every
    point of each within `abs` metres of the other's track (the polylines' symmetric Hausdorff
    distance). With points=True the lists are sets of places (camera triggers): every place of
    each within `abs` of one of the other's."""
    abs: float
    why: str = ""
    points: bool = False

    def distance(self, want: list, got: list) -> float:
        near = _nearest_point if self.points else _nearest_on_polyline
        return max(max((near(p, got) for p in want), default=0.0), max((near(p, want) for p in got), default=0.0))

    def accepts(self, want: list, got: list) -> bool:
        if not want or not got:
            return not want and not got
        return self.distance(want, got) <= self.abs


def _nearest_point(p, places: list) -> float:
    return min((math.dist(p, q) for q in places), default=math.inf)


def _nearest_on_polyline(p, line: list) -> float:
    if len(line) == 1:
        return math.dist(p, line[0])
    best = math.inf
    for a, b in zip(line, line[1:]):
        dn, de = b[0] - a[0], b[1] - a[1]
        span = dn * dn + de * de
        t = 0.0 if span == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * dn + (p[1] - a[1]) * de) / span))
        best = min(best, math.hypot(p[0] - a[0] - t * dn, p[1] - a[1] - t * de))
    return best


def _is_path(value) -> bool:
    return isinstance(value, list) and all(isinstance(p, list) and len(p) == 2 for p in value)


@dataclass
class Trace:
    """The facts one probe observed, in the order it observed them."""
    values: dict = field(default_factory=dict)
    tolerances: dict = field(default_factory=dict)

    def fact(self, name: str, value, tol: Tol | PathTol | None = None) -> None:
        if name in self.values:
            raise ValueError(f"fact {name} recorded twice")
        self.values[name] = _plain(value)
        if tol is not None:
            self.tolerances[name] = tol


def _plain(value):
    """JSON-ready: tuples become lists, floats are rounded to what a client can see."""
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, float):
        return round(value, 3)
    return value


@dataclass(frozen=True)
class Check:
    area: str
    name: str          # probe/fact
    want: object
    got: object
    ok: bool
    tol: Tol | PathTol | None = None


def compare(area: str, probe: str, recorded: dict, trace: Trace) -> list[Check]:
    """One check per recorded fact: exact equality, or within the fact's tolerance for numbers.
    A fact the recording has and the probe did not observe is a failed check."""
    checks = []
    for name, want in recorded.items():
        got = trace.values.get(name, "<not observed>")
        tol = trace.tolerances.get(name)
        if isinstance(tol, PathTol):
            ok = _is_path(want) and _is_path(got) and tol.accepts(want, got)
        elif tol is not None and isinstance(want, (int, float)) and isinstance(got, (int, float)):
            ok = tol.accepts(want, got)
        elif tol is not None and isinstance(want, list) and isinstance(got, list) and len(want) == len(got) \
                and all(isinstance(x, (int, float)) for x in want + got):
            ok = all(tol.accepts(w, g) for w, g in zip(want, got))
        else:
            ok = want == got
        checks.append(Check(area, f"{probe}/{name}", want, got, ok, tol))
    return checks

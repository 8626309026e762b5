"""A probe's result: named facts, each compared with the recording exactly or within a tolerance.

A fact is a value a client can observe (an ACK result, a mode, a text, a rate, a distance). Its
tolerance travels with the probe that measures it, and says why: the recording holds only values.
"""
from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class Tol:
    """How far a measured number may be from the reference's: |got - want| <= abs + rel*|want|."""
    abs: float = 0.0
    rel: float = 0.0
    why: str = ""

    def accepts(self, want: float, got: float) -> bool:
        return abs(got - want) <= self.abs + self.rel * abs(want)


@dataclass
class Trace:
    """The facts one probe observed, in the order it observed them."""
    values: dict = field(default_factory=dict)
    tolerances: dict = field(default_factory=dict)

    def fact(self, name: str, value, tol: Tol | None = None) -> None:
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
    tol: Tol | None = None


def compare(area: str, probe: str, recorded: dict, trace: Trace) -> list[Check]:
    """One check per recorded fact: exact equality, or within the fact's tolerance for numbers.
    A fact the recording has and the probe did not observe is a failed check."""
    checks = []
    for name, want in recorded.items():
        got = trace.values.get(name, "<not observed>")
        tol = trace.tolerances.get(name)
        if tol is not None and isinstance(want, (int, float)) and isinstance(got, (int, float)):
            ok = tol.accepts(want, got)
        elif tol is not None and isinstance(want, list) and isinstance(got, list) and len(want) == len(got) \
                and all(isinstance(x, (int, float)) for x in want + got):
            ok = all(tol.accepts(w, g) for w, g in zip(want, got))
        else:
            ok = want == got
        checks.append(Check(area, f"{probe}/{name}", want, got, ok, tol))
    return checks

"""When to declare the fire (docs/strategy.md, "When to declare").

Declare as soon as the belief mass in the (2r+1) x (2r+1) block around the most likely cell (3 x 3
by default) reaches the threshold (0.95 by default). The cell declared is the one whose block holds
the most mass: usually the most likely cell itself, but when the mass straddles a cell border (a
fire near the edge between two cells, with a third cell beyond) the block centred on the middle of
the mass covers it better, and success is judged on exactly that block ("within one cell"). Its
block mass is at least the most likely cell's. When the search has to end without a confident
belief (its path budget spent), force() declares that cell anyway, marked forced. A belief that may
hold no (further) fire (a null hypothesis, belief.p_fire < 1) counts a block's mass times the
probability that there is a fire, and clear() says when it is confident there is none.

Confirmation: with confirm_m set, a confident belief is declared only once a reading has been
taken within confirm_m of the cell's centre; until then to_confirm() names the centre to fly to,
and the readings on the way either keep the belief confident (declared on arrival) or overturn it
(the policy takes over again; strategy/controller.py).
"""
from __future__ import annotations

from dataclasses import dataclass

from .belief import Belief


@dataclass(frozen=True)
class Declaration:
    position: tuple[float, float]  # (n, e) of the declared cell's centre, local metres
    index: tuple[int, int]         # (i_north, j_east) of the declared cell
    mass: float                    # belief mass in the block around it
    forced: bool                   # True: declared without the belief being confident (the budget ran out,
                                   # or a policy that relies on the belief had nothing more to do)
    reason: str                    # "confident", "budget" or "end" (the policy had nothing more to do)


@dataclass(frozen=True)
class StoppingRule:
    threshold: float = 0.95
    radius_cells: int = 1
    confirm_m: float | None = None
    clear_threshold: float | None = None  # probability of no (further) fire that ends the search; None: threshold

    def __post_init__(self):
        if not 0 < self.threshold <= 1:
            raise ValueError(f"threshold must be within (0, 1], got {self.threshold}")
        if self.radius_cells < 0:
            raise ValueError("radius_cells must be zero or positive")
        if self.confirm_m is not None and not self.confirm_m >= 0:
            raise ValueError("confirm_m must be zero or positive")
        if self.clear_threshold is not None and not 0 < self.clear_threshold <= 1:
            raise ValueError(f"clear_threshold must be within (0, 1], got {self.clear_threshold}")

    def candidate(self, belief: Belief):
        """The block to declare, if the belief is confident: the mass counted is the probability that
        the (further) fire is there, i.e. the block's share times the probability there is one."""
        if belief.n == 0:
            return None
        _, index = belief.most_likely()
        if belief.mass_around(index, self.radius_cells) * belief.p_fire < self.threshold:
            return None
        best, mass = belief.best_block(self.radius_cells)
        return belief.geometry.centre_of(best), best, mass * belief.p_fire

    def clear(self, belief: Belief) -> bool:
        """The belief is confident that there is no (further) fire."""
        limit = self.threshold if self.clear_threshold is None else self.clear_threshold
        return belief.n > 0 and 1.0 - belief.p_fire >= limit

    def confident(self, belief: Belief) -> Declaration | None:
        """The declaration if the block mass around the most likely cell reaches the threshold
        (and, with confirm_m, a reading has been taken within confirm_m of its centre)."""
        found = self.candidate(belief)
        if found is None:
            return None
        position, index, mass = found
        if self.confirm_m is not None and belief.closest_reading_m(index) > self.confirm_m:
            return None
        return Declaration(position, index, mass, False, "confident")

    def to_confirm(self, belief: Belief) -> tuple[float, float] | None:
        """The centre to fly over when the belief is confident but not yet confirmed, else None."""
        if self.confirm_m is None:
            return None
        found = self.candidate(belief)
        if found is None or belief.closest_reading_m(found[1]) <= self.confirm_m:
            return None
        return found[0]

    def force(self, belief: Belief, reason: str = "budget") -> Declaration:
        index, mass = belief.best_block(self.radius_cells)
        return Declaration(belief.geometry.centre_of(index), index, mass * belief.p_fire, True, reason)

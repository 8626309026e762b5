"""The team flight's feed of the team controller, sans-IO: every vehicle's positions and readings
in, a move for every vehicle out.

Each vehicle has its own Survey (survey.py): its positions, its readings paired with the position
at their own timestamps, averaged to the evaluated density, its track and its path. What a Survey
would hand its controller goes to the one TeamController instead, tagged with the vehicle and the
height at which it was read (the vehicles fly at separated heights, and the belief uses each
reading's own). Positions are in the area's frame (metres north and east of the first vehicle's
home), whatever frame each vehicle's own local position uses: the I/O side converts.

The controller is asked for the team's moves when it has something new to decide on: a new
observation from any vehicle, or a vehicle within arrival_m of its target.
"""
from __future__ import annotations

import math

from ..strategy import Geometry
from ..strategy.controller import Goto, SearchConfig
from ..strategy.stopping import Declaration
from ..strategy.team import TeamController
from .survey import ARRIVAL_M, Survey


class _Member:
    """What a vehicle's Survey sees as its controller: vehicle i's share of the team's."""

    def __init__(self, team: TeamController, i: int):
        self.team, self.i = team, i

    @property
    def declared(self):
        return self.team.declared

    def observe(self, n: float, e: float, z: float, height_m: float) -> None:
        self.team.observe(self.i, n, e, z, height_m)


class TeamSurvey:
    def __init__(self, geometry: Geometry, config: SearchConfig, k: int, arrival_m: float = ARRIVAL_M):
        self.geometry = geometry
        self.members = [Survey(geometry, config, arrival_m) for _ in range(k)]
        self.arrival_m = arrival_m
        self.team: TeamController | None = None
        self.out: dict[int, str] = {}  # vehicle -> why it left the search
        self._stepped_at = 0

    def start(self, team: TeamController) -> None:
        """Feed `team` from now on (readings before this moment are not used)."""
        self.team = team
        for i, member in enumerate(self.members):
            member.start(_Member(team, i))

    def add_position(self, i: int, t_ms: int, n: float, e: float, d: float) -> None:
        self.members[i].add_position(t_ms, n, e, d)

    def add_reading(self, i: int, t_ms: int, z: float) -> None:
        self.members[i].add_reading(t_ms, z)

    def heres(self) -> list[tuple[float, float]]:
        return [member.here() for member in self.members]

    @property
    def paths_m(self) -> list[float]:
        return [member.path_m for member in self.members]

    def next_moves(self) -> list[Goto | None] | Declaration | None:
        """The team's moves if the controller has something new to decide on, else None (fly on)."""
        team = self.team
        if team.declared is not None:
            return team.declared
        if team.observations == 0:
            return None  # the search starts with a reading
        heres = self.heres()
        arrived = [team.active[i] and team.targets[i] is not None and math.dist(heres[i], team.targets[i]) <= self.arrival_m
                   for i in range(team.k)]
        if team.observations == self._stepped_at and not any(arrived):
            return None
        self._stepped_at = team.observations
        return team.step(heres, self.paths_m, arrived)

    def drop(self, i: int, why: str) -> None:
        """Vehicle i is out: its readings stop counting and it gets no more targets."""
        self.out[i] = why
        self.team.drop(i)

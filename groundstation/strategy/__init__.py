"""The decision layer's strategy (docs/strategy.md): a belief over the grid of cells with the
ambient and the fire's strength integrated out exactly, an information-gain-per-distance planner,
baseline policies, the stopping rule, and the search controller that runs them (one loop for
the judged and the flown search).

Pure code: no I/O, no MAVLink, no wall clock, no knowledge of the true fire.
"""
from .belief import Belief, Geometry
from .planner import Planner, PlannerConfig
from .policies import POLICIES, Policy, make_policy
from .stopping import StoppingRule
from .controller import Goto, SearchConfig, SearchController

__all__ = ["Belief", "Geometry", "Planner", "PlannerConfig", "POLICIES", "Policy", "make_policy",
           "StoppingRule", "SearchConfig", "SearchController", "Goto"]

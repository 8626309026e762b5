"""The decision layer's strategy (docs/strategy.md): a belief over the grid of cells with the
ambient and the fire's strength integrated out exactly, an information-gain-per-distance planner,
baseline policies and the stopping rule.

Pure code: no I/O, no MAVLink, no wall clock, no knowledge of the true fire.
"""
from .belief import Belief, Geometry
from .planner import Planner, PlannerConfig
from .policies import POLICIES, Policy, make_policy
from .stopping import StoppingRule

__all__ = ["Belief", "Geometry", "Planner", "PlannerConfig", "POLICIES", "Policy", "make_policy",
           "StoppingRule"]

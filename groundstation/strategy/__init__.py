"""The decision layer's strategy (docs: STRATEGY.md): a belief over the grid of cells with the
ambient and the fire's strength integrated out exactly, an information-gain-per-distance planner,
baseline policies, the stopping rule, and a decision-level episode simulator to judge them.

Pure code: no I/O, no MAVLink, no wall clock (except timing decisions in episode.py).
"""
from .belief import Belief, Geometry
from .planner import Planner, PlannerConfig
from .policies import POLICIES, Policy, make_policy
from .stopping import StoppingRule
from .episode import EpisodeConfig, EpisodeResult, episode_world, run_episode

__all__ = ["Belief", "Geometry", "Planner", "PlannerConfig", "POLICIES", "Policy", "make_policy",
           "StoppingRule", "EpisodeConfig", "EpisodeResult", "episode_world", "run_episode"]

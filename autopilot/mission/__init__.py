"""Missions: stored lists of items (mission, fence, rally) and their persistence."""
from .store import MissionItem, MissionStore, MISSION, FENCE, RALLY

__all__ = ["MissionItem", "MissionStore", "MISSION", "FENCE", "RALLY"]

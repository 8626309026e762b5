"""Judging the strategy: `groundstation evaluate`, the decision-level episodes it runs (the true
sensor, no vehicle), and the same episodes flown end to end through a real autopilot."""

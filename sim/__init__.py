"""Perception layer and world: quadrotor physics, sensors, wind. No I/O, no MAVLink, no wall time."""

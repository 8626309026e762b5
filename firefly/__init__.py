"""Firefly: an ArduCopter-compatible SITL quadrotor with a fire-search companion.

Installed, everything lives under this one name, so that none of it can collide with a user's own
modules: `firefly.sim` (the world), `firefly.autopilot` (the vehicle a client flies, and the pytest
plugin under `firefly.autopilot.testing`) and `firefly.groundstation` (the decision layer). In a
checkout the three layers keep their top-level folders; the links beside this file name them.
"""

"""Fault injection: SIM_* parameters applied to the simulated world (world.py) and to the MAVLink link (link.py)."""

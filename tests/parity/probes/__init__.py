"""Probes by area. Each module has AREA and run(target) -> {probe name: Trace}."""
from . import commands

AREAS = {m.AREA: m for m in (commands,)}

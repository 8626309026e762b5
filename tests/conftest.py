"""Settings for the whole suite.

Hypothesis times each example against a 200 ms deadline by default; on a loaded CI machine that
turns a slow example into a failure that has nothing to do with the code. Nothing in this suite
is timed (figures are measured by `make bench`), so the deadline is off."""
from hypothesis import settings

settings.register_profile("firefly", deadline=None)
settings.load_profile("firefly")

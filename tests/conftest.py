"""Settings for the whole suite.

Hypothesis times each example against a 200 ms deadline by default; on a loaded CI machine that
turns a slow example into a failure that has nothing to do with the code. Nothing in this suite
is timed (figures are measured by `make bench`), so the deadline is off.

Every test fails if a vehicle it ran in this process had an internal error (a bug caught by the
vehicle's guards, autopilot/safety/internal_error.py), unless it is marked
`@pytest.mark.internal_errors` (a test of those guards themselves).

Ctrl-C is this suite's to handle: a shell without job control starts a backgrounded `make test`
with SIGINT ignored, every process it starts inherits that, and the tests that stop an autopilot
or a campaign with SIGINT would wait on a process that cannot hear it. Handled here, the
signal goes back to its default in every child."""
import signal

import pytest
from hypothesis import settings

from firefly.autopilot.safety.internal_error import InternalErrors

settings.register_profile("firefly", deadline=None)
settings.load_profile("firefly")
signal.signal(signal.SIGINT, signal.default_int_handler)


@pytest.fixture(autouse=True)
def no_internal_errors(request, monkeypatch):
    seen: list[str] = []
    record = InternalErrors.record

    def recording(self, exc, where, *args, **kw):
        new = record(self, exc, where, *args, **kw)
        seen.append(self.last)
        return new

    monkeypatch.setattr(InternalErrors, "record", recording)
    yield seen
    if seen and request.node.get_closest_marker("internal_errors") is None:
        pytest.fail(f"{len(seen)} internal errors in the vehicle, first: {seen[0]}", pytrace=False)

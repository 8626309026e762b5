"""`groundstation campaign`: many seeded episodes over a sweep of conditions, decision-level and
flown, on a local process pool or on Ray, with results that survive a crash and resume."""

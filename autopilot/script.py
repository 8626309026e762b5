"""Scripted commands in sim time, from a scenario's [script] table: a client-free flight that runs
identically at any speedup (used for determinism checks and for headless benchmarks).

    [script]
    steps = [[0.5, "mode", 4], [0.5, "arm"], [1.0, "takeoff", 10], [12.0, "goto", 30, 0, 10],
             [25.0, "mode", 6]]

Each step is [time_s, verb, args...]; verbs: mode N, arm, disarm, takeoff ALT, goto N E ALT
(local metres, altitude above home), speed M_S.
"""
from __future__ import annotations

import math

VERBS = {"mode": 1, "arm": 0, "disarm": 0, "takeoff": 1, "goto": 3, "speed": 1}


class ScriptError(ValueError):
    pass


def parse_steps(steps, where: str) -> list[tuple]:
    if not isinstance(steps, list):
        raise ScriptError(f"{where}: [script].steps must be a list of [time, verb, args...]")
    parsed = []
    for k, step in enumerate(steps):
        at = f"{where}: [script].steps[{k}]"
        if not isinstance(step, list) or len(step) < 2:
            raise ScriptError(f"{at}: expected [time, verb, args...]")
        t, verb, *args = step
        if isinstance(t, bool) or not isinstance(t, (int, float)) or not math.isfinite(t) or t < 0:
            raise ScriptError(f"{at}: time must be a non-negative number")
        if verb not in VERBS:
            raise ScriptError(f"{at}: unknown verb {verb!r} (known: {', '.join(VERBS)})")
        if len(args) != VERBS[verb] or not all(isinstance(a, (int, float)) and not isinstance(a, bool)
                                               and math.isfinite(a) for a in args):
            raise ScriptError(f"{at}: {verb} takes {VERBS[verb]} number(s)")
        parsed.append((float(t), verb, tuple(float(a) for a in args)))
    return sorted(parsed, key=lambda s: s[0])


class Script:
    def __init__(self, steps: list[tuple]):
        self.steps = list(steps)
        self.next = 0
        self.results: list[tuple] = []

    def run_due(self, vehicle) -> None:
        while self.next < len(self.steps) and self.steps[self.next][0] <= vehicle.time_s + 1e-9:
            t, verb, args = self.steps[self.next]
            self.results.append((t, verb, int(self._do(vehicle, verb, args))))
            self.next += 1

    @staticmethod
    def _do(v, verb: str, args: tuple):
        if verb == "mode":
            return v.set_mode(int(args[0]))
        if verb == "arm":
            return v.arm()
        if verb == "disarm":
            return v.disarm("script")
        if verb == "takeoff":
            return v.takeoff(args[0])
        if verb == "goto":
            home = v.home_ned or (0.0, 0.0, 0.0)
            return v.guided_goto(args[0], args[1], home[2] - args[2])
        return v.set_speed(args[0])

"""Scripted commands in sim time, from a scenario's [script] table: a client-free flight that runs
identically at any speedup (used for determinism checks and for headless benchmarks).

    [script]
    steps = [[0.5, "mode", 4], [0.5, "arm"], [1.0, "takeoff", 10], [12.0, "goto", 30, 0, 10],
             [25.0, "mode", 6]]

Each step is [time_s, verb, args...]; verbs: mode N, arm, disarm, takeoff ALT, goto N E ALT
(local metres from the vehicle's own start, as LOCAL_POSITION_NED; altitude above home),
speed M_S, param NAME VALUE (any parameter, e.g. a fault: [20.0, "param", "SIM_GPS_DISABLE", 1]).
"""
from __future__ import annotations

import math

from ..params import ParamError, checked_value
from ..results import Result

VERBS = {"mode": 1, "arm": 0, "disarm": 0, "takeoff": 1, "goto": 3, "speed": 1, "param": 2}


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
        if verb == "param":
            parsed.append((float(t), verb, _param_args(args, at)))
            continue
        if len(args) != VERBS[verb] or not all(_is_number(a) for a in args):
            raise ScriptError(f"{at}: {verb} takes {VERBS[verb]} number(s)")
        parsed.append((float(t), verb, tuple(float(a) for a in args)))
    return sorted(parsed, key=lambda s: s[0])


def _is_number(a) -> bool:
    return isinstance(a, (int, float)) and not isinstance(a, bool) and math.isfinite(a)


def _param_args(args: list, at: str) -> tuple:
    """(NAME, value) for a param step, checked against the parameter table now, not mid-flight."""
    if len(args) != 2 or not isinstance(args[0], str) or not _is_number(args[1]):
        raise ScriptError(f"{at}: param takes a parameter name and a number")
    try:
        return args[0], checked_value(args[0], args[1])
    except ParamError as exc:
        raise ScriptError(f"{at}: {exc}") from None


class Script:
    def __init__(self, steps: list[tuple]):
        self.steps = list(steps)
        self.next = 0
        self.results: list[tuple] = []

    def run_due(self, vehicle) -> None:
        while self.next < len(self.steps) and self.steps[self.next][0] <= vehicle.time_s + 1e-9:
            t, verb, args = self.steps[self.next]
            self.next += 1  # first: a step that raises is run once, not at every tick after
            self.results.append((t, verb, int(self._do(vehicle, verb, args))))

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
        if verb == "goto":  # local metres from the vehicle's own EKF origin, as on the wire
            home = v.home_ned or (0.0, 0.0, 0.0)
            return v.guided_goto(*v.sim_ne(args[0], args[1]), home[2] - args[2])
        if verb == "param":
            try:
                v.params.set(*args)
            except ValueError:  # ParamError: refused, as a PARAM_SET would be
                return Result.FAILED
            return Result.ACCEPTED
        return v.set_speed(args[0])

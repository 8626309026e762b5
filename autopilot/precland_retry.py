"""What a landing does when its target is not in sight, as ArduCopter's AC_PrecLand_StateMachine
decides it (measured on ArduCopter SITL, parity area precland: lost_strict_*).

The target's state (`TargetState`, kept by precland.py each update): found; recently lost (it was
found, or recently lost, on the update before); never seen (otherwise: so a target lost while the
sensor was out of its range counts as never seen once back in it); out of range, whatever it was,
while the rangefinder reads outside PLND_ALT_MIN..PLND_ALT_MAX (both 0: always in range).

Found or out of range, the landing descends and the machine starts afresh. Never seen: the
failsafe. Recently lost, with PLND_STRICT 0 it descends where it is; with 1 or 2 it descends on
until PLND_TIMEOUT has passed since the target was last acquired, then retries ("PrecLand:
Retrying"): it flies to where it last measured the target from (PLND_RET_BEHAVE 0; 1: over the
target as last estimated, at that height), 1.5 m higher, until within 0.75 m of that point, then
down to the height of the last reading ("PrecLand: Retry Completed"), then the failsafe. Each
retry counts against PLND_RET_MAX for as long as the mode lasts (a target found again starts the
machine afresh, not the count); past it, or with PLND_RET_MAX 0, the failsafe instead.

The failsafe ("PrecLand: Failsafe Measures", once until the machine starts afresh): PLND_STRICT 2
holds for good, 1 holds 7 s and then descends where it is, 0 descends at once.
"""
from __future__ import annotations

import enum
import math

from .results import Severity

RETRY_CLIMB_M = 1.5  # RETRY_OFFSET_ALT_M
RETRY_REACHED_M = 0.75  # MAX_POS_ERROR_M
FAILSAFE_HOLD_S = 7.0  # FAILSAFE_INIT_TIMEOUT_MS


class TargetState(enum.Enum):
    FOUND = enum.auto()
    RECENTLY_LOST = enum.auto()
    NEVER_SEEN = enum.auto()
    OUT_OF_RANGE = enum.auto()


class Action(enum.Enum):
    DESCEND = enum.auto()  # the landing's own descent (onto the target when it is acquired)
    RETRY = enum.auto()  # fly to the retry point
    HOLD = enum.auto()  # the failsafe's hold: no descent


NOT_STRICT, NORMAL, VERY_STRICT = 0, 1, 2  # PLND_STRICT


class _Lost(enum.Enum):
    FIRST = enum.auto()  # the strictness not yet looked at
    DESCENDING = enum.auto()  # on down until PLND_TIMEOUT, then a retry
    RETRYING = enum.auto()
    VERTICAL = enum.auto()  # PLND_STRICT 0: down where it is


class _Retry(enum.Enum):
    START = enum.auto()
    GOING = enum.auto()  # to the point above where the target was last measured
    RETURNING = enum.auto()  # down to the height of that measurement
    DONE = enum.auto()


class RetryMachine:
    def __init__(self) -> None:
        self.retries = 0
        self.restart()

    def begin(self) -> None:
        """A landing mode entered: its retries are counted from none."""
        self.retries = 0
        self.restart()

    def restart(self) -> None:
        """The target back in sight (or out of the sensor's range): a later loss starts over."""
        self._lost = _Lost.FIRST
        self._retry = _Retry.START
        self._failsafe_since_s: float | None = None

    def update(self, state: TargetState, now_s: float, notify, params, last_valid_s: float,
               retry_from_ned: tuple[float, float, float], position_ned: tuple[float, float, float]
               ) -> tuple[Action, tuple[float, float, float] | None]:
        """(what the landing does, the point to fly to when retrying). `retry_from_ned` is the
        point chosen by PLND_RET_BEHAVE at the last reading's height; `last_valid_s` when the
        target was last acquired."""
        if state in (TargetState.FOUND, TargetState.OUT_OF_RANGE):
            self.restart()
            return Action.DESCEND, None
        if state == TargetState.NEVER_SEEN:
            return self._failsafe(now_s, notify, params), None
        strict = int(params["PLND_STRICT"])
        if self._lost == _Lost.FIRST:
            self._lost = _Lost.VERTICAL if strict == NOT_STRICT else _Lost.DESCENDING
            return Action.DESCEND, None
        if self._lost == _Lost.DESCENDING:
            if now_s - last_valid_s >= params["PLND_TIMEOUT"]:
                self._lost, self._retry = _Lost.RETRYING, _Retry.START
            return Action.DESCEND, None
        if self._lost == _Lost.VERTICAL:
            return Action.DESCEND, None
        return self._retrying(now_s, notify, params, retry_from_ned, position_ned)

    def _retrying(self, now_s, notify, params, retry_from_ned, position_ned):
        most = int(params["PLND_RET_MAX"])
        if most == 0 or self.retries > most:
            return self._failsafe(now_s, notify, params), None
        n, e, d = retry_from_ned
        above = (n, e, d - RETRY_CLIMB_M)
        if self._retry == _Retry.START:
            self.retries += 1
            self._retry = _Retry.GOING
            if self.retries <= most:
                notify("PrecLand: Retrying", Severity.INFO)
            return Action.RETRY, above
        if self._retry == _Retry.GOING:
            if math.dist(above, position_ned) < RETRY_REACHED_M:
                self._retry = _Retry.RETURNING
            return Action.RETRY, above
        if self._retry == _Retry.RETURNING:
            back = (position_ned[0], position_ned[1], d)  # straight down from wherever it is
            if abs(position_ned[2] - d) < RETRY_REACHED_M:
                self._retry = _Retry.DONE
                notify("PrecLand: Retry Completed", Severity.INFO)
            return Action.RETRY, back
        return self._failsafe(now_s, notify, params), None

    def _failsafe(self, now_s: float, notify, params) -> Action:
        if self._failsafe_since_s is None:
            self._failsafe_since_s = now_s
            notify("PrecLand: Failsafe Measures", Severity.INFO)
        strict = int(params["PLND_STRICT"])
        if strict == VERY_STRICT or (strict == NORMAL and now_s - self._failsafe_since_s < FAILSAFE_HOLD_S):
            return Action.HOLD
        return Action.DESCEND

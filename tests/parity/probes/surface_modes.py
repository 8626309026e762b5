"""Every ArduCopter mode number × the states a ground station asks for it in: disarmed on the
ground (from STABILIZE), armed on the ground (from GUIDED), and hovering in GUIDED at 10 m; in
flight, what the vehicle then does in it for 5 s of vehicle time with no pilot input.

The mode list is ArduCopter's own (surface/arducopter.json "modes", less scope.toml's [[out]]),
so every in-scope mode number is covered by construction; the probe name is the mode's name.

Facts per state ("<state>.<fact>"), read at vehicle times counted from the ACK:
* every state: the DO_SET_MODE ACK (`result`), the mode in the first HEARTBEAT after it
  (`mode_after`), what the vehicle said within SAID_WITHIN_S (`said`);
* armed_ground: still armed ARMED_AFTER_S later, off the ground then (a mode that lifts off), and
  whether it can be disarmed and armed again at once (`rearm_result`);
* flying, for a mode it accepted, after HOLD_S with no RC override (ArduCopter SITL's RC then
  stays at its defaults: sticks centred, throttle at 1000 us, the bottom of the stick): the height
  change, horizontal distance and heading change, whether it rolled past 90 degrees, armed or not,
  the mode, what it said during the hold. FLIP and AUTOTUNE, which ArduCopter enters in flight only
  from a pilot's mode, are also tried from ALT_HOLD (`flying_from_alt_hold`).
Numbers carry tolerances wide enough to ask "does the mode do the same kind of thing".
"""
from __future__ import annotations

import json
import math
import re
import tomllib
from pathlib import Path

from ..client import Client, ProbeTimeout, mav
from ..facts import Tol, Trace
from .states import ALT_HOLD, GUIDED, HOVER_ALT_M, STABILIZE, on_ground_disarmed
from .texts import said as said_all

# Said by ArduCopter's EKF when a hard landing makes it switch cores: timing, not the mode's reply.
EKF_CORE_SWITCH = re.compile(r"^EKF primary changed")


def said(texts: list[str]) -> list[str]:
    return [t for t in said_all(texts) if not EKF_CORE_SWITCH.search(t)]


AREA = "surface_modes"
KIND = "modes"
SURFACE_DIR = Path(__file__).resolve().parent.parent / "surface"

SAID_WITHIN_S = 0.5   # the replies to a mode change, not what follows it (LAND on the ground disarms ~1 s later)
DEFAULT_DISARM_DELAY_S = 10.0  # DISARM_DELAY's default on both vehicles
LEFT_GROUND_M = 0.5  # above home ARMED_AFTER_S after the change: the mode lifted off (SMART_RTL: 0.9-1.6 m)
ARMED_AFTER_S = 3.0   # armed on the ground: still armed this long after the mode change? (LAND disarms in ~1 s)
HOLD_S = 5.0          # vehicle seconds in the new mode before the flight facts are read
HOME_LAT, HOME_LON = -35.363261, 149.165230  # targets.HOME: both vehicles take off there
EARTH_M_PER_DEG = 111_195.0
# SET_POSITION_TARGET_GLOBAL_INT mask: position only (velocity, acceleration, yaw, yaw rate ignored)
POSITION_ONLY = 0x38 | 0x1C0 | 0x400 | 0x800
# Modes ArduCopter enters in flight only from a pilot's mode (FLIP: ACRO, STABILIZE, ALT_HOLD;
# AUTOTUNE: its allows_autotune() modes), never from GUIDED: also tried from ALT_HOLD at 10 m.
FROM_PILOT_MODE = ("FLIP", "AUTOTUNE")
BACK_WITHIN_M = 1.5   # near enough the hover point to start the next mode from it
REBOOTS = 2           # fresh vehicles a run may take to get back to a hover (after a crash)

ALT_TOL = Tol(abs=2.0, why="height after 5 s in a mode: climb and sink rates, the landing moment and "
                           "the ground contact differ by a metre or two between autopilots and runs")
MOVED_TOL = Tol(abs=3.0, rel=0.25, why="how far a mode carries the vehicle in 5 s: a hold drifts under a "
                                       "metre, a circle or a return moves it metres, speeds and "
                                       "accelerations differ")
HEADING_TOL = Tol(abs=20.0, rel=0.25, why="heading change in 5 s: a hold keeps it within degrees, a circle "
                                          "turns it by its rate; the rate's ramp differs")


def surface_modes() -> list[tuple[str, int]]:
    """(name, number) of every in-scope mode in ArduCopter's surface list, by number."""
    doc = json.loads((SURFACE_DIR / "arducopter.json").read_text())
    scope = tomllib.loads((SURFACE_DIR / "scope.toml").read_text())
    out = {name for block in scope.get("out", []) if block.get("kind") == KIND for name in block["names"]}
    return sorted(((m["name"], int(m["number"])) for m in doc[KIND] if m["name"] not in out),
                  key=lambda m: m[1])


class Vehicle:
    """The target's present vehicle; booted again when one can no longer be brought back to a hover."""

    def __init__(self, target, names: dict[int, str]):
        self.target, self.names = target, names
        self.c: Client = target.boot()
        self.reboots = 0
        self.params: dict[str, float] = {}  # set again on a fresh vehicle

    def name(self, number) -> str:
        return self.names.get(number, str(number))

    def reboot(self) -> Client:
        self.reboots += 1
        self.c = self.target.boot()
        self.set_params(**self.params)
        return self.c

    def set_params(self, **values: float) -> None:
        self.params.update(values)
        for name, value in values.items():
            if not self.c.set_param(name, value):
                raise ProbeTimeout(f"{name} not set to {value}")

    # ----- states --------------------------------------------------------------------------------
    def disarmed_in(self, mode: int) -> None:
        c = self.c
        on_ground_disarmed(c)
        answers = []
        while c.mode != mode:  # setting up, not a fact: an exchange lost on a loaded machine is tried again
            if len(answers) == 3:
                raise ProbeTimeout(f"mode {self.name(mode)} not entered: DO_SET_MODE answered {answers}, "
                                   f"the vehicle in {self.name(c.mode)}, said {c.texts[-3:]}")
            answers.append(c.set_mode(mode))
            c.try_wait(lambda: c.mode == mode, 3)

    def armed_on_ground(self, mode: int = GUIDED) -> None:
        """Armed on the ground in `mode`; arming is retried for a while (a vehicle that just landed
        hard may need a moment before its checks pass)."""
        c = self.c
        if c.armed and c.mode == mode and c.rel_alt_m() < 0.5:
            return
        self.disarmed_in(mode)
        start = c.now_ms
        while c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1) != mav.MAV_RESULT_ACCEPTED:
            if c.now_ms - start > 20_000:
                raise ProbeTimeout(f"not armable within 20 s of vehicle time: {c.texts_since(start)[-3:]}")
            c.idle(1.0)
        c.wait(lambda: c.armed, 5, what="armed")

    def hovering(self) -> None:
        """Hovering in GUIDED HOVER_ALT_M above home: flown back there when still in the air,
        landed and taken off again otherwise, a fresh vehicle when neither works."""
        for attempt in range(REBOOTS + 1):
            try:
                if self._back_to_hover() or self._take_off():
                    return
            except ProbeTimeout:
                pass
            if attempt < REBOOTS:
                self.reboot()
        raise ProbeTimeout("could not bring the vehicle back to a hover")

    def _back_to_hover(self) -> bool:
        c = self.c
        if not (c.armed and c.rel_alt_m() > 2.0):
            return False
        if c.mode != GUIDED:
            c.set_mode(GUIDED)
            if not c.try_wait(lambda: c.mode == GUIDED, 3):
                return False
        c.conn.mav.set_position_target_global_int_send(
            0, 1, 1, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, POSITION_ONLY,
            round(HOME_LAT * 1e7), round(HOME_LON * 1e7), HOVER_ALT_M, 0, 0, 0, 0, 0, 0, 0, 0)
        if not c.try_wait(lambda: distance_from_home_m(c) < BACK_WITHIN_M
                          and abs(c.rel_alt_m() - HOVER_ALT_M) < 1.0, 40):
            return False
        c.idle(1.0)
        return True

    def _take_off(self) -> bool:
        c = self.c
        self.armed_on_ground(GUIDED)
        if c.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, HOVER_ALT_M) != mav.MAV_RESULT_ACCEPTED:
            return False
        c.wait(lambda: c.rel_alt_m() > HOVER_ALT_M - 0.5, 60, what="takeoff altitude")
        c.idle(1.0)
        return True


def distance_from_home_m(c: Client) -> float:
    pos = c.last.get("GLOBAL_POSITION_INT")
    return horizontal_m((HOME_LAT * 1e7, HOME_LON * 1e7), (pos.lat, pos.lon)) if pos else math.inf


def horizontal_m(a: tuple[float, float], b: tuple[float, float]) -> float:
    """Metres between two (lat, lon) in 1e-7 degrees: flat earth, plenty for tens of metres."""
    north = (b[0] - a[0]) * 1e-7 * EARTH_M_PER_DEG
    east = (b[1] - a[1]) * 1e-7 * EARTH_M_PER_DEG * math.cos(math.radians(a[0] * 1e-7))
    return math.hypot(north, east)


class Timeline:
    """What the vehicle sent while a mode change is tried, each message stamped with the vehicle
    time it came at. Facts are read off it at vehicle times counted from the ACK, not from when
    the client got round to looking: a client that falls behind a vehicle run at 20x on a busy
    machine reads a batch of seconds at once, and must still see the state at the moment asked."""
    KINDS = ("HEARTBEAT", "GLOBAL_POSITION_INT", "ATTITUDE", "STATUSTEXT", "COMMAND_ACK")

    def __init__(self, c: Client):
        self.c = c
        self.sent_ms = c.now_ms
        self.at_send = {kind: c.last.get(kind) for kind in self.KINDS}
        self.log: list[tuple[int, object]] = []

    def __call__(self, msg) -> None:
        if msg.get_type() in self.KINDS:
            self.log.append((self.c.now_ms, msg))

    def ack_ms(self, command: int) -> int:
        """When the vehicle answered the command (when it was sent, if it did not)."""
        return next((t for t, m in self.log if m.get_type() == "COMMAND_ACK" and m.command == command),
                    self.sent_ms)

    def first(self, kind: str, from_ms: float):
        return next((m for t, m in self.log if m.get_type() == kind and t >= from_ms), None)

    def last(self, kind: str, until_ms: float):
        found = self.at_send[kind]
        for t, m in self.log:
            if t > until_ms:
                break
            if m.get_type() == kind:
                found = m
        return found

    def between(self, kind: str, from_ms: float, to_ms: float) -> list:
        return [m for t, m in self.log if m.get_type() == kind and from_ms <= t <= to_ms]

    def texts(self, from_ms: float, to_ms: float) -> list[str]:
        return said([m.text for m in self.between("STATUSTEXT", from_ms, to_ms)])

    def until(self, at_ms: float) -> None:
        self.c.wait(lambda: self.c.now_ms >= at_ms, (at_ms - self.c.now_ms) / 1000.0 + 5, what="vehicle time")

    def heartbeat_after_ack(self, command: int):
        """The first HEARTBEAT received after the command's ACK, waited for: a beat sent in the same
        vehicle millisecond but before the ACK still says the mode before the command."""
        def found():
            at = next((i for i, (_, m) in enumerate(self.log)
                       if m.get_type() == "COMMAND_ACK" and m.command == command), None)
            if at is None:
                return self.first("HEARTBEAT", self.sent_ms)
            return next((m for _, m in self.log[at + 1:] if m.get_type() == "HEARTBEAT"), None)
        self.c.wait(lambda: found() is not None, 5, what="a HEARTBEAT after the answer")
        return found()

    def heartbeat_after(self, at_ms: float):
        """The first HEARTBEAT sent from `at_ms` on, waited for."""
        self.c.wait(lambda: self.first("HEARTBEAT", at_ms) is not None and self.c.now_ms >= at_ms,
                    (at_ms - self.c.now_ms) / 1000.0 + 5, what="a HEARTBEAT after the moment")
        return self.first("HEARTBEAT", at_ms)


def is_armed(heartbeat) -> bool:
    return bool(heartbeat.base_mode & mav.MAV_MODE_FLAG_SAFETY_ARMED)


def try_mode(v: Vehicle, trace: Trace, state: str, number: int, then_s: float = 0.0,
             only_if_accepted: bool = False) -> tuple:
    """DO_SET_MODE; records result, mode_after and said. Keeps the timeline going until
    `then_s` after the ACK (if the mode was accepted, with only_if_accepted); returns (result,
    timeline, the ACK's vehicle time)."""
    c = v.c
    timeline = Timeline(c)
    with c.listening(timeline):
        result = c.set_mode(number)
        acked = timeline.ack_ms(mav.MAV_CMD_DO_SET_MODE)
        # The first HEARTBEAT after the answer: a mode that hands back by itself (FLIP, ~1.4 s)
        # is still seen, whatever the 1 Hz beat's phase.
        beat = timeline.heartbeat_after_ack(mav.MAV_CMD_DO_SET_MODE)
        timeline.until(acked + SAID_WITHIN_S * 1000)  # every reply in the window has come
        if then_s and (result == mav.MAV_RESULT_ACCEPTED or not only_if_accepted):
            timeline.heartbeat_after(acked + then_s * 1000)
    trace.fact(f"{state}.result", result)
    trace.fact(f"{state}.mode_after", v.name(beat.custom_mode))
    trace.fact(f"{state}.said", timeline.texts(timeline.sent_ms, acked + SAID_WITHIN_S * 1000))
    return result, timeline, acked


def fly_in(v: Vehicle, trace: Trace, number: int, state: str = "flying") -> None:
    """From a hover, enter the mode; when accepted, what the vehicle did in it within HOLD_S."""
    result, timeline, acked = try_mode(v, trace, state, number, then_s=HOLD_S, only_if_accepted=True)
    if result != mav.MAV_RESULT_ACCEPTED:
        return
    end = acked + HOLD_S * 1000
    pos0, att0 = timeline.last("GLOBAL_POSITION_INT", acked), timeline.last("ATTITUDE", acked)
    pos, att = timeline.last("GLOBAL_POSITION_INT", end), timeline.last("ATTITUDE", end)
    beat = timeline.first("HEARTBEAT", end)
    rolls = [abs(math.degrees(m.roll)) for m in timeline.between("ATTITUDE", acked, end)]
    turned = math.degrees(att.yaw - att0.yaw)
    trace.fact(f"{state}.alt_change_m", (pos.relative_alt - pos0.relative_alt) / 1000.0, ALT_TOL)
    trace.fact(f"{state}.moved_m", horizontal_m((pos0.lat, pos0.lon), (pos.lat, pos.lon)), MOVED_TOL)
    trace.fact(f"{state}.heading_change_deg", abs((turned + 180.0) % 360.0 - 180.0), HEADING_TOL)
    trace.fact(f"{state}.rolled_past_90", max(rolls, default=0.0) > 90.0)  # a flip, or a crash
    trace.fact(f"{state}.armed_after_hold", is_armed(beat))
    trace.fact(f"{state}.mode_after_hold", v.name(beat.custom_mode))
    trace.fact(f"{state}.said_in_hold", timeline.texts(acked + SAID_WITHIN_S * 1000 + 1, end))


def on_ground_in(v: Vehicle, trace: Trace, number: int) -> None:
    """Armed on the ground in GUIDED, enter the mode: still armed ARMED_AFTER_S later, and how high?"""
    result, timeline, acked = try_mode(v, trace, "armed_ground", number, then_s=ARMED_AFTER_S)
    at = acked + ARMED_AFTER_S * 1000
    trace.fact("armed_ground.armed_after_3s", is_armed(timeline.first("HEARTBEAT", at)))
    pos = timeline.last("GLOBAL_POSITION_INT", at)
    trace.fact("armed_ground.left_ground", pos.relative_alt / 1000.0 > LEFT_GROUND_M)


def rearm(v: Vehicle, trace: Trace) -> None:
    """Disarmed in GUIDED after the mode, can it be armed again at once? (ArduCopter's land
    detector can latch an internal error in a mode that spins the motors up on the ground, and
    then refuses every arm until rebooted.) A vehicle that cannot is booted again."""
    c = v.c
    v.disarmed_in(GUIDED)
    result = c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    trace.fact("armed_ground.rearm_result", result)
    if result != mav.MAV_RESULT_ACCEPTED or not c.try_wait(lambda: c.armed, 5):
        v.reboot()


def run(target) -> dict[str, Trace]:
    modes = surface_modes()
    names = {number: name for name, number in modes}
    traces = {name: Trace() for name, _ in modes}
    v = Vehicle(target, names)
    try:
        for name, number in modes:
            v.disarmed_in(STABILIZE)
            try_mode(v, traces[name], "disarmed", number)
        # Auto-disarm counts from arming: on a busy machine a client behind Firefly at 20x can
        # lose seconds before the mode change, so it is off while armed on the ground (on both
        # vehicles); a mode's own disarm (LAND's) does not depend on it.
        v.set_params(DISARM_DELAY=0)
        for name, number in modes:
            v.armed_on_ground(GUIDED)
            on_ground_in(v, traces[name], number)
            rearm(v, traces[name])
        v.set_params(DISARM_DELAY=DEFAULT_DISARM_DELAY_S)
        for name, number in modes:
            v.hovering()
            fly_in(v, traces[name], number)
        for name, number in modes:
            if name in FROM_PILOT_MODE:
                v.hovering()
                v.c.set_mode(ALT_HOLD)
                v.c.wait(lambda: v.c.mode == ALT_HOLD, 3, what="ALT_HOLD")
                fly_in(v, traces[name], number, "flying_from_alt_hold")
    finally:
        target.close()
    return traces

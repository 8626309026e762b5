"""The state-space walk: the sans-IO vehicle and its MAVLink session driven through every state a
user can put them in, with hostile messages sent in each, and the invariants checked after every
message and every 10 ms tick.

`Walk` is one vehicle (realistic start-up or instant) with its `Session` and a `Link` that packs
what the vehicle sends, as the I/O edge would. Everything reaches it as MAVLink from a ground
station (system 255, component 190): `send(message)` packs the message, decodes it as the link
would and hands it to `session.receive`; `advance_to(t)` runs the vehicle in 10 ms ticks, polling
the session at each as the runner does, while the ground station's HEARTBEAT goes out every second
(unless `gcs=False`: the link to the ground station is lost).

ACTIONS are the steps of a walk, each a function of (walk, random.Random): drive towards a state
(take off, change mode, upload a mission, trip a failsafe, lose the GPS, open an FTP session, start
a transfer and leave it half done, let time pass) or send hostile messages (hostile.py). The
property test (tests/unit/test_state_space.py) runs them as hypothesis rules, the long run
(state_walk.py) as a seeded random walk.

Invariants (a `WalkFailure` names the state, the message, what broke, a traceback and the steps
that led there; `shrink` and `render` turn those into the shortest Python found that fails the same
way):
- nothing raises out of session.receive, session.poll or vehicle.run_until;
- no handler error (session.counters["handler_errors"]) and no internal error
  (vehicle.internal_errors.count, where the vehicle has one);
- every COMMAND_LONG / COMMAND_INT addressed to the vehicle (target_system 0 or ours) gets exactly
  one COMMAND_ACK for its command id (SET_MODE none, as ArduCopter 4.7); a message for another system
  gets no answer and changes nothing;
- a refused command (ACK not ACCEPTED) changes neither the mode, nor arming, nor home;
- the vehicle arms only on an accepted ARM;
- the vehicle stays valid (checks.vehicle_problems: finite, above ground, parameters in range),
  after every message and every 0.5 s of sim time;
- every message the session returns packs, through the link, into a frame a ground station decodes
  (the long run decodes one telemetry frame in 16 again; every answer to a message, always);
- HEARTBEAT keeps its rate while time advances: no gap over 1.5 s of sim time (or 1.5 intervals,
  when a ground station asked for another with SET_MESSAGE_INTERVAL), and it tells the mode and
  arming as they are.

Every state the walk passes through is labelled (`label()`: start-up stage, mode, flight phase,
failsafes, transfers in progress) and counted, by label and by facet, for the coverage report.
"""
from __future__ import annotations

import math
import re
import time
import traceback
from collections import Counter
from dataclasses import dataclass, field

from firefly.autopilot.mavlink.dialect import mavlink as mav
from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.mavlink.link import Link
from firefly.autopilot.mavlink.session import Session
from firefly.autopilot.mission.commands import NAMES as MISSION_COMMAND_NAMES
from firefly.autopilot.modes import MODE_BY_NUMBER, ModeNumber
from firefly.autopilot.params import ParamStore
from firefly.autopilot.startup import StartupTimeline
from firefly.autopilot.vehicle import Vehicle, VehicleConfig

from . import hostile
from .checks import vehicle_problems
from .hostile import SYSTEM_ID, ftp_payload, near, param_f

GCS = (255, 190)
TICK_S = 0.01  # the runner's tick: the session is polled this often
HEARTBEAT_GAP_S = 1.5
GCS_HEARTBEAT_S = 1.0
LABEL_EVERY_TICKS = 10  # states are labelled and counted this often while time passes (0.1 s)
VALID_EVERY_TICKS = 50  # and checked valid this often (0.5 s; at the end of every advance and message too)
ARM, FORCE_ARM, FORCE_DISARM = mav.MAV_CMD_COMPONENT_ARM_DISARM, 2989.0, 21196.0
ACCEPTED = mav.MAV_RESULT_ACCEPTED
MODE_NAMES = {n: cls.name for n, cls in MODE_BY_NUMBER.items()}
PHASES = {"ON_GROUND": "armed_ground", "TAKEOFF": "takeoff", "IN_AIR": "flying", "LANDING": "landing"}
KIND_NAMES = {0: "mission", 1: "fence", 2: "rally"}
# "camera": an instant start with a servo camera (SERVO9_FUNCTION 10 at power-on makes CAM1_TYPE 1),
# so that the camera's commands and mission items act rather than answer that there is none, with
# its zoom, focus and ISO outputs (SERVO10-12_FUNCTION 180, 92, 90);
# "payload": an instant start with every payload that is off by default fitted, so that its
# commands act: the winch (WINCH_TYPE 1 on output 10), the optical flow sensor (FLOW_TYPE 10, SITL's
# camera on: FLOWHOLD can be entered) and the thermal camera as component 100, driven by CAM1_TYPE 6
STARTS = ("realistic", "instant", "camera", "payload")
CAMERA_PARAMS = {"SERVO9_FUNCTION": 10, "SERVO10_FUNCTION": 180, "SERVO11_FUNCTION": 92, "SERVO12_FUNCTION": 90}
PAYLOAD_PARAMS = {"WINCH_TYPE": 1, "SERVO10_FUNCTION": 88, "FLOW_TYPE": 10, "SIM_FLOW_ENABLE": 1, "CAM1_TYPE": 6}


# ----- failures ---------------------------------------------------------------------------------------
@dataclass
class Failure:
    kind: str  # exception, handler_error, internal_error, ack, other_system, refused_changed, unasked_arm,
    #            invalid_state, pack, heartbeat
    where: str  # session.receive, session.poll, vehicle.run_until
    state: str  # the state's label when it happened
    message: str  # the message (or tick) that broke it
    detail: str  # what broke; a traceback where there is one
    step: int
    trace: list = field(repr=False, default_factory=list)

    def exception(self) -> str:
        """The exception's type, from the traceback's last line (or the error's words)."""
        lines = [line for line in self.detail.strip().splitlines() if line.strip()]
        m = re.match(r"([A-Za-z_][\w.]*)(?::|$)", lines[-1]) if lines else None
        if m and not lines[-1].startswith(" "):
            return m.group(1)
        found = re.findall(r"\b([A-Za-z_][\w.]*(?:Error|Exception|error|Requirement))\b", self.detail)
        return found[-1] if found else "?"

    def origin(self) -> str:
        """Where in the vehicle's code it raised: the innermost autopilot/ or sim/ frame."""
        frames = re.findall(r'File "[^"]*?/((?:autopilot|sim)/[^"]+)", line \d+, in (\w+)', self.detail)
        if frames:
            return f"{frames[-1][0]}:{frames[-1][1]}"
        place = re.findall(r"\((\w+\.py):\d+\)", self.detail)
        return place[-1] if place else "?"

    def signature(self) -> str:
        """What makes two failures the same bug: the kind, where, and the exception and the
        function of the vehicle's code it came from (or what broke, for a broken invariant)."""
        if self.kind in ("exception", "handler_error", "internal_error"):
            return f"{self.kind} in {self.where}: {self.exception()} at {self.origin()}"
        if self.kind in ("pack", "invalid_state"):
            return f"{self.kind}: {re.sub(r'[-0-9.e+]+', 'N', self.detail.splitlines()[0].split(':', 1)[0])}"
        head = self.message.split("(", 1)[0]
        if head in ("COMMAND_LONG", "COMMAND_INT"):
            command = re.search(r"command=(\d+)", self.message)
            head += f" {command.group(1) if command else '?'}"
        return f"{self.kind}: {head}"

    def describe(self, repro: str | None = None) -> str:
        text = (f"{self.kind} in {self.where} at step {self.step}\n  state:   {self.state}\n"
                f"  message: {self.message}\n  {self.detail.rstrip()}")
        if repro:
            text += "\n  reproduction:\n" + "\n".join("    " + line for line in repro.splitlines())
        return text


class WalkFailure(AssertionError):
    def __init__(self, failure: Failure, repro: str | None = None):
        self.failure = failure
        super().__init__(failure.describe(repro))


# ----- state labels -----------------------------------------------------------------------------------
def startup_stage(v) -> str:
    tl = v.startup.timeline
    if tl is None:
        return "instant"
    t = v.time_s
    if t < tl.initialised_s:
        return "boot"
    if t < tl.gps_fix_s:
        return "no_fix"
    if t < tl.origin_s:
        return "no_home"
    if t < tl.gps_in_use_s:
        return "no_position"
    return "ready"


def flight_phase(v) -> str:
    if not v.armed:
        return "disarmed" if v.landed else "disarmed_air"
    try:
        return PHASES.get(v.landed_state(), "?")
    except Exception:  # noqa: BLE001 - a label must not hide the failure the telemetry will report
        return "?"


def facets(v, s) -> tuple:
    """(stage, mode, phase, flags): what a state is, for labels and coverage."""
    mode = MODE_NAMES.get(v.mode.number, str(v.mode.number))
    flags = []
    fs = v.failsafes
    if fs.battery_level:
        flags.append("fs:batt_crit" if fs.battery_level >= 2 else "fs:batt_low")
    if fs.gcs:
        flags.append("fs:gcs")
    if fs.fence.breaches:
        flags.append("fs:fence")
    if fs.ekf.failsafe:
        flags.append("fs:ekf")
    if fs.terrain:
        flags.append("fs:terrain")
    if v.startup.gps_powered_up(v.time_s) and v.gps.fix_type < 3:
        flags.append("gps_lost")
    if fs.ekf.gps_glitching:
        flags.append("gps_glitch")
    flags.append("home" if v.home_ned is not None else "no_home")
    for k in sorted(s.missions.uploads):
        flags.append(f"xfer:{KIND_NAMES.get(k, k)}")
    if s.params.streaming:
        flags.append("xfer:params")
    if s.ftp.file is not None:
        flags.append("xfer:ftp")
    if v.camera.busy:
        flags.append("camera_busy")
    return startup_stage(v), mode, flight_phase(v), flags


def label_of(v, s) -> str:
    stage, mode, phase, flags = facets(v, s)
    return " ".join([stage, mode, phase] + flags)


# ----- rendering messages as Python -------------------------------------------------------------------
def _lit(x, py: bool = False) -> str:
    """A field value as text; with `py`, as Python that evaluates to it (math.nan, math.inf)."""
    if isinstance(x, float):
        if math.isnan(x):
            return "math.nan" if py else "nan"
        if math.isinf(x):
            return ("" if x > 0 else "-") + ("math.inf" if py else "inf")
        return repr(x)
    if isinstance(x, (list, tuple)):
        return "[" + ", ".join(_lit(y, py) for y in x) + "]"
    return repr(x)


def encode_call(msg) -> str:
    """The pymavlink call that builds `msg` (a decoded message), e.g. command_long_encode(1, 1, ...)."""
    args = []
    for name in msg.fieldnames:
        raw = getattr(msg, f"_{name}_raw", None)
        args.append(_lit(raw if raw is not None else getattr(msg, name), py=True))
    return f"{msg.get_type().lower()}_encode({', '.join(args)})"


def describe_message(msg) -> str:
    return f"{msg.get_type()}({', '.join(f'{n}={_lit(getattr(msg, n))}' for n in msg.fieldnames)})"


# ----- the walk ---------------------------------------------------------------------------------------
class Walk:
    def __init__(self, start: str = "realistic", decode_every: int = 1):
        """`start`: "realistic" (ArduCopter's start-up, startup.py), "instant" or "camera" (instant,
        with a camera); `decode_every`:
        every message the vehicle sends is packed, and every decode_every-th of its telemetry
        decoded again (answers to a message always are)."""
        if start not in STARTS:
            raise ValueError(f"start must be one of {STARTS}")
        self.start = start
        timeline = StartupTimeline() if start == "realistic" else None
        params = ParamStore()
        if start == "camera":
            for name, value in CAMERA_PARAMS.items():
                params.set(name, value)
        if start == "payload":
            for name, value in PAYLOAD_PARAMS.items():
                params.set(name, value)
        self.vehicle = v = Vehicle(VehicleConfig(startup=timeline), params)
        self.session = s = Session(v, new_codec(SYSTEM_ID))
        if start == "payload":
            _fit_thermal_camera(v, s)
        self.link = Link(s.codec, s.signing)  # what the vehicle sends is packed as the I/O edge packs it
        self.client = new_codec(*GCS)  # the ground station's codec: builds and packs what it sends
        self._parser = new_codec(0, 0)  # decodes what the ground station packed, as the link does
        self._reader = new_codec(*GCS)  # decodes what the vehicle sent, as the ground station does
        self._decode_every = max(1, decode_every)
        self._packed = 0
        self._gcs_hb = None
        self.origin = v.origin
        self.trace: list = [("start", start)]
        self.steps = 0
        self.gcs_alive = True
        self._next_gcs_heartbeat_s = 0.0
        self.hb_interval_s = 1.0  # what the HEARTBEAT's interval should be (SET_MESSAGE_INTERVAL may change it)
        self.hb_since_s = 0.0  # a gap is measured from the later of this and the last HEARTBEAT
        self.last_hb_s = -math.inf
        self.ftp_seq = 0
        self.visited: Counter = Counter()  # full labels
        self.facets: Counter = Counter()  # stage:, mode:, phase:, mode|phase:, fs:, xfer:, ...
        self.sent: Counter = Counter()  # messages sent, by type
        self.acks: Counter = Counter()  # (command, result) of every COMMAND_ACK
        self.tracebacks: list[str] = []  # of exceptions the vehicle or session caught and counted
        self._keep_tracebacks()

    # ----- sending ------------------------------------------------------------------------------------
    def send(self, built) -> list:
        """Pack `built` as the ground station does, decode it as the link does, hand it to the
        session, check every invariant; what the session answered (decoded by a ground station)."""
        msgs = self._parser.parse_buffer(bytes(built.pack(self.client)))
        assert msgs and len(msgs) == 1 and msgs[0].get_type() != "BAD_DATA", f"harness: {built} did not decode"
        return self.deliver(msgs[0])

    def deliver(self, msg, traced: bool = True) -> list:
        if traced:
            self.trace.append(("send", msg))
            self.steps += 1
        v, s = self.vehicle, self.session
        kind = msg.get_type()
        self.sent[kind] += 1
        state = self.label()
        before = self._snapshot()
        errors = self._error_counts()
        try:
            out = s.receive(msg, v.time_s, v.time_s)
        except Exception:  # noqa: BLE001 - it is what the walk looks for
            self._fail("exception", "session.receive", state, msg, traceback.format_exc())
        self._check_errors(errors, "session.receive", state, msg)
        answers = self._pack(out, "session.receive", state, msg)
        self._check_answers(msg, answers, before, state)
        self._check_valid("session.receive", state, msg)
        self._visit()
        return answers

    def command(self, command: int, *params, as_int: bool = False, frame: int = 0, x: int = 0, y: int = 0):
        p = [float(q) for q in params] + [0.0] * (7 - len(params))
        if as_int:
            return self.send(self.client.command_int_encode(SYSTEM_ID, 1, frame, command, 0, 0, *p[:4], x, y, p[6]))
        return self.send(self.client.command_long_encode(SYSTEM_ID, 1, command, 0, *p))

    def set_param(self, name: str, value: float):
        return self.send(self.client.param_set_encode(SYSTEM_ID, 1, name.encode(), value, mav.MAV_PARAM_TYPE_REAL32))

    # ----- time ---------------------------------------------------------------------------------------
    def advance(self, dt_s: float, gcs: bool | None = None) -> None:
        self.advance_to(self.vehicle.time_s + dt_s, gcs)

    def advance_to(self, t_s: float, gcs: bool | None = None) -> None:
        """Run the vehicle to sim time t_s in 10 ms ticks, as the runner does: the session polled
        at each tick (unless it says it is idle), then the vehicle stepped; the ground station's
        HEARTBEAT goes out every second while `gcs_alive`."""
        if gcs is not None:
            self.gcs_alive = gcs
        self.trace.append(("advance", t_s, self.gcs_alive))
        self.steps += 1
        v, s = self.vehicle, self.session
        idle = getattr(s, "idle", None)
        ticks = 0
        errors = self._error_counts()
        while v.time_s < t_s - 1e-9:
            now = v.time_s
            if self.gcs_alive and now >= self._next_gcs_heartbeat_s - 1e-9:
                self._next_gcs_heartbeat_s = now + GCS_HEARTBEAT_S
                self.deliver(self._gcs_heartbeat(), traced=False)
                errors = self._error_counts()
            check = ticks % LABEL_EVERY_TICKS == 0
            state = self.label() if check else None
            if idle is None or not idle(now, now):
                try:
                    out = s.poll(now, now)
                except Exception:  # noqa: BLE001
                    self._fail("exception", "session.poll", state, None, traceback.format_exc())
                errors = self._check_errors(errors, "session.poll", state, None)
                if out:
                    self._check_heartbeats(self._pack(out, "session.poll", state, None, self._decode_every), now, state)
            self._check_heartbeat_gap(now, state)
            nxt = min(t_s, (math.floor(now / TICK_S + 1e-6) + 1) * TICK_S)
            try:
                v.run_until(nxt)
            except Exception:  # noqa: BLE001
                self._fail("exception", "vehicle.run_until", state, None, traceback.format_exc())
            errors = self._check_errors(errors, "vehicle.run_until", state, None)
            if check:
                if ticks % VALID_EVERY_TICKS == 0:
                    self._check_valid("vehicle.run_until", state, None)
                self._visit()
            ticks += 1
        self._check_valid("vehicle.run_until", None, None)
        self._visit()

    def _gcs_heartbeat(self):
        if self._gcs_hb is None:
            built = self.client.heartbeat_encode(mav.MAV_TYPE_GCS, mav.MAV_AUTOPILOT_INVALID, 0, 0, 0)
            self._gcs_hb = self._parser.parse_buffer(bytes(built.pack(self.client)))[0]
        return self._gcs_hb

    # ----- invariants ---------------------------------------------------------------------------------
    def _snapshot(self) -> tuple:
        """What a refused command must leave as it was: arming, the mode, home, and what the payload
        commands move (the winch's control, the thermal camera's card and capture)."""
        v = self.vehicle
        winch = v.winch
        payload = (winch.mode, winch.length_desired_m, winch.rate_desired_m_s)
        thermal = self.session.camera_component
        if thermal is not None:
            camera = thermal.camera
            payload += (len(camera.stills), camera.interval_s, camera.left)
        return v.armed, int(v.mode.number), repr(v.home_ned), repr(payload)

    def _error_counts(self) -> tuple:
        """(handler errors, internal errors, tracebacks kept): what _check_errors compares."""
        errors = getattr(self.vehicle, "internal_errors", None)
        return (self.session.counters.get("handler_errors", 0),
                getattr(errors, "count", 0) if errors is not None else 0, len(self.tracebacks))

    def _check_errors(self, before: tuple, where: str, state, msg) -> tuple:
        """Fails on a new handler or internal error since `before`; the counts now."""
        now = handler, internal, _ = self._error_counts()
        if now[:2] == before[:2]:
            return now
        kept = self.tracebacks[before[2]:]
        tb = kept[0] if kept else "(no traceback kept)"
        if handler != before[0]:
            self._fail("handler_error", where, state, msg, f"{self.session.last_handler_error}\n{tb}")
        errors = self.vehicle.internal_errors
        self._fail("internal_error", where, state, msg,
                   f"internal_errors.count {before[1]} -> {internal}, bits 0x{getattr(errors, 'bits', 0):x}: "
                   f"{getattr(errors, 'last', '')}\n{tb}")

    def _pack(self, out: list, where: str, state, msg, decode_every: int = 1) -> list:
        """Pack each message as the link does, and decode (every `decode_every`th of them) as a
        ground station does; the messages, decoded where they were."""
        decoded = []
        for m in out:
            self._packed += 1
            try:
                frames = self.link.pack([m])
            except Exception:  # noqa: BLE001
                fields = ", ".join(f"{n}={_lit(getattr(m, n, None))}" for n in getattr(m, "fieldnames", ()))
                self._fail("pack", where, state, msg,
                           f"{m.get_type()}: does not pack: {m.get_type()}({fields})\n{traceback.format_exc()}")
            if self._packed % decode_every:
                decoded.append(m)
                continue
            try:  # one whole frame: the header's length, the CRC and the fields must all hold
                got = self._reader.decode(bytearray(frames[0]))
            except Exception as exc:  # noqa: BLE001
                got = exc
            if isinstance(got, Exception) or got.get_type() != m.get_type():
                self._fail("pack", where, state, msg,
                           f"{m.get_type()}: packed into a frame a ground station does not decode: {got!r}")
            decoded.append(got)
        return decoded

    def _check_answers(self, msg, answers: list, before: tuple, state: str) -> None:
        v = self.vehicle
        kind = msg.get_type()
        addressed = getattr(msg, "target_system", getattr(msg, "target", 0)) in (0, SYSTEM_ID)
        acks = [m for m in answers if m.get_type() == "COMMAND_ACK"]
        for a in acks:
            self.acks[(a.command, a.result)] += 1
        if not addressed:
            if answers or self._snapshot() != before:
                self._fail("other_system", "session.receive", state, msg,
                           f"a message for system {msg.target_system if hasattr(msg, 'target_system') else msg.target} "
                           f"was answered {[a.get_type() for a in answers]} or changed "
                           f"(armed, mode, home) {before} -> {self._snapshot()}")
            return
        command = msg.command if kind in ("COMMAND_LONG", "COMMAND_INT") else None  # SET_MODE: unanswered
        if command is not None:
            if len(acks) != 1 or acks[0].command != command:
                self._fail("ack", "session.receive", state, msg,
                           f"expected exactly one COMMAND_ACK for command {command}, got "
                           f"{[(a.command, a.result) for a in acks]}")
            result = acks[0].result
            if result != ACCEPTED and self._snapshot() != before:
                self._fail("refused_changed", "session.receive", state, msg,
                           f"refused with result {result} yet (armed, mode, home) changed {before} -> "
                           f"{self._snapshot()}")
            if result == ACCEPTED and command == mav.MAV_CMD_SET_MESSAGE_INTERVAL and msg.param1 == 0:
                self._heartbeat_interval_asked(msg.param2)
        if v.armed and not before[0]:
            if not (command == ARM and msg.param1 == 1 and acks and acks[0].result == ACCEPTED):
                self._fail("unasked_arm", "session.receive", state, msg, "armed without an accepted ARM")

    def _heartbeat_interval_asked(self, interval_us: float) -> None:
        if interval_us < 0:
            self.hb_interval_s = math.inf
        elif interval_us == 0:
            self.hb_interval_s = 1.0
        else:
            self.hb_interval_s = max(interval_us * 1e-6, 0.001)
        self.hb_since_s = self.vehicle.time_s

    def _check_heartbeats(self, answers: list, now: float, state) -> None:
        v = self.vehicle
        for m in answers:
            if m.get_type() == "HEARTBEAT" and m.type != mav.MAV_TYPE_CAMERA:  # the autopilot's, not component 100's
                self.last_hb_s = now
                armed = bool(m.base_mode & mav.MAV_MODE_FLAG_SAFETY_ARMED)
                if m.custom_mode != v.mode.number or armed != v.motors_armed:  # (a motor test arms the motors)
                    self._fail("heartbeat", "session.poll", state, None,
                               f"HEARTBEAT says mode {m.custom_mode} armed {armed}; the vehicle is in mode "
                               f"{v.mode.number} with its motors armed {v.motors_armed}")

    def _check_heartbeat_gap(self, now: float, state) -> None:
        allowed = max(HEARTBEAT_GAP_S, 1.5 * self.hb_interval_s)
        gap = now - max(self.last_hb_s, self.hb_since_s)
        if gap > allowed + 1e-6:
            self._fail("heartbeat", "session.poll", state, None,
                       f"no HEARTBEAT for {gap:.2f} s of sim time (at most {allowed:.2f} s allowed)")

    def _check_valid(self, where: str, state, msg) -> None:
        problems = vehicle_problems(self.vehicle)
        if problems:
            self._fail("invalid_state", where, state, msg, "; ".join(problems))

    def _fail(self, kind: str, where: str, state, msg, detail: str):
        if state is None:
            try:
                state = self.label()
            except Exception as exc:  # noqa: BLE001
                state = f"(no label: {type(exc).__name__}: {exc})"
        message = describe_message(msg) if msg is not None else f"(the tick at sim time {self.vehicle.time_s:.2f} s)"
        raise WalkFailure(Failure(kind, where, state, message, detail, self.steps, list(self.trace)))

    def _keep_tracebacks(self) -> None:
        """Keep the traceback of every exception the vehicle and session catch and count (a
        handler that raised, an internal error): they go on, the walk reports it with where it
        came from. Wraps the session's handlers and the vehicle's internal-error recorder."""
        handlers = getattr(self.session, "_handlers", None)
        if isinstance(handlers, dict):
            for name, handler in list(handlers.items()):
                handlers[name] = self._traced(handler)
        errors = getattr(self.vehicle, "internal_errors", None)
        record = getattr(errors, "record", None)
        if record is not None:
            def traced_record(exc, *args, **kwargs):
                self.tracebacks.append("".join(traceback.format_exception(type(exc), exc, exc.__traceback__)))
                return record(exc, *args, **kwargs)
            errors.record = traced_record

    def _traced(self, handler):
        def call(msg, now):
            try:
                return handler(msg, now)
            except Exception:
                self.tracebacks.append(traceback.format_exc())
                raise
        return call

    # ----- coverage -----------------------------------------------------------------------------------
    def label(self) -> str:
        return label_of(self.vehicle, self.session)

    def _visit(self) -> None:
        stage, mode, phase, flags = facets(self.vehicle, self.session)
        self.visited[" ".join([stage, mode, phase] + flags)] += 1
        f = self.facets
        f[f"stage:{stage}"] += 1
        f[f"mode:{mode}"] += 1
        f[f"phase:{phase}"] += 1
        f[f"{mode}|{phase}"] += 1
        for flag in flags:
            f[flag] += 1

    # ----- what the actions use -----------------------------------------------------------------------
    def awaiting(self) -> dict:
        """{mission_type: next seq} of the uploads in progress."""
        return {k: len(up.items) for k, up in self.session.missions.uploads.items()}

    def ftp(self, session: int, opcode: int, size: int = 0, offset: int = 0, data: bytes = b""):
        self.ftp_seq = (self.ftp_seq + 1) & 0xFFFF
        return self.send(self.client.file_transfer_protocol_encode(
            0, SYSTEM_ID, 1, ftp_payload(self.ftp_seq, session, opcode, size, offset, data)))

    def upload(self, kind: int, items: list, stop_after: int | None = None) -> None:
        """MISSION_COUNT and the items (command, frame, p1..p4, x, y, z) in order; with stop_after,
        only that many items: the transfer is left half done."""
        c = self.client
        self.send(c.mission_count_encode(SYSTEM_ID, 1, len(items), kind))
        for seq, (command, fr, p1, p2, p3, p4, x, y, z) in enumerate(items[:stop_after]):
            self.send(c.mission_item_int_encode(SYSTEM_ID, 1, seq, fr, command, 0, 1, p1, p2, p3, p4, x, y, z, kind))


# ----- actions: each drives the walk one step towards some state, or attacks the one it is in -----------
REL = mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT
GUIDED, AUTO, LAND, RTL = 4, 3, 9, 6
ADVANCE_S = (0.01, 0.01, 0.02, 0.05, 0.1, 0.1, 0.2, 0.5, 1.0, 3.0)
START_AT_S = (0.0, 1.0, 3.0, 6.0, 11.0, 15.0, 20.5, 25.0, 42.0, 45.0)  # realistic start-up: every stage


def act_advance(w: Walk, r) -> None:
    w.advance(r.choice(ADVANCE_S))


def act_set_mode(w: Walk, r) -> None:
    mode = r.choice(hostile.MODES)
    how = r.randrange(3)
    if how == 0:
        w.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, mode)
    elif how == 1:
        w.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, mode, as_int=True)
    else:
        w.send(w.client.set_mode_encode(SYSTEM_ID, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, mode))


def act_arm(w: Walk, r) -> None:
    w.command(ARM, 1, FORCE_ARM if r.random() < 0.3 else 0)


def act_arm_in_mode(w: Walk, r) -> None:
    """A mode that arms (STABILIZE, ALT_HOLD, GUIDED, LOITER, POSHOLD), then ARM."""
    w.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, r.choice((0, 2, 4, 5, 16)))
    w.command(ARM, 1, FORCE_ARM if r.random() < 0.3 else 0)


def act_settle(w: Walk, r) -> None:
    """Let the flight play out: up to 40 s, until the vehicle is disarmed on the ground."""
    end = w.vehicle.time_s + 40.0
    while w.vehicle.time_s < end - 1e-9 and (w.vehicle.armed or not w.vehicle.landed):
        w.advance(1.0)


def act_disarm(w: Walk, r) -> None:
    w.command(ARM, 0, FORCE_DISARM if r.random() < 0.2 else 0)


def act_takeoff(w: Walk, r) -> None:
    w.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, r.choice((2.0, 5.0, 10.0, 25.0)))


def act_fly(w: Walk, r) -> None:
    """GUIDED, arm (forced half the time: before the position estimate too), take off, climb a while
    (the vehicle leaves the ground about 4 s after arming: the arming delay, then the spool-up)."""
    w.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, GUIDED)
    w.command(ARM, 1, FORCE_ARM if r.random() < 0.5 else 0)
    w.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, r.choice((5.0, 10.0, 20.0)))
    w.advance(r.choice((1.0, 4.5, 5.0, 7.0)))


def act_land(w: Walk, r) -> None:
    how = r.randrange(4)
    if how == 0:
        w.command(mav.MAV_CMD_NAV_LAND)
    elif how == 1:
        w.command(mav.MAV_CMD_NAV_RETURN_TO_LAUNCH)
    else:
        w.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, LAND if how == 2 else RTL)


def act_goto(w: Walk, r) -> None:
    c = w.client
    if r.random() < 0.5:
        mask = 0b110111111000  # position only
        w.send(c.set_position_target_local_ned_encode(0, SYSTEM_ID, 1, mav.MAV_FRAME_LOCAL_NED, mask,
                                                      r.uniform(-60, 60), r.uniform(-60, 60), -r.uniform(2, 30),
                                                      0, 0, 0, 0, 0, 0, 0, 0))
    else:
        lat, lon = near(w.origin, r, 80)
        w.command(mav.MAV_CMD_DO_REPOSITION, -1, mav.MAV_DO_REPOSITION_FLAGS_CHANGE_MODE, 0, param_f(r, math.nan),
                  0, 0, param_f(r, r.uniform(3, 30)), as_int=True, frame=REL, x=lat, y=lon)


def act_pilot(w: Walk, r) -> None:
    c = w.client
    if r.random() < 0.5:
        w.send(c.manual_control_encode(SYSTEM_ID, r.randint(-1000, 1000), r.randint(-1000, 1000),
                                       r.choice((0, 500, 700, 1000)), r.randint(-1000, 1000), 0))
    else:
        w.send(c.rc_channels_override_encode(SYSTEM_ID, 1, r.randint(1100, 1900), r.randint(1100, 1900),
                                             r.choice((1000, 1500, 1700, 2000)), r.randint(1100, 1900), 0, 0, 0, 0))


# Every mission command AUTO names (a new item joins the walk by joining that table), and values its
# parameters mean something with: turns, radii, seconds, metres, flags, angles, a negative direction.
MISSION_COMMANDS = tuple(sorted(MISSION_COMMAND_NAMES))
PLAUSIBLE_PARAMS = (0.0, 1.0, 2.0, 3.0, 5.0, 10.0, 45.0, 90.0, -1.0, -90.0, 300.0)


def mission_items(w: Walk, r) -> list:
    """A mission as a ground station uploads it (seq 0 home), with a DO_JUMP, speeds, loiters and
    landings, and hostile parameters (NaN most of all) in some of them."""
    items = [(16, 0, 0, 0, 0, 0, *near(w.origin, r, 0), 0.0)]
    for _ in range(r.randint(1, 8)):
        lat, lon = near(w.origin, r, 120)
        alt = param_f(r, r.uniform(3, 40), 0.1)
        pick = r.randrange(12)
        n = len(items) + 1
        if pick < 4:
            items.append((16, REL, param_f(r, 0.0), 0, 0, param_f(r, math.nan, 0.1), lat, lon, alt))
        elif pick == 4:
            items.append((22, REL, 0, 0, 0, math.nan, 0, 0, alt))
        elif pick == 5:  # DO_JUMP: target and repeat count, NaN as often as not
            items.append((177, 2, param_f(r, float(r.randint(0, n)), 0.5), param_f(r, float(r.randint(-1, 3)), 0.5),
                          param_f(r, 0.0, 0.2), 0, 0, 0, 0.0))
        elif pick == 6:
            items.append((178, 2, 0, param_f(r, 5.0, 0.5), -1, 0, 0, 0, math.nan))
        elif pick == 7:
            items.append((19, REL, param_f(r, 2.0, 0.4), 0, 0, 0, lat, lon, alt))
        elif pick <= 10:  # any command the mission knows, with the parameters its items read
            command = r.choice(MISSION_COMMANDS)
            items.append((command, r.choice((REL, 2, 0)), *(param_f(r, r.choice(PLAUSIBLE_PARAMS), 0.3)
                                                            for _ in range(4)), lat, lon, alt))
        else:
            items.append((hostile.command_id(r), hostile.frame(r), *(hostile.f32(r) for _ in range(4)),
                          hostile.i32(r), hostile.i32(r), hostile.f32(r)))
    return items


def fence_items(w: Walk, r) -> list:
    """Polygons (vertex count in p1: 3, 4, NaN, 0, 255, ...) and circles (radius NaN, -1, 0, 40),
    inclusion and exclusion, and a return point."""
    items = []
    for _ in range(r.randint(1, 3)):
        shape = r.randrange(3)
        if shape == 0:
            command = r.choice((5001, 5002))
            count = r.choice((3, 4, 5))
            p1 = param_f(r, float(count), 0.5)
            radius = r.uniform(15, 120)
            for k in range(count):
                a = 2 * math.pi * k / count
                lat = w.origin.lat_deg + radius * math.cos(a) / 111_320.0
                lon = w.origin.lon_deg + radius * math.sin(a) / (111_320.0 * math.cos(math.radians(w.origin.lat_deg)))
                items.append((command, REL, p1, 0, 0, 0, int(lat * 1e7), int(lon * 1e7), 0.0))
        elif shape == 1:
            lat, lon = near(w.origin, r, 30)
            items.append((r.choice((5003, 5004)), REL, param_f(r, r.uniform(10, 80), 0.5), 0, 0, 0, lat, lon, 0.0))
        else:
            lat, lon = near(w.origin, r, 30)
            items.append((5000, REL, 0, 0, 0, 0, lat, lon, param_f(r, 10.0, 0.3)))
    return items


def rally_items(w: Walk, r) -> list:
    return [(5100, REL, 0, 0, 0, 0, *near(w.origin, r, 100), param_f(r, 15.0, 0.4)) for _ in range(r.randint(1, 3))]


def act_mission(w: Walk, r) -> None:
    items = mission_items(w, r)
    w.upload(0, items, None if r.random() < 0.75 else r.randrange(len(items)))


def act_fence(w: Walk, r) -> None:
    items = fence_items(w, r)
    w.upload(1, items, None if r.random() < 0.75 else r.randrange(len(items)))
    if r.random() < 0.7:
        w.set_param("FENCE_TYPE", float(r.choice((4, 5, 7, 6))))
        w.set_param("FENCE_ENABLE", 1.0)


def act_rally(w: Walk, r) -> None:
    items = rally_items(w, r)
    w.upload(2, items, None if r.random() < 0.7 else r.randrange(len(items)))


def act_mission_start(w: Walk, r) -> None:
    if r.random() < 0.7:
        w.command(mav.MAV_CMD_MISSION_START)
    else:
        w.send(w.client.mission_set_current_encode(SYSTEM_ID, 1, r.randint(0, 5)))


def act_battery(w: Walk, r) -> None:
    name, value = r.choice((("FS_BATT_ENABLE", 1.0), ("FS_BATT_ENABLE", 2.0), ("BATT_LOW_VOLT", 17.0),
                            ("BATT_CRT_VOLT", 16.9), ("SIM_BATT_VOLTAGE", 13.0), ("BATT_LOW_VOLT", 10.5),
                            ("BATT_CRT_VOLT", 0.0), ("SIM_BATT_VOLTAGE", 16.8)))
    w.set_param(name, value)


def act_gcs(w: Walk, r) -> None:
    if w.gcs_alive:
        w.set_param("FS_GCS_ENABLE", float(r.choice((1, 2, 5))))
        w.advance(r.choice((2.0, 6.0, 8.0)), gcs=False)  # silence: longer than FS_GCS_TIMEOUT (5 s)
    else:
        w.advance(r.choice((0.5, 2.0)), gcs=True)


def act_gps(w: Walk, r) -> None:
    name, value = r.choice((("SIM_GPS1_ENABLE", 0.0), ("SIM_GPS1_ENABLE", 1.0), ("SIM_GPS1_ENABLE", 0.0),
                            ("SIM_GPS1_ENABLE", 1.0), ("SIM_GPS1_NUMSATS", 3.0), ("SIM_GPS1_NUMSATS", 10.0),
                            ("SIM_GPS1_GLTCH_X", 0.0005), ("SIM_GPS1_GLTCH_X", 0.0), ("FS_EKF_ACTION", 2.0)))
    w.set_param(name, value)


def act_fence_params(w: Walk, r) -> None:
    name, value = r.choice((("FENCE_ENABLE", 1.0), ("FENCE_ENABLE", 0.0), ("FENCE_TYPE", float(r.randint(1, 7))),
                            ("FENCE_ALT_MAX", 10.0), ("FENCE_RADIUS", 30.0), ("FENCE_ACTION", float(r.randint(0, 5)))))
    w.set_param(name, value)


def act_param_list(w: Walk, r) -> None:
    w.send(w.client.param_request_list_encode(SYSTEM_ID, 1))


def act_ftp(w: Walk, r) -> None:
    from firefly.autopilot.mavlink import ftp
    session = r.choice((0, 1))
    step = r.randrange(6)
    path = b"@PARAM/param.pck"
    if step <= 1:
        w.ftp(session, ftp.OPEN_FILE_RO, len(path), 0, path)
    elif step == 2:
        w.ftp(session, ftp.READ_FILE, 239, r.choice((0, 239, 100_000)))
    elif step == 3:
        w.ftp(session, ftp.BURST_READ_FILE, 239, 0)
    elif step == 4:
        w.ftp(session, ftp.CREATE_FILE, len(path), 0, path)
        data = bytes(r.getrandbits(8) for _ in range(r.randint(0, 200)))
        w.ftp(session, ftp.WRITE_FILE, len(data), 0, data)
    else:
        w.ftp(session, r.choice((ftp.TERMINATE_SESSION, ftp.RESET_SESSIONS)))


def act_hostile(w: Walk, r) -> None:
    for _ in range(r.choice((1, 1, 1, 2, 4, 8))):
        w.send(hostile.hostile_message(w.client, r, w.awaiting()))


def act_camera(w: Walk, r) -> None:
    """A camera command, as a ground station sends them (its values hostile now and then): a
    picture, an interval capture, distance triggering on or off, the capture stopped."""
    how = r.randrange(4)
    if how == 0:
        w.command(mav.MAV_CMD_DO_DIGICAM_CONTROL, 0, 0, 0, 0, param_f(r, 1.0))
    elif how == 1:
        w.command(mav.MAV_CMD_IMAGE_START_CAPTURE, 0, param_f(r, r.choice((0.5, 1.0, 3.0))), param_f(r, r.randrange(6)))
    elif how == 2:
        w.command(mav.MAV_CMD_DO_SET_CAM_TRIGG_DIST, param_f(r, r.choice((0.0, 5.0, 20.0))), 0, param_f(r, 1.0))
    else:
        w.command(mav.MAV_CMD_IMAGE_STOP_CAPTURE)


def _fit_thermal_camera(v, s) -> None:
    """The thermal camera and its component as the CLI fits them (cli/main.py), its stills kept on
    its card only (no copy on disk)."""
    from firefly.autopilot.cli.main import attach_thermal_camera
    from firefly.autopilot.payload.thermal_camera import ThermalCamera, look_of
    from firefly.sim.thermal_camera import ThermalCameraSpec
    camera = ThermalCamera(ThermalCameraSpec(), v.config.sim.world, look=lambda: look_of(v), now=lambda: v.time_s)
    attach_thermal_camera(v, s, camera.spec, None, {"thermal_camera": camera})


def act_payload(w: Walk, r) -> None:
    """What the payload start's devices take (their values hostile now and then): DO_WINCH (any
    action), a command to the thermal camera's component (any it knows, and others), MAVLink FTP
    to it, FLOWHOLD, the devices' parameters."""
    how = r.randrange(5)
    if how == 4:  # the card, by MAVLink FTP to the camera: any opcode, its paths or others
        data = r.choice((b"DCIM", b"DCIM/IR_0000.tif", b"/", b"", b"@PARAM/param.pck", b"DCIM/IR_0000.tif/x"))
        payload = ftp_payload(r.randrange(65536), r.choice((0, 0, 1, 255)), r.choice(hostile.FTP_OPCODES), len(data),
                              r.choice((0, 239, 2**32 - 1)), data)
        w.send(w.client.file_transfer_protocol_encode(0, SYSTEM_ID, mav.MAV_COMP_ID_CAMERA, payload))
    elif how == 0:
        w.command(mav.MAV_CMD_DO_WINCH, 1, param_f(r, r.choice((0, 1, 2, 3))), param_f(r, r.uniform(-5, 5)),
                  param_f(r, r.uniform(-2, 2)), as_int=r.random() < 0.3)
    elif how == 1:
        from firefly.autopilot.mavlink.camera_component import COMMANDS, CameraComponent
        command = r.choice(sorted(COMMANDS) + [mav.MAV_CMD_COMPONENT_ARM_DISARM, mav.MAV_CMD_DO_WINCH, 0])
        p = [param_f(r, r.choice((0.0, 1.0, 0.5, -1.0, 259.0, 263.0)), 0.4) for _ in range(7)]
        w.send(w.client.command_long_encode(SYSTEM_ID, CameraComponent.COMPONENT, command, 0, *p))
    elif how == 2:
        w.command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, int(ModeNumber.FLOWHOLD))
    else:
        w.set_param(r.choice(("SIM_FLOW_ENABLE", "SIM_FLOW_POS_Z", "WINCH_RATE_MAX", "FLOW_TYPE")),
                    param_f(r, r.choice((0.0, 1.0, 0.5, 5.0)), 0.2))


def act_terrain(w: Walk, r) -> None:
    """Terrain (its values hostile now and then): its parameters (RTL above terrain, the database
    off), targets in the terrain frame (GUIDED's SET_POSITION_TARGET_GLOBAL_INT, DO_REPOSITION),
    and a ground station's TERRAIN_DATA for the block the vehicle asks about, or for another."""
    c, v, how = w.client, w.vehicle, r.randrange(4)
    terrain_frame = mav.MAV_FRAME_GLOBAL_TERRAIN_ALT_INT
    if how == 0:
        w.set_param(*r.choice((("RTL_ALT_TYPE", 1.0), ("RTL_ALT_TYPE", 0.0), ("TERRAIN_ENABLE", 0.0),
                               ("TERRAIN_ENABLE", 1.0), ("WPNAV_RFND_USE", 0.0), ("TERRAIN_SPACING", 30.0))))
    elif how == 1:
        lat, lon = near(w.origin, r, 80)
        w.send(c.set_position_target_global_int_encode(0, SYSTEM_ID, 1, terrain_frame, 0b110111111000, lat, lon,
                                                       param_f(r, r.uniform(3, 30)), 0, 0, 0, 0, 0, 0, 0, 0))
    elif how == 2:
        lat, lon = near(w.origin, r, 80)
        w.command(mav.MAV_CMD_DO_REPOSITION, -1, mav.MAV_DO_REPOSITION_FLAGS_CHANGE_MODE, 0, math.nan, 0, 0,
                  param_f(r, r.uniform(3, 30)), as_int=True, frame=terrain_frame, x=lat, y=lon)
    else:
        block = v.terrain.request(v.params, v.terrain_here())
        if block is not None and r.random() < 0.8:
            lat, lon, spacing = block.lat_e7, block.lon_e7, block.spacing_m
        else:
            (lat, lon), spacing = near(w.origin, r, 3000), r.choice((0, 30, 100, 65535))
        w.send(c.terrain_data_encode(lat, lon, spacing, r.choice((r.randrange(56), 56, 255)),
                                     [r.choice((600, 584, -32768, 32767)) for _ in range(16)]))


def act_gps_jam(w: Walk, r) -> None:
    """SIM_GPS1_JAM on and off, and the EKF check's filter, threshold and vibration switch, their
    values hostile now and then: the jammed GPS's variances, glitch flag and vibration check."""
    name = r.choice(("SIM_GPS1_JAM", "SIM_GPS1_JAM", "FS_EKF_FILT", "FS_EKF_THRESH", "FS_VIBE_ENABLE"))
    w.set_param(name, param_f(r, r.choice((0.0, 1.0, 5.0, 0.8)), 0.2))


def act_camera_lens(w: Walk, r) -> None:
    """A servo camera's lens and settings outputs (their values hostile now and then): a zoom or a
    focus of any type (a continuous one moves the lens until held), a DO_DIGICAM_CONFIGURE."""
    how = r.randrange(3)
    value = param_f(r, r.choice((-1.0, 0.0, 1.0, 50.0)))
    if how == 0:
        w.command(mav.MAV_CMD_SET_CAMERA_ZOOM, param_f(r, r.randrange(5)), value)
    elif how == 1:
        w.command(mav.MAV_CMD_SET_CAMERA_FOCUS, param_f(r, r.randrange(7)), value)
    else:
        w.command(mav.MAV_CMD_DO_DIGICAM_CONFIGURE, 0, param_f(r, 125.0), param_f(r, 1234.0), param_f(r, 100.0))


def act_known(w: Walk, r) -> None:
    w.send(r.choice(hostile.known_reproductions(w.client, w.origin)))


# name -> (weight in the seeded walk, action)
ACTIONS = {
    "hostile": (30, act_hostile), "advance": (22, act_advance), "set_mode": (9, act_set_mode),
    "arm": (3, act_arm), "arm_in_mode": (2, act_arm_in_mode), "disarm": (2, act_disarm),
    "settle": (1, act_settle), "takeoff": (2, act_takeoff), "fly": (5, act_fly), "land": (3, act_land),
    "goto": (3, act_goto), "pilot": (2, act_pilot), "mission": (3, act_mission), "fence": (2, act_fence),
    "rally": (1, act_rally), "mission_start": (2, act_mission_start), "battery": (2, act_battery),
    "gcs": (1, act_gcs), "gps": (2, act_gps), "fence_params": (2, act_fence_params),
    "param_list": (1, act_param_list), "ftp": (2, act_ftp), "known": (3, act_known),
    "camera": (3, act_camera),
}


# ----- replaying and shrinking a failure --------------------------------------------------------------
def replay(trace: list) -> Failure | None:
    """Run a recorded trace on a fresh walk: the failure it ends in, or None."""
    w = Walk(trace[0][1])
    try:
        for action in trace[1:]:
            if action[0] == "send":
                w.deliver(action[1])
            else:
                w.advance_to(action[1], gcs=action[2])
    except WalkFailure as exc:
        return exc.failure
    return None


def merge_advances(steps: list) -> list:
    """Consecutive advances with the same ground-station state as one (their targets are absolute)."""
    out = []
    for action in steps:
        if out and action[0] == "advance" and out[-1][0] == "advance" and out[-1][2] == action[2]:
            out[-1] = action
        else:
            out.append(action)
    return out


def shrink(failure: Failure, budget_s: float = 20.0) -> list:
    """The shortest trace found within budget_s of wall time that still ends in a failure with the
    same signature: first the last few messages alone with the time that passed, then delta
    debugging (removing ever smaller chunks of steps)."""
    start, steps = failure.trace[:1], failure.trace[1:]
    want = failure.signature()
    deadline = time.monotonic() + budget_s

    def fails(candidate) -> bool:
        got = replay(start + candidate)
        return got is not None and got.signature() == want

    sends = [i for i, action in enumerate(steps) if action[0] == "send"]
    for k in (1, 2, 4, 8, 16):
        if k > len(sends) or time.monotonic() >= deadline:
            break
        keep = set(sends[-k:])
        candidate = merge_advances([a for i, a in enumerate(steps) if a[0] == "advance" or i in keep])
        if fails(candidate):
            steps = candidate
            break
    else:
        candidate = merge_advances(steps)
        if candidate != steps and time.monotonic() < deadline and fails(candidate):
            steps = candidate
    n = 2
    while len(steps) >= 2 and time.monotonic() < deadline:
        chunk = math.ceil(len(steps) / n)
        for i in range(n):
            candidate = steps[:i * chunk] + steps[(i + 1) * chunk:]
            if time.monotonic() >= deadline:
                break
            if candidate != steps and fails(candidate):
                steps, n = candidate, max(n - 1, 2)
                break
        else:
            if chunk == 1:
                break
            n = min(len(steps), n * 2)
    return start + steps


def render(trace: list) -> str:
    """A trace as Python that replays it (and raises the same WalkFailure)."""
    lines = ["from tests.fuzz.state_machine import Walk", f"w = Walk({trace[0][1]!r})",
             "c = w.client" if any(a[0] == "send" for a in trace[1:]) else None]
    for action in trace[1:]:
        if action[0] == "send":
            lines.append(f"w.send(c.{encode_call(action[1])})")
        else:
            lines.append(f"w.advance_to({round(action[1], 6)!r}{'' if action[2] else ', gcs=False'})")
    text = "\n".join(line for line in lines if line)
    return ("import math\n" + text) if "math." in text else text

"""What goes into the dataflash log, and when, as ArduPilot's logger decides it; sans-IO.

The I/O edge calls tick() after each loop tick of the vehicle (100 Hz of sim time) and hands the
recorder a LogSink (the log files, autopilot/io/dataflash_files.py) that it starts, writes and
stops. Timestamps (TimeUS) are sim microseconds since boot, so a flight's log is the same on
every run.

When ArduPilot logs (measured on ArduCopter 4.7 SITL, and its AP_Logger): LOG_BACKEND_TYPE bit 0
(file) must be set. With LOG_DISARMED 0 it logs while armed, for 15 s after a disarm, and for 15 s
after an arming attempt that failed; a fresh SITL writes no log until then. Any other
LOG_DISARMED logs always. A log file, once started, is continued at the next arming; with
LOG_FILE_DSRMROT 1 it is closed when logging stops after a disarm (at once when logging never
stops), so each flight gets its own file.

A log starts with its self-description (FMT for every message, then UNIT, MULT, FMTU), every
parameter (PARM), the current mode (MODE) and the mission (CMD); then come the events (EV on arm,
disarm, landing and take-off; MODE on a mode change; MSG for each status text; ERR for a refused
mode change; PARM for each parameter change; CMD when the mission changes) and the flight data
at their rates (messages.py).
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Protocol

from ..c_casts import as_int16
from ..modes import MODE_BY_NAME
from ..params import SERVED_BY_NAME
from ..results import Severity
from ..views import DataflashView
from .encoding import fmt_record
from .flight_data import gps_week_time
from .messages import CAMERA, FORMATS, MESSAGES, MULTS, PERIODIC, UNITS

if TYPE_CHECKING:
    from ..payload.camera import Feedback

INSTANCE_AT = 11  # offset of a per-instance record's instance number: after the header and TimeUS
ARM_PERSIST_S = 15.0  # ArduPilot's HAL_LOGGER_ARM_PERSIST
BACKEND_FILE = 1
# EV ids (AP_Logger's LogEvent)
EV_ARMED, EV_DISARMED, EV_LAND_COMPLETE, EV_NOT_LANDED = 10, 11, 18, 28
ERR_FLIGHT_MODE = 10  # ERR subsystem of a refused mode change; its code is the mode's number
MODE_REASON_UNKNOWN = 0  # Firefly does not keep why the mode changed
MAX_PENDING = 4096  # events waiting for the next tick (a flood of parameter sets cannot grow memory)
LOGGING_PARAMS = ("LOG_BACKEND_TYPE", "LOG_DISARMED", "LOG_BITMASK", "LOG_FILE_DSRMROT")


class LogSink(Protocol):
    """Where the log goes: a numbered file the I/O edge opens, writes in big chunks and closes."""

    @property
    def open(self) -> bool: ...
    @property
    def paused(self) -> bool: ...
    def start(self) -> None: ...
    def write(self, data: bytes) -> None: ...
    def stop(self) -> None: ...


def _us(t_s: float) -> int:
    return int(round(t_s * 1e6))


class _Group:
    """The flight data messages logged at one rate, and when they are next due [sim us]."""

    def __init__(self, every_us: int):
        self.every_us = every_us
        self.next_us = 0
        self.members: list = []


def _schedule() -> list[_Group]:
    groups: dict[int, _Group] = {}
    for fmt, p in PERIODIC:
        every = _us(p.every_s)
        groups.setdefault(every, _Group(every)).members.append((fmt, p))
    return list(groups.values())


def _header(t_us: int) -> bytes:
    """FMT, UNIT, MULT and FMTU records: the log's description of itself."""
    out = [fmt_record(f) for f in FORMATS.values()]
    unit, mult, fmtu = FORMATS["UNIT"], FORMATS["MULT"], FORMATS["FMTU"]
    out += [unit.pack_text(t_us, ord(k), label) for k, label in UNITS.items()]
    out += [mult.pack(t_us, ord(k), v) for k, v in MULTS.items()]
    out += [fmtu.pack_text(t_us, f.type_id, f.units, f.mults) for f in FORMATS.values()]
    return b"".join(out)


class Recorder:
    def __init__(self, vehicle: DataflashView, sink: LogSink):
        self.v = vehicle
        self.sink = sink
        self._pending: list[bytes] = []  # events since the last tick, packed
        self._settings: dict[str, int] = {}
        self._read_settings()
        self.arm_changes = vehicle.arm_changes  # the arms and disarms seen
        self._landed = vehicle.landed
        self._mode = vehicle.mode_number
        self._mission_version = vehicle.mission_version
        # False while nothing is logged and nothing waits: a tick then only looks for an arm or
        # disarm; a status text or parameter change (which queue a record) wakes it too.
        self.awake = True
        self._arm_change_s: float | None = None
        self._arm_failure_s: float | None = None
        self._rotate_pending = False
        self._groups = _schedule()
        self._due_s = 0.0  # sim time of the next flight data records
        self.records = 0  # flight data records written (for the cost measurements)
        vehicle.params.on_change(self._param_changed)
        self._parm = FORMATS["PARM"]
        self._defaults = {name: spec.default for name, spec in SERVED_BY_NAME.items()}

    # ----- hooks the vehicle calls ------------------------------------------------------------
    def text(self, severity: int, text: str) -> None:
        """A status text the vehicle sends (Vehicle.notify)."""
        t_us = _us(self.v.time_s)
        self._queue(FORMATS["MSG"].pack_text(t_us, text[:64]))
        if severity <= Severity.CRITICAL and text.startswith("Arm: "):  # a refused ARM (AP_Arming)
            self._arm_failure_s = self.v.time_s
        if text.startswith("Mode change to ") and " failed" in text:
            name = text[len("Mode change to "):text.index(" failed")]  # ArduCopter's name ("SMARTRTL")
            mode = next((cls for cls in MODE_BY_NAME.values() if cls.text_name == name), None)
            if mode is not None:
                self._queue(FORMATS["ERR"].pack(t_us, ERR_FLIGHT_MODE, int(mode.number)))

    def picture(self, f: Feedback) -> None:
        """A picture the camera took (payload/camera.py): a CAM record, as AP_Camera writes one
        (LOG_BITMASK's camera bit), with the GPS's own altitude beside the estimate's."""
        if not self._settings["LOG_BITMASK"] & CAMERA:
            return
        v = self.v
        week_ms, week = gps_week_time(f.time_usec)
        g = v.gps
        gps_alt_cm = round(v.ned_to_global(g.n_m, g.e_m, g.d_m).alt_m * 100) if g.fix_type >= 3 else 0
        self._queue(FORMATS["CAM"].pack(_us(v.time_s), 0, f.image_index, week_ms, week, f.lat_e7, f.lon_e7,
                                        round(f.alt_msl_m * 100), round(f.alt_rel_m * 100), gps_alt_cm,
                                        as_int16(f.roll_deg * 100), as_int16(f.pitch_deg * 100),
                                        round(f.yaw_deg * 100) % 36000))

    def _param_changed(self, name: str, value: float) -> None:
        if name in LOGGING_PARAMS:
            self._read_settings()
        self._queue(self._parm_record(_us(self.v.time_s), name, value))

    # ----- the loop ---------------------------------------------------------------------------
    def tick(self) -> None:
        """After a loop tick. Most ticks nothing changed and nothing is due: a few reads; asleep,
        one (a vehicle that never arms does not pay for a log it does not write)."""
        v = self.v
        if not self.awake:
            if v.arm_changes == self.arm_changes:
                return
            # what changed while nothing was logged is not logged, as on ArduPilot
            self.awake = True
            self._landed, self._mode, self._mission_version = v.landed, v.mode_number, v.mission_version
        if (v.arm_changes == self.arm_changes and v.time_s < self._due_s and not self._pending
                and v.mode_number == self._mode and v.landed == self._landed):
            return
        self._update(v)

    def _update(self, v: DataflashView) -> None:
        now = v.time_s
        t_us = _us(now)
        armed, changes = v.armed, v.arm_changes
        if changes != self.arm_changes:  # each arm and disarm since the last tick, in order
            count, self.arm_changes, self._arm_change_s = changes - self.arm_changes, changes, now
            for k in range(count):
                now_armed = armed if (count - 1 - k) % 2 == 0 else not armed
                self._queue(FORMATS["EV"].pack(t_us, EV_ARMED if now_armed else EV_DISARMED))
                if not now_armed and self._settings["LOG_FILE_DSRMROT"]:
                    self._rotate_pending = True
        landed = v.landed
        if landed != self._landed:
            self._landed = landed
            if armed or not landed:
                self._queue(FORMATS["EV"].pack(t_us, EV_LAND_COMPLETE if landed else EV_NOT_LANDED))
        mode_changed = v.mode_number != self._mode
        if mode_changed:
            self._mode = v.mode_number
        if v.mission_version != self._mission_version:
            self._mission_version = v.mission_version
            self._queue(self._mission_records(t_us))
        logging = self._should_log(now, armed)
        sink = self.sink
        if self._rotate_pending and (not logging or self._settings["LOG_DISARMED"]):
            self._rotate_pending = False
            if sink.open:
                sink.stop()
        if not logging or sink.paused:  # a download pauses logging, as ArduPilot's does
            self._pending.clear()
            self._periodic(t_us, write=False)
            if not logging:  # asleep until something changes (which takes the slow path)
                self._due_s = math.inf
                self.awake = self._rotate_pending
            return
        if not sink.open:
            sink.start()
            sink.write(self._start_records(t_us))  # with the mode
        elif mode_changed:
            self._queue(self._mode_record(t_us))
        if self._pending:
            sink.write(b"".join(self._pending))
            self._pending.clear()
        self._periodic(t_us)

    def _periodic(self, t_us: int, write: bool = True) -> None:
        """The flight data records due at t_us (written only with `write`); sets when the next
        are due."""
        bitmask = self._settings["LOG_BITMASK"]
        v, out, body, due = self.v, [], None, math.inf
        for group in self._groups:
            if t_us >= group.next_us:
                group.next_us = (t_us // group.every_us + 1) * group.every_us  # on multiples of the period
                if write:
                    body = body or v.body
                    for fmt, p in group.members:
                        if (p.mask and not bitmask & p.mask) or (p.when is not None and not p.when(v)):
                            continue
                        if p.instances == 1:
                            out.append(fmt.pack(t_us, *p.build(v, body)))
                        else:  # the same values for each instance: packed once, the number patched
                            record = fmt.pack(t_us, 0, *p.build(v, body))
                            out.append(record)
                            out.extend(record[:INSTANCE_AT] + bytes((i,)) + record[INSTANCE_AT + 1:]
                                       for i in range(1, p.instances))
            due = min(due, group.next_us)
        self._due_s = due / 1e6 - 1e-9
        if out:
            self.records += len(out)
            self.sink.write(b"".join(out))

    # ----- what decides -----------------------------------------------------------------------
    def _read_settings(self) -> None:
        params = self.v.params
        self._settings = {name: int(params[name]) for name in LOGGING_PARAMS}

    def _should_log(self, now: float, armed: bool) -> bool:
        s = self._settings
        if not s["LOG_BACKEND_TYPE"] & BACKEND_FILE:
            return False
        if armed or s["LOG_DISARMED"]:
            return True
        changed, failed = self._arm_change_s, self._arm_failure_s
        return ((changed is not None and now - changed < ARM_PERSIST_S)
                or (failed is not None and now - failed < ARM_PERSIST_S))

    def _queue(self, record: bytes) -> None:
        self.awake = True
        if len(self._pending) < MAX_PENDING:
            self._pending.append(record)

    # ----- records ----------------------------------------------------------------------------
    def _parm_record(self, t_us: int, name: str, value: float) -> bytes:
        return self._parm.pack_text(t_us, name[:16], value, self._defaults.get(name, math.nan))

    def _mode_record(self, t_us: int) -> bytes:
        number = self.v.mode_number
        return FORMATS["MODE"].pack(t_us, number, number, MODE_REASON_UNKNOWN)

    def _mission_records(self, t_us: int) -> bytes:
        items = self.v.mission_items()
        cmd = FORMATS["CMD"]
        return b"".join(cmd.pack(t_us, len(items), seq, item.command, item.p1, item.p2, item.p3, item.p4,
                                 item.x, item.y, item.z, item.frame)
                        for seq, item in enumerate(items))

    def _start_records(self, t_us: int) -> bytes:
        params = self.v.params
        parms = [self._parm_record(t_us, name, params[name]) for name in params.names()]
        return b"".join([_header(t_us), *parms, self._mode_record(t_us), self._mission_records(t_us)])


__all__ = ["Recorder", "LogSink", "MESSAGES"]

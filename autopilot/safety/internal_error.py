"""Internal errors: a bug that raised inside the vehicle loop, handled as ArduPilot handles its own.

ArduPilot keeps a bitmask of internal error kinds (AP_InternalError) and a count, reports them in
SYS_STATUS (errors_count1/2: the mask's low and high halves, errors_count4: the count), marks the
HEARTBEAT's system_status CRITICAL, says "Internal Errors 0x<mask>" when the mask changes, and
refuses to arm with "Internal errors 0x<mask> l:<line> <names>" — and keeps flying. Firefly
records an exception the same way, under the kind flow_of_control (ArduPilot's "we should never
get here"), with the line of the Python code that raised as the line.

Nothing here raises: recording an error must never be a second error.
"""
from __future__ import annotations

from collections.abc import Callable

FLOW_OF_CONTROL = 1 << 20  # AP_InternalError::error_t::flow_of_control
CONSTRAINING_NAN = 1 << 10  # AP_InternalError::error_t::constraining_nan: a NaN a limit was applied to
REPORT_FIRST = 5  # errors passed to `report` (a process prints them); the rest are only counted
BIT_NAMES = {CONSTRAINING_NAN: "cnstring_nan", FLOW_OF_CONTROL: "flow_of_ctrl"}  # as AP_InternalError::errors_as_string names them


class InternalErrors:
    """What has gone wrong inside this vehicle since boot: ArduPilot's mask, count and last line,
    and (for the exit report and a failing test) the last exception in words."""

    def __init__(self) -> None:
        self.bits = 0
        self.count = 0
        self.flagged = 0  # ArduPilot's own errors on bad input (flag), counted apart from the bugs
        self.line = 0
        self.last = ""  # "where: ExceptionType: message (file:line)"
        self.report: Callable[[str], None] | None = None  # told of the first REPORT_FIRST errors

    def __bool__(self) -> bool:
        return self.bits != 0

    def record(self, exc: BaseException, where: str, bit: int = FLOW_OF_CONTROL) -> bool:
        """Count `exc`, raised in `where`; True the first time this kind of error is seen."""
        new = not self.bits & bit
        self.bits |= bit
        self.count += 1
        tb = exc.__traceback__
        while tb is not None and tb.tb_next is not None:  # the innermost frame: where it raised
            tb = tb.tb_next
        self.line = tb.tb_lineno if tb is not None else 0
        place = f" ({tb.tb_frame.f_code.co_filename.rsplit('/', 1)[-1]}:{tb.tb_lineno})" if tb is not None else ""
        self.last = f"{where}: {type(exc).__name__}: {exc}{place}"
        if self.report is not None and self.count <= REPORT_FIRST:
            try:
                self.report(self.last)
            except Exception:  # noqa: BLE001 - reporting must never be a second error
                pass
        return new

    def flag(self, bit: int, line: int = 0, where: str = "") -> bool:
        """An error ArduPilot itself detects, with no exception here (CONSTRAINING_NAN: a client's
        NaN it limits; flow_of_control: a landed vehicle climbing with no takeoff), at ArduPilot's
        source `line` when known; reported as it reports one, but not a Firefly bug, so counted in
        `flagged`, not in `count` (which the tests require to stay 0). True the first time this
        kind is seen."""
        new = not self.bits & bit
        self.bits |= bit
        self.flagged += 1
        if line:
            self.line = line
        if where:
            self.last = where
        return new

    def names(self) -> str:
        return ",".join(name for bit, name in BIT_NAMES.items() if self.bits & bit)

    def announcement(self) -> str:
        """What ArduPilot says (CRITICAL) when its mask changes (AP_Vehicle; measured on
        ArduCopter SITL: "Internal Errors 0x400")."""
        return f"Internal Errors 0x{self.bits:x}"

    def prearm_text(self) -> str | None:
        """The pre-arm failure ArduPilot reports while any internal error is set, or None."""
        if not self.bits:
            return None
        return f"Internal errors 0x{self.bits:x} l:{self.line} {self.names()}"

    def sys_status_fields(self) -> tuple[int, int, int]:
        """SYS_STATUS's (errors_count1, errors_count2, errors_count4), as ArduPilot fills them."""
        return self.bits & 0xFFFF, (self.bits >> 16) & 0xFFFF, (self.count + self.flagged) & 0xFFFF

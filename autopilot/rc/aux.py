"""The aux functions (RCn_OPTION, MAV_CMD_DO_AUX_FUNCTION), as ArduCopter's RC_Channel_Copter runs
them: one table, a function joins it in one line.

A function gets the vehicle (AuxHost) and the switch position (LOW, MIDDLE, HIGH) and returns
whether it is one ArduCopter knows (False: "Invalid channel option (N)", and the command FAILED).
Mode functions enter their mode at HIGH (a refused mode changes nothing and is still a success,
as ArduCopter's); at LOW or MIDDLE, if the vehicle is in that mode, the flight-mode switch is
read afresh and its mode taken back. `announce` is ArduPilot's text for a switch moved on a
channel ("RC7: SaveWaypoint HIGH"); most functions say nothing.
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

from ..modes.numbers import ModeNumber
from ..results import Result, Severity
from .channels import HIGH, LOW, MIDDLE

if TYPE_CHECKING:
    from ..payload.winch import Winch

POSITION_NAMES = ("LOW", "MIDDLE", "HIGH")


class AuxHost(Protocol):
    """What the aux functions may do to the vehicle."""
    mode_number: int
    armed: bool
    motors_emergency_stopped: bool

    def set_mode(self, number: int) -> Result: ...
    def arm(self, force: bool = False) -> Result: ...
    def disarm(self, reason: str = "", force: bool = False) -> Result: ...
    def pause(self, paused: bool) -> Result: ...
    def notify(self, text: str, severity: int = Severity.INFO) -> None: ...
    def reset_mode_switch(self) -> None: ...
    def zigzag_switch(self, which: str, position: int) -> None: ...
    def rangefinder_switch(self, position: int) -> None: ...
    def avoid_adsb_switch(self, position: int) -> None: ...
    def source_set_switch(self, position: int) -> None: ...
    @property
    def winch(self) -> Winch: ...


@dataclass(frozen=True)
class AuxFunction:
    number: int
    name: str
    run: Callable[[AuxHost, int], None]
    announce: str | None = None  # ArduPilot's words for it when a channel's switch moves
    settle_on_first_read: bool = False  # the position at start-up is taken as is, not acted on


def _mode(number: ModeNumber) -> Callable[[AuxHost, int], None]:
    def change(v: AuxHost, position: int) -> None:
        if position == HIGH:
            v.set_mode(number)
        elif v.mode_number == number:
            v.reset_mode_switch()
    return change


def _flip(v: AuxHost, position: int) -> None:
    if position == HIGH:
        v.set_mode(ModeNumber.FLIP)


def _nothing(v: AuxHost, position: int) -> None:
    """Known to ArduCopter, nothing Firefly's vehicle has to act on (SaveWaypoint: see below)."""


def _motor_estop(v: AuxHost, position: int) -> None:
    if position != MIDDLE:
        v.motors_emergency_stopped = position == HIGH


def _arm_disarm(v: AuxHost, position: int) -> None:
    if position == HIGH:
        v.arm()
    elif position == LOW:
        v.disarm("aux switch", force=False)


def _disarm(v: AuxHost, position: int) -> None:
    if position == HIGH:
        v.disarm("aux switch", force=False)


def _arm_emergency_stop(v: AuxHost, position: int) -> None:
    v.motors_emergency_stopped = position == LOW
    if position == HIGH:
        v.arm()


def _pause(v: AuxHost, position: int) -> None:
    if position == HIGH:
        if v.pause(True) != Result.ACCEPTED:
            v.notify("Flight Mode Pause failed", Severity.WARNING)
    elif position == LOW:
        v.pause(False)


def _zigzag(which: str) -> Callable[[AuxHost, int], None]:
    def run(v: AuxHost, position: int) -> None:
        if v.mode_number == ModeNumber.ZIGZAG:
            v.zigzag_switch(which, position)
    return run


def _winch_enable(v: AuxHost, position: int) -> None:
    """HIGH holds the winch at rate 0 (rate control, the output at trim); LOW and MIDDLE relax it."""
    if position == HIGH:
        v.winch.set_rate(0.0)
    else:
        v.winch.relax()


M = ModeNumber
AUX_FUNCTIONS: dict[int, AuxFunction] = {f.number: f for f in (
    AuxFunction(2, "FLIP", _flip),
    AuxFunction(4, "RTL", _mode(M.RTL)),
    # SaveWaypoint: ArduCopter appends the vehicle's place to the mission; Firefly does not (yet)
    AuxFunction(7, "SAVE_WP", _nothing, announce="SaveWaypoint"),
    AuxFunction(10, "RANGEFINDER", lambda v, position: v.rangefinder_switch(position), announce="Rangefinder"),
    AuxFunction(38, "AVOID_ADSB", lambda v, position: v.avoid_adsb_switch(position)),
    AuxFunction(16, "AUTO", _mode(M.AUTO)),
    AuxFunction(17, "AUTOTUNE", _mode(M.AUTOTUNE)),
    AuxFunction(18, "LAND", _mode(M.LAND)),
    AuxFunction(31, "MOTOR_ESTOP", _motor_estop, announce="MotorEStop"),
    AuxFunction(33, "BRAKE", _mode(M.BRAKE)),
    AuxFunction(37, "THROW", _mode(M.THROW)),
    AuxFunction(42, "SMART_RTL", _mode(M.SMART_RTL)),
    AuxFunction(44, "WINCH_ENABLE", _winch_enable, announce="WinchEnable"),
    # WinchControl: nothing to do on a switch; the winch reads the channel's stick itself (payload/winch.py)
    AuxFunction(45, "WINCH_CONTROL", _nothing, announce="WinchControl"),
    AuxFunction(52, "ACRO", _mode(M.ACRO)),
    AuxFunction(55, "GUIDED", _mode(M.GUIDED)),
    AuxFunction(56, "LOITER", _mode(M.LOITER)),
    AuxFunction(57, "FOLLOW", _mode(M.FOLLOW)),
    AuxFunction(60, "ZIGZAG", _mode(M.ZIGZAG)),
    AuxFunction(61, "ZIGZAG_SaveWP", _zigzag("save_wp")),
    AuxFunction(68, "STABILIZE", _mode(M.STABILIZE)),
    AuxFunction(69, "POSHOLD", _mode(M.POSHOLD)),
    AuxFunction(70, "ALTHOLD", _mode(M.ALT_HOLD)),
    AuxFunction(71, "FLOWHOLD", _mode(M.FLOWHOLD)),
    AuxFunction(72, "CIRCLE", _mode(M.CIRCLE)),
    AuxFunction(73, "DRIFT", _mode(M.DRIFT)),
    AuxFunction(81, "DISARM", _disarm),
    AuxFunction(83, "ZIGZAG_Auto", _zigzag("auto")),
    AuxFunction(90, "EKF_SOURCE_SET", lambda v, position: v.source_set_switch(position)),
    AuxFunction(99, "AUTO_RTL", _mode(M.AUTO_RTL)),
    AuxFunction(151, "TURTLE", _mode(M.TURTLE)),
    AuxFunction(153, "ARMDISARM", _arm_disarm, settle_on_first_read=True),
    AuxFunction(165, "ARM_EMERGENCY_STOP", _arm_emergency_stop, settle_on_first_read=True),
    AuxFunction(178, "FLIGHTMODE_PAUSE", _pause),
)}
# Functions ArduCopter runs for hardware and features Firefly's vehicle does not have (camera,
# relays, gripper, mount, simple modes, ...): known, accepted, nothing moves. Those whose
# missing device ArduCopter reports as a failure are FAILED_WITHOUT_DEVICE.
NOTHING_HERE = (3, 5, 9, 11, 13, 14, 15, 19, 21, 22, 23, 24, 25, 26, 27, 28, 29, 30, 32, 34, 35, 36, 39,
                40, 46, 47, 48, 49, 58, 62, 65, 66, 67, 75, 76, 78, 79, 80, 84, 85, 100, 101,
                102, 103, 104, 105, 106, 109, 110, 111, 112, 113, 152, 154, 158, 159, 160, 162, 163,
                164, 171, 172, 177, 180, 182, *range(212, 220), *range(300, 316))
FAILED_WITHOUT_DEVICE = (166, 167, 168, 169, 174, 175)  # camera functions: no camera
for _n in NOTHING_HERE:
    AUX_FUNCTIONS.setdefault(_n, AuxFunction(_n, f"aux {_n}", _nothing))


def run_aux_function(v: AuxHost, number: int, position: int) -> bool:
    """Run aux function `number` at `position`; False (and ArduPilot's text) for one unknown."""
    if number in FAILED_WITHOUT_DEVICE:
        return False
    function = AUX_FUNCTIONS.get(number)
    if function is None:
        v.notify(f"Invalid channel option ({number})", Severity.INFO)
        return False
    function.run(v, position)
    return True


def announcement(channel: int, number: int, position: int) -> str | None:
    """What ArduPilot says when channel `channel`'s switch moves to `position`, if anything."""
    function = AUX_FUNCTIONS.get(number)
    if function is None or function.announce is None:
        return None
    return f"RC{channel}: {function.announce} {POSITION_NAMES[position]}"

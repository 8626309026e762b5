"""The payload's commands (COMMAND_LONG / COMMAND_INT), as ArduCopter answers them (measured):
DO_PARACHUTE, DO_SPRAYER, DO_GRIPPER, DO_WINCH and DO_MOTOR_TEST. Joined into the command table (commands.HANDLERS) as **HANDLERS."""
from __future__ import annotations

from ..c_casts import as_uint8, as_uint16, param5_int
from ..results import Result
from .dialect import mavlink as mav


def do_parachute(s, c) -> Result:
    """Param 1, cut to a uint16: 0 disable, 1 enable, 2 release (refused in words on the ground and
    below CHUTE_ALT_MIN, still ACCEPTED; accepted and ignored while disabled); else FAILED."""
    return s.vehicle.parachute_action(as_uint16(c.p1))


def do_gripper(s, c) -> Result:
    """Param 1 the gripper (one: ignored), param 2 the action cut to a uint8: 0 release, 1 grab."""
    return s.vehicle.gripper_action(as_uint16(c.p2) & 0xFF)


def do_winch(s, c) -> Result:
    """Param 1 the winch (one: ignored), 2 the action cut to a uint8 (0 relax, 1 length, 2 rate),
    3 the length to let out [m], 4 the rate [m/s] (payload/winch.py)."""
    return s.vehicle.winch_action(as_uint8(c.p2), c.p3, c.p4)


def do_sprayer(s, c) -> Result:
    """Param 1: exactly 1 on, exactly 0 off, anything else nothing; always ACCEPTED."""
    if c.p1 == 1.0:
        s.vehicle.run_sprayer(True)
    elif c.p1 == 0.0:
        s.vehicle.run_sprayer(False)
    return Result.ACCEPTED


def do_motor_test(s, c) -> Result:
    """Param 1 the motor's place in the test order, 2 the throttle's type, 3 its value, 4 the
    timeout [s], 5 (x) how many motors in turn; param 6, the order, is not read (motor_test.py)."""
    return s.vehicle.start_motor_test(as_uint16(c.p1) & 0xFF, as_uint16(c.p2) & 0xFF, c.p3, c.p4,
                                        param5_int(c.p5, c.is_int) & 0xFF)


HANDLERS = {
    mav.MAV_CMD_DO_MOTOR_TEST: do_motor_test,
    mav.MAV_CMD_DO_PARACHUTE: do_parachute,
    mav.MAV_CMD_DO_SPRAYER: do_sprayer,
    mav.MAV_CMD_DO_GRIPPER: do_gripper,
    mav.MAV_CMD_DO_WINCH: do_winch,
}

"""ArduCopter's flight-mode numbers (HEARTBEAT custom_mode, DO_SET_MODE, SET_MODE): the one table.

Only the modes Firefly flies are listed; any other number is refused as an unknown mode."""
from enum import IntEnum


class ModeNumber(IntEnum):
    STABILIZE = 0
    ALT_HOLD = 2
    AUTO = 3
    GUIDED = 4
    LOITER = 5
    RTL = 6
    LAND = 9
    POSHOLD = 16
    BRAKE = 17
    GUIDED_NOGPS = 20

"""ArduCopter's flight-mode numbers (HEARTBEAT custom_mode, DO_SET_MODE, SET_MODE): the one table.

Only the modes Firefly flies are listed; any other number is refused as an unknown mode."""
from enum import IntEnum


class ModeNumber(IntEnum):
    STABILIZE = 0
    ACRO = 1
    ALT_HOLD = 2
    AUTO = 3
    GUIDED = 4
    LOITER = 5
    RTL = 6
    CIRCLE = 7
    LAND = 9
    DRIFT = 11
    FLIP = 14
    AUTOTUNE = 15
    POSHOLD = 16
    BRAKE = 17
    THROW = 18
    AVOID_ADSB = 19
    GUIDED_NOGPS = 20
    SMART_RTL = 21
    FLOWHOLD = 22
    FOLLOW = 23
    ZIGZAG = 24
    SYSTEMID = 25
    AUTO_RTL = 27
    TURTLE = 28

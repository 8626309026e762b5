"""Outcomes of vehicle commands. Values equal MAVLink's MAV_RESULT so the wire layer maps 1:1."""
from enum import IntEnum


class Result(IntEnum):
    ACCEPTED = 0
    TEMPORARILY_REJECTED = 1
    DENIED = 2
    UNSUPPORTED = 3
    FAILED = 4
    IN_PROGRESS = 5


class Severity(IntEnum):
    """Same numbers as MAV_SEVERITY."""
    EMERGENCY = 0
    ALERT = 1
    CRITICAL = 2
    ERROR = 3
    WARNING = 4
    NOTICE = 5
    INFO = 6
    DEBUG = 7

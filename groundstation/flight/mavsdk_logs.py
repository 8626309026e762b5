"""MAVSDK's own log lines, kept to warnings and errors: its debug and info lines would drown the
progress output of the commands and of a campaign's workers."""
from __future__ import annotations


def quiet_mavsdk_logs() -> None:
    from mavsdk import LogLevel, log_subscribe
    log_subscribe(lambda level, message, file, line: level < LogLevel.WARN)

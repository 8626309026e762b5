"""The host's machine id, which ArduPilot's SITL makes its board id from (autopilot/version.py):
read here, at the I/O edge, once per vehicle built."""
from __future__ import annotations

from pathlib import Path

MACHINE_ID_FILES = (Path("/etc/machine-id"), Path("/var/lib/dbus/machine-id"))  # where SITL looks, in order
MACHINE_ID_MAX_CHARS = 39  # SITL reads 40 bytes into a string


def read_machine_id() -> str | None:
    """The first line of the first machine-id file that has one, or None."""
    for path in MACHINE_ID_FILES:
        try:
            text = path.read_text(errors="replace")[:MACHINE_ID_MAX_CHARS]
        except OSError:
            continue
        line = text.split("\n", 1)[0]
        if line:
            return line
    return None

"""The directories MAVLink FTP serves besides `@PARAM`, sans-IO: the root as ArduCopter SITL lists
it (".", "logs", "..", "terrain", "@ROMFS", "@SYS", measured; "logs" once a log has been
written, as the reference's directory appears with its first log), `logs/` with the vehicle's
dataflash logs (read through the store the I/O edge injects), and `terrain`, `@ROMFS` and `@SYS`,
which hold nothing Firefly can serve (ArduPilot's @SYS texts describe its threads and UARTs, and
its ROMFS its build): terrain lists only "." and "..", the other two nothing.

Entries are ArduPilot's: "D<name>" for a directory, "F<name>\\t<size>" for a file.
"""
from __future__ import annotations

from typing import Protocol

from .param_files import ENOENT, FsError

ENOTDIR = 20
ROOT = ("D.", "Dlogs", "D..", "Dterrain", "D@ROMFS", "D@SYS")
LOGS_ENTRY = 1
EMPTY_DIRS = {"terrain": ("D.", "D.."), "@ROMFS": (), "@SYS": ()}


class LogDirectory(Protocol):
    @property
    def exists(self) -> bool: ...
    def listing(self) -> list[tuple[str, int]]: ...
    def open_file(self, name: str): ...


def _parts(path: str) -> list[str]:
    return [p for p in path.split("/") if p]


def is_tree_path(path: str) -> bool:
    """Whether `path` lies in one of these directories (else it is @PARAM's, or nothing)."""
    parts = _parts(path)
    return not parts or parts[0] == "logs" or parts[0] in EMPTY_DIRS


class FtpTree:
    def __init__(self, logs: LogDirectory | None = None):
        self.logs = logs

    def list(self, path: str) -> tuple[str, ...]:
        """The entries of directory `path`; raises FsError (ENOENT, ENOTDIR) when it is none."""
        parts = _parts(path)
        if not parts:
            if self.logs is not None and self.logs.exists:
                return ROOT
            return ROOT[:LOGS_ENTRY] + ROOT[LOGS_ENTRY + 1:]
        if len(parts) == 1 and parts[0] in EMPTY_DIRS:
            return EMPTY_DIRS[parts[0]]
        if parts[0] != "logs" or self.logs is None or not self.logs.exists:
            raise FsError(ENOENT)
        files = self.logs.listing()
        if len(parts) == 1:
            return ("D.", "D..", *(f"F{name}\t{size}" for name, size in files))
        if len(parts) == 2 and any(name == parts[1] for name, _ in files):
            raise FsError(ENOTDIR)
        raise FsError(ENOENT)

    def open(self, path: str):
        """A reader (size_estimate, read(offset, length)) of the file at `path`; raises FsError."""
        parts = _parts(path)
        if len(parts) != 2 or parts[0] != "logs" or self.logs is None:
            raise FsError(ENOENT)
        return self.logs.open_file(parts[1])

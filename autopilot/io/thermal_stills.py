"""The thermal camera's card copied to disk, one TIFF per still, in the vehicle's state directory
(`thermal/`): a user finds the stills there after a run, besides downloading them by MAVLink FTP.
Formatting the card empties the directory. A file that cannot be written is counted and
skipped: the still stays on the card, and the vehicle flies on."""
from __future__ import annotations

from pathlib import Path


class ThermalStills:
    def __init__(self, directory: Path):
        self.directory = directory
        self.failed = 0

    def write(self, still) -> None:
        try:
            self.directory.mkdir(parents=True, exist_ok=True)
            (self.directory / still.name).write_bytes(still.data)
        except OSError:
            self.failed += 1

    def clear(self) -> None:
        for path in self.directory.glob("IR_*.tif"):
            try:
                path.unlink()
            except OSError:
                self.failed += 1

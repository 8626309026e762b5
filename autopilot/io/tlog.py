"""Telemetry log (.tlog): every MAVLink frame sent and received, each preceded by its time as a
big-endian 64-bit count of microseconds since the UNIX epoch — the format pymavlink, MAVExplorer
and MAVProxy read. Flushed to disk at least once a second (of wall time), so a crash loses at
most the last second."""
from __future__ import annotations

import os
import struct
import time
from pathlib import Path

FLUSH_INTERVAL_S = 1.0


class TlogWriter:
    def __init__(self, path: Path):
        path.parent.mkdir(parents=True, exist_ok=True)
        self._file = open(path, "ab", buffering=1 << 16)
        self._last_flush = time.monotonic()
        self.frames = 0

    def write(self, time_us: int, frame: bytes) -> None:
        self._file.write(struct.pack(">Q", time_us) + frame)
        self.frames += 1

    def maybe_flush(self) -> None:
        now = time.monotonic()
        if now - self._last_flush >= FLUSH_INTERVAL_S:
            self.flush()
            self._last_flush = now

    def flush(self) -> None:
        self._file.flush()
        os.fsync(self._file.fileno())

    def close(self) -> None:
        self.flush()
        self._file.close()

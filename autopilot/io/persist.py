"""Atomic JSON files: write to a temporary file, fsync, rename. A crash at any instant leaves
either the previous or the new version, never a torn file."""
from __future__ import annotations

import json
import math
import os
import tempfile
from collections.abc import Callable
from pathlib import Path


def write_json_atomic(path: Path, data) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}-")
    try:
        with os.fdopen(fd, "w") as f:
            json.dump(data, f, indent=1, sort_keys=True)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
        _fsync_dir(path.parent)  # the rename itself reaches the disk, not only the data
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


class JsonFile:
    """How every store (parameters, missions, fence and rally) writes its file.

    - Atomically (write_json_atomic).
    - A disk that refuses (full, read-only, its directory gone): the error is counted and kept for
      the exit report, the change still takes effect in flight, and the caller learns it failed
      (a mission transfer then answers MAV_MISSION_ERROR, as ArduPilot does when its storage
      refuses a write).
    - At most once per `min_interval_s` of link time, which the I/O edge sets (0: every change at
      once, as in the unit tests): a change within it is written at the first poll after it, so
      a flood of PARAM_SETs costs two writes a second, not one each (as ArduPilot's storage
      writes behind the changes); the first change after a quiet spell is written at once, and
      the exit flushes what is left.
    """

    def __init__(self, path: Path | None) -> None:
        self.path = path
        self.save_errors = 0
        self.last_save_error = ""
        self.min_interval_s = 0.0
        # the link clock (wall seconds), injected by the I/O edge with min_interval_s
        self.clock: Callable[[], float] | None = None
        self._written_s = -math.inf
        self._pending: Callable[[], object] | None = None  # the data still to write
        # the files with a write waiting, shared with whoever polls (the vehicle's stores_waiting)
        self.waiting: set = set()

    @property
    def pending(self) -> bool:
        return self._pending is not None

    def save(self, data: Callable[[], object]) -> bool:
        """Write data() now (whether the disk took it), or after the interval (True)."""
        if self.path is None:
            return True
        now = self.clock() if self.clock is not None else 0.0
        if now - self._written_s < self.min_interval_s:
            self._pending = data
            self.waiting.add(self)
            return True
        return self._write(data, now)

    def poll(self, now_s: float) -> None:
        if self._pending is not None and now_s - self._written_s >= self.min_interval_s:
            self._write(self._pending, now_s)

    def flush(self) -> None:
        if self._pending is not None:
            self._write(self._pending, self._written_s)

    def _write(self, data: Callable[[], object], now_s: float) -> bool:
        self._pending = None
        self.waiting.discard(self)
        self._written_s = now_s
        assert self.path is not None
        try:
            write_json_atomic(self.path, data())
        except OSError as exc:
            self.save_errors += 1
            self.last_save_error = f"{self.path}: {exc.strerror or exc}"
            return False
        return True


def _fsync_dir(directory: Path) -> None:
    fd = os.open(directory, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def remove_stale_temporaries(path: Path) -> int:
    """Temporary files a killed writer left beside `path` (never the file itself); how many."""
    removed = 0
    for stale in path.parent.glob(f".{path.name}-*"):
        stale.unlink(missing_ok=True)
        removed += 1
    return removed


def read_json(path: Path):
    """The file's JSON, or None when it is missing or unreadable. Read at start-up, so it first
    removes the temporaries a killed writer may have left beside the file."""
    remove_stale_temporaries(path)
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError):
        return None

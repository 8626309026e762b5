"""Atomic JSON files: write to a temporary file, fsync, rename. A crash at any instant leaves
either the previous or the new version, never a torn file."""
from __future__ import annotations

import json
import os
import tempfile
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


class SaveErrors:
    """How every store (parameters, missions, fence and rally) meets a disk that refuses a save
    (full, read-only, its directory gone): the error is counted and kept for the exit report, the
    change still takes effect in flight, and the caller learns it failed (a mission transfer then
    answers MAV_MISSION_ERROR, as ArduPilot does when its storage refuses a write)."""

    def __init__(self) -> None:
        self.save_errors = 0
        self.last_save_error = ""

    def save_json(self, path: Path, data) -> bool:
        try:
            write_json_atomic(path, data)
        except OSError as exc:
            self.save_errors += 1
            self.last_save_error = f"{path}: {exc.strerror or exc}"
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

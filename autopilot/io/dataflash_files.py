"""The dataflash log files of one vehicle: `logs/` in its state directory, as ArduPilot's file
backend keeps them (AP_Logger_File).

- Logs are 00000001.BIN, 00000002.BIN, ...; LASTLOG.TXT holds the number of the latest ("N\\r\\n").
  A new log takes the next number (re-using the latest if it is empty); after LOG_MAX_FILES the
  numbering starts again at 1 and the oldest file is overwritten (truncated).
- Writes are buffered and reach the file in big chunks: when BUFFER_BYTES are waiting and at
  least every FLUSH_EVERY_S of wall time (maybe_flush, from the loop), and when the log stops.
- Reading a log for download (LOG_REQUEST_DATA) first stops the log being written, as ArduPilot's
  does; the recorder then starts a new one if it goes on logging.
- The listing ArduPilot serves: `count()` is LASTLOG's number (plus the wrapped logs above it),
  and list entry k is log number oldest + k - 1 (wrapping at LOG_MAX_FILES), so after an erase or
  with gaps an entry may name no file (size and time 0).
- erase() removes every log and LASTLOG.TXT; numbering restarts at 1.
"""
from __future__ import annotations

import errno
import os
import re
import time
from pathlib import Path
from typing import IO, Any

from ..mavlink.param_files import FsError

BUFFER_BYTES = 1 << 16
FLUSH_EVERY_S = 1.0
LOG_NAME = re.compile(r"^(\d{8})\.BIN$")


class LogFiles:
    def __init__(self, directory: Path, params):
        self.directory = directory
        self.params = params
        self._file: Any = None  # the log being written (an open file, or _Discard after a failed open)
        self._number = 0  # the log being written
        self._buffer: list[bytes] = []
        self._buffered = 0
        self._written = 0  # bytes of the current log already in the file
        self._last_flush = time.monotonic()
        self._reader: tuple[int, IO[bytes]] | None = None  # (number, open file) of the log downloaded
        self.write_errors = 0
        self.last_error = ""

    # ----- the sink the recorder writes to ------------------------------------------------------
    @property
    def open(self) -> bool:
        return self._file is not None

    @property
    def paused(self) -> bool:
        """A log is being downloaded: ArduPilot's file backend writes nothing meanwhile."""
        return self._reader is not None

    def start(self) -> None:
        self.stop()
        self.end_transfer()
        number = self.last_log()
        if number == 0 or self._size_on_disk(number) > 0:
            number += 1
        if number > self.max_logs:
            number = 1
        try:
            self.directory.mkdir(parents=True, exist_ok=True)
            self._file = open(self.path(number), "wb")
            (self.directory / "LASTLOG.TXT").write_bytes(f"{number}\r\n".encode())
        except OSError as exc:
            self._failed(exc)
            if self._file is not None:
                self._file.close()
                self._file = None
            # nothing opened: the recorder's writes go nowhere until the next start
            self._file = _Discard()
        self._number, self._written = number, 0
        self._last_flush = time.monotonic()

    def write(self, data: bytes) -> None:
        self._buffer.append(data)
        self._buffered += len(data)
        if self._buffered >= BUFFER_BYTES:
            self.flush()

    def stop(self) -> None:
        if self._file is None:
            return
        self.flush()
        self._file.close()
        self._file, self._number = None, 0

    def flush(self) -> None:
        if not self._buffer or self._file is None:
            return
        data = b"".join(self._buffer)
        self._buffer.clear()
        self._buffered = 0
        try:
            self._file.write(data)
            self._file.flush()
            self._written += len(data)
        except OSError as exc:
            self._failed(exc)

    def maybe_flush(self) -> None:
        """Called from the loop: the buffer reaches the file at least every FLUSH_EVERY_S."""
        if self._buffered:
            now = time.monotonic()
            if now - self._last_flush >= FLUSH_EVERY_S:
                self._last_flush = now
                self.flush()

    def _failed(self, exc: OSError) -> None:
        self.write_errors += 1
        self.last_error = f"{self.directory}: {exc.strerror or exc}"

    # ----- numbering ----------------------------------------------------------------------------
    @property
    def max_logs(self) -> int:
        return max(1, int(self.params["LOG_MAX_FILES"]))

    def path(self, number: int) -> Path:
        return self.directory / f"{number:08d}.BIN"

    def last_log(self) -> int:
        try:
            text = (self.directory / "LASTLOG.TXT").read_text()
        except (OSError, ValueError):
            return 0
        digits = re.match(r"\s*(\d+)", text)
        return int(digits.group(1)) if digits else 0

    def numbers(self) -> list[int]:
        try:
            names = os.listdir(self.directory)
        except OSError:
            return []
        found = (LOG_NAME.match(name) for name in names)
        return sorted(n for n in (int(m.group(1)) for m in found if m) if 0 < n <= self.max_logs)

    def _size_on_disk(self, number: int) -> int:
        try:
            return self.path(number).stat().st_size
        except OSError:
            return 0

    # ----- the store LOG_REQUEST_* and FTP read -------------------------------------------------
    def count(self) -> int:
        """ArduPilot's get_num_logs: the latest number, plus the logs above it after a wrap."""
        last = self.last_log()
        above = [n for n in self.numbers() if n > last]
        return last + (self.max_logs - min(above) + 1 if above else 0)

    def _oldest(self) -> int:
        last = self.last_log()
        numbers = self.numbers()
        if last == 0 or not numbers:
            return 0
        above = [n for n in numbers if n > last]
        return min(above) if above else min(numbers)

    def number_of(self, entry: int) -> int:
        """The log number of list entry `entry` (1-based), or 0."""
        oldest = self._oldest()
        if oldest == 0 or entry < 1:
            return 0
        number = oldest + entry - 1
        return number - self.max_logs if number > self.max_logs else number

    def info(self, entry: int) -> tuple[int, int]:
        """(size in bytes, UTC seconds of its last write) of list entry `entry`; (0, 0) if none."""
        number = self.number_of(entry)
        if number == 0:
            return 0, 0
        if number == self._number and self._file is not None:
            return self._written + self._buffered, int(time.time())
        try:
            st = self.path(number).stat()
        except OSError:
            return 0, 0
        return st.st_size, int(st.st_mtime)

    def read(self, entry: int, offset: int, length: int) -> bytes | None:
        """Bytes of list entry `entry` from `offset`; None when it cannot be read. Reading the
        log being written stops it first, as ArduPilot does; the file stays open for the next
        read until end_transfer()."""
        number = self.number_of(entry)
        if number == 0:
            return None
        if self._file is not None:
            self.stop()
        if self._reader is None or self._reader[0] != number:
            self.end_transfer()
            try:
                self._reader = (number, open(self.path(number), "rb"))
            except OSError:
                return None
        try:
            reader = self._reader[1]
            reader.seek(offset)
            return reader.read(length)
        except (OSError, OverflowError, ValueError):
            self.end_transfer()
            return None

    def end_transfer(self) -> None:
        if self._reader is not None:
            self._reader[1].close()
            self._reader = None

    def erase(self) -> None:
        self.stop()
        self.end_transfer()
        for number in self.numbers():
            self.path(number).unlink(missing_ok=True)
        (self.directory / "LASTLOG.TXT").unlink(missing_ok=True)

    # ----- FTP: the `logs` directory --------------------------------------------------------------
    @property
    def exists(self) -> bool:
        return self.directory.is_dir()

    def listing(self) -> list[tuple[str, int]]:
        """(name, size) of each file in logs/, the one being written with what it holds."""
        self.flush()
        try:
            names = sorted(os.listdir(self.directory))
        except OSError:
            return []
        out = []
        for name in names:
            try:
                st = (self.directory / name).stat()
            except OSError:
                continue
            if not name.startswith(".") and os.path.isfile(self.directory / name):
                out.append((name, st.st_size))
        return out

    def open_file(self, name: str) -> LogFileReader:
        """A file of logs/ for reading by FTP; raises FsError (with its errno)."""
        if "/" in name or name in ("", ".", ".."):
            raise FsError(errno.ENOENT)
        path = self.directory / name
        if self._number and path == self.path(self._number):
            self.flush()
        try:
            return LogFileReader(open(path, "rb"))
        except OSError as exc:
            raise FsError(exc.errno or errno.EIO) from None


class LogFileReader:
    """A file as FTP reads it: its size at the open, and reads by offset from the open file
    (closed when the reader is dropped, as CPython does at once)."""

    def __init__(self, file: IO[bytes]):
        self.file = file
        self.size_estimate = os.fstat(file.fileno()).st_size

    def read(self, offset: int, length: int) -> bytes:
        try:
            self.file.seek(offset)
            return self.file.read(length)
        except (OSError, OverflowError, ValueError) as exc:
            raise FsError(getattr(exc, "errno", None) or errno.EIO) from None

    def __del__(self) -> None:
        self.file.close()


class _Discard:
    """The file that could not be opened: writes go nowhere (counted in write_errors)."""

    def write(self, data: bytes) -> int:
        return len(data)

    def flush(self) -> None:
        pass

    def close(self) -> None:
        pass

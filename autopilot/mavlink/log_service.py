"""Log download over MAVLink (LOG_REQUEST_LIST / LOG_ENTRY, LOG_REQUEST_DATA / LOG_DATA,
LOG_ERASE, LOG_REQUEST_END), sans-IO, answering as ArduCopter's AP_Logger does (measured on
ArduCopter 4.7 SITL, and its AP_Logger_MAVLinkLogTransfer):

- While armed every request is ignored; the first after arming (or after a request was last
  served disarmed) gets "Disarm for log download" (severity ERROR).
- LOG_REQUEST_LIST: entries `start`..min(`end`, num_logs), `start` raised to 1; with no logs a
  single entry id 0 (num_logs 0). last_log_num is the last entry listed. A list whose start lies
  past its end counts up until it wraps round to it, as ArduPilot's does. Entries leave
  LIST_PER_POLL a loop tick (ArduCopter SITL sent some 1,300 a second).
- LOG_REQUEST_DATA: LOG_DATA in 90-byte chunks from `ofs`, `count` bytes at most, up to the log's
  end; the transfer ends with a short chunk (0 bytes past the end: an offset beyond the log gets
  one LOG_DATA of count 0). An id that names no log (0, or above num_logs) ends any transfer and
  is not answered. DATA_PER_POLL chunks leave a loop tick (ArduCopter SITL: 40 per update).
- A request while a transfer is under way: a list gets "Log download in progress" (INFO) and
  is dropped; a data request is dropped in silence (MAVProxy re-requests gaps while one runs).
- LOG_ERASE removes every log; LOG_REQUEST_END ends the transfer.

The store (the vehicle's log files) is injected by the I/O edge (autopilot/io/dataflash_files.py);
without one the vehicle has no logs.
"""
from __future__ import annotations

from typing import Protocol

from ..results import Severity

CHUNK = 90  # LOG_DATA's data field
LIST_PER_POLL = 13
DATA_PER_POLL = 40
IDLE, LISTING, SENDING = 0, 1, 2


class LogStore(Protocol):
    def count(self) -> int: ...
    def info(self, entry: int) -> tuple[int, int]: ...
    def read(self, entry: int, offset: int, length: int) -> bytes | None: ...
    def end_transfer(self) -> None: ...
    def erase(self) -> None: ...


class LogService:
    def __init__(self, vehicle, codec, store: LogStore | None = None):
        """`vehicle`: what tells whether it is armed; `codec`: pymavlink's encoder."""
        self.vehicle = vehicle
        self.codec = codec
        self.store = store
        self.activity = IDLE  # IDLE is 0: `if service.activity` asks whether it is busy, as cheaply as can be
        self._warned_armed = False
        self._num_logs = 0
        self._next_entry = self._last_entry = 0
        self._data_id = 0
        self._offset = self._remaining = 0

    # ----- requests ---------------------------------------------------------------------------
    def handle(self, msg) -> list:
        if self.vehicle.armed:
            if self._warned_armed:
                return []
            self._warned_armed = True
            return [self._text(Severity.ERROR, "Disarm for log download")]
        self._warned_armed = False
        kind = msg.get_type()
        if kind == "LOG_REQUEST_LIST":
            return self._request_list(msg)
        if kind == "LOG_REQUEST_DATA":
            return self._request_data(msg)
        if kind == "LOG_ERASE":
            if self.store is not None:
                self.store.erase()
            return []
        self._end()  # LOG_REQUEST_END
        return []

    def _request_list(self, msg) -> list:
        if self.activity != IDLE:
            return [self._text(Severity.INFO, "Log download in progress")]
        self._num_logs = self.store.count() if self.store is not None else 0
        if self._num_logs == 0:
            self._next_entry = self._last_entry = 0
        else:
            self._next_entry = max(1, msg.start)
            self._last_entry = min(msg.end, self._num_logs)
        self.activity = LISTING
        return self._list(1)

    def _request_data(self, msg) -> list:
        if self.activity != IDLE:
            return []
        num_logs = self.store.count() if self.store is not None else 0
        if not 1 <= msg.id <= num_logs:
            self._end()
            return []
        assert self.store is not None  # num_logs > 0
        size, _ = self.store.info(msg.id)
        self._data_id = msg.id
        self._offset = msg.ofs
        self._remaining = min(0 if msg.ofs >= size else size - msg.ofs, msg.count)
        self.activity = SENDING
        return self._send(DATA_PER_POLL)

    # ----- what is due ------------------------------------------------------------------------
    def poll(self) -> list:
        if self.activity == IDLE or self.vehicle.armed:
            return []
        if self.activity == LISTING:
            return self._list(LIST_PER_POLL)
        return self._send(DATA_PER_POLL)

    def _list(self, most: int) -> list:
        out: list = []
        while self.activity == LISTING and len(out) < most:
            entry = self._next_entry
            size, time_utc = self.store.info(entry) if entry and self.store is not None else (0, 0)
            out.append(self.codec.log_entry_encode(entry, self._num_logs, self._last_entry, time_utc, size))
            if entry == self._last_entry:
                self.activity = IDLE
            else:
                self._next_entry = (entry + 1) & 0xFFFF
        return out

    def _send(self, most: int) -> list:
        out: list = []
        while self.activity == SENDING and len(out) < most:
            length = min(self._remaining, CHUNK)
            data = self.store.read(self._data_id, self._offset, length) if self.store is not None else None
            data = data or b""
            out.append(self.codec.log_data_encode(self._data_id, self._offset & 0xFFFFFFFF, len(data),
                                                  list(data.ljust(CHUNK, b"\0"))))
            self._offset += len(data)
            self._remaining -= len(data)
            if len(data) < CHUNK or self._remaining == 0:
                self._end()
        return out

    def _end(self) -> None:
        self.activity = IDLE
        if self.store is not None:
            self.store.end_transfer()

    def _text(self, severity: int, text: str):
        return self.codec.statustext_encode(severity, text.encode())

"""Where the vehicle's camera took its photos: CAMERA_FEEDBACK, which MAVSDK's Python API does not
expose, read by a pymavlink listener of its own on a link the vehicle sends to (an extra `--out`
of an autopilot `groundstation` starts, or a URL the user gives: a MAVProxy output, a SITL port).
It runs in a thread beside the MAVSDK flight and keeps every photo's place and index."""
from __future__ import annotations

import threading

from pymavlink import mavutil

POLL_S = 0.2  # how long a read waits, so that stop() is heard


class CameraFeedbackListener:
    def __init__(self, url: str):
        self.url = url
        self.photos: list[tuple[float, float, int]] = []  # (lat, lon, image index)
        self._stop = threading.Event()
        self._conn = mavutil.mavlink_connection(url, source_system=255, source_component=191)
        self._thread = threading.Thread(target=self._listen, name="camera-feedback", daemon=True)

    def start(self) -> None:
        self._thread.start()

    def stop(self) -> None:
        self._stop.set()
        if self._thread.is_alive():
            self._thread.join(timeout=5 * POLL_S)
        self._conn.close()

    def _listen(self) -> None:
        while not self._stop.is_set():
            try:
                msg = self._conn.recv_match(type="CAMERA_FEEDBACK", blocking=True, timeout=POLL_S)
            except (OSError, ValueError):  # the socket closed under us, or a mangled datagram
                continue
            if msg is not None:
                self.photos.append((msg.lat * 1e-7, msg.lng * 1e-7, msg.img_idx))

"""The thermal camera's own MAVLink FTP server, sans-IO: the card's stills, read-only, as a camera
component serves the files its CAMERA_IMAGE_CAPTURED file_url names (mftp://DCIM/IR_0000.tif,
the path relative to the camera's root). It is ftp.py's server (the same sessions, retries, bursts
and work budget) over a different tree: the root lists "DCIM", DCIM lists the stills with their
sizes; nothing can be written, removed or renamed (a NAK, as for a read-only card)."""
from __future__ import annotations

from dataclasses import replace

from .ftp import FAIL, FtpServer, Packet, _nak
from .param_files import ENOENT, FsError

ROOT = ("D.", "D..", "DDCIM")
DIRECTORY = "DCIM"
ENOTDIR = 20


class StillReader:
    """A still as ftp.py reads a file: its size, and bytes by offset."""

    def __init__(self, data: bytes):
        self.data = data
        self.size_estimate = len(data)

    def read(self, offset: int, length: int) -> bytes:
        return self.data[offset:offset + length]


class CardTree:
    def __init__(self, camera):
        self.camera = camera

    def list(self, path: str) -> tuple[str, ...]:
        parts = [p for p in path.split("/") if p]
        if not parts:
            return ROOT
        if parts == [DIRECTORY]:
            return ("D.", "D..", *(f"F{s.name}\t{len(s.data)}" for s in self.camera.stills if s.ok))
        if len(parts) == 2 and parts[0] == DIRECTORY and self.camera.file(parts[1]) is not None:
            raise FsError(ENOTDIR)
        raise FsError(ENOENT)

    def open(self, path: str) -> StillReader:
        parts = [p for p in path.split("/") if p]
        still = self.camera.file(parts[1]) if len(parts) == 2 and parts[0] == DIRECTORY else None
        if still is None:
            raise FsError(ENOENT)
        return StillReader(still.data)


class CameraFtp(FtpServer):
    def __init__(self, camera):
        super().__init__(params=None, notify=lambda text, severity: None)
        self.tree = CardTree(camera)  # type: ignore[assignment]

    def _open_path(self, path: str):
        return self.tree.open(path)

    def _open_write(self, request: Packet, reply: Packet, sender: tuple) -> Packet:
        return _nak(replace(reply), FAIL)


def file_url(name: str) -> str:
    return f"mftp://{DIRECTORY}/{name}"

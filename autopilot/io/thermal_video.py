"""The thermal video on the wire: each frame the camera makes (payload/thermal_video.py) encoded as
H.264 (PyAV's libx264) in an MPEG transport stream, sent by UDP to one address, 7 transport packets
(1316 bytes) per datagram as ffmpeg and GStreamer send MPEG-TS. MPEG-TS rather than RTP: it carries
its own description (codec, size, the H.264 parameter sets at each key frame), so a reader opens it
with nothing but the address (`av.open("udp://127.0.0.1:5600")`, OpenCV, ffplay), while RTP needs an
SDP file first. A key frame every second of vehicle time lets a reader that joins late start soon.

Timestamps are vehicle time (frame k at k / fps); when the vehicle's clock starts again (a reboot)
a new stream begins. Never down: an encoder error is counted and the encoder opened again at the
next frame; a datagram the socket refuses (no route, a full buffer) is counted and dropped.
"""
from __future__ import annotations

import io
import socket
from fractions import Fraction
from typing import Any

import numpy as np

TS_PACKET = 188
DATAGRAM = 7 * TS_PACKET


class _Collected(io.RawIOBase):
    """Where the muxer writes: the bytes wait here until the frame's datagrams go out."""

    def __init__(self) -> None:
        self.data = bytearray()

    def writable(self) -> bool:
        return True

    def write(self, b) -> int:
        self.data += b
        return len(b)

    def take(self) -> bytes:
        data, self.data = bytes(self.data), bytearray()
        return data


class VideoSender:
    def __init__(self, address: tuple[str, int], width: int, height: int, fps: float, bit_rate: int):
        self.address = address
        self.width, self.height = width, height
        self.rate = Fraction(fps).limit_denominator(1000)
        self.bit_rate = bit_rate
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.setblocking(False)
        self.counters = {"frames": 0, "encoder_errors": 0, "datagrams": 0, "send_errors": 0, "streams": 0}
        self.last_error = ""
        self._out = _Collected()
        self._container: Any = None  # av's OutputContainer and VideoStream, once opened
        self._stream: Any = None
        self._last_index = -1

    def _open(self) -> None:
        import av  # the encoder: only a vehicle with the thermal camera's video needs it
        self._close()
        self._out = _Collected()
        container = av.open(self._out, mode="w", format="mpegts", container_options={"flush_packets": "1"})
        stream = container.add_stream("libx264", rate=self.rate)
        stream.width, stream.height, stream.pix_fmt = self.width, self.height, "yuv420p"
        stream.bit_rate = self.bit_rate
        stream.codec_context.time_base = 1 / self.rate
        stream.codec_context.gop_size = max(1, round(self.rate))
        stream.options = {"preset": "ultrafast", "tune": "zerolatency"}
        self._container, self._stream = container, stream
        self._last_index = -1
        self.counters["streams"] += 1

    def _close(self) -> None:
        container, self._container, self._stream = self._container, None, None
        if container is not None:
            try:
                container.close()
            except Exception:  # noqa: BLE001 - a broken encoder is dropped whatever it says
                pass

    def frame(self, rgb: np.ndarray, index: int) -> None:
        """Encode frame `index` (an RGB uint8 image) and send what the muxer made of it."""
        import av
        try:
            if self._container is None or index <= self._last_index:  # first, or the clock went back
                self._open()
            assert self._container is not None and self._stream is not None
            picture = av.VideoFrame.from_ndarray(rgb, format="rgb24")
            picture.pts, picture.time_base = index, 1 / self.rate
            for packet in self._stream.encode(picture):
                self._container.mux(packet)
            self._last_index = index
            self.counters["frames"] += 1
        except Exception as exc:  # noqa: BLE001 - never down: counted, and a fresh encoder next frame
            self.counters["encoder_errors"] += 1
            self.last_error = f"{type(exc).__name__}: {exc}"
            self._close()
        self._send(self._out.take())

    def _send(self, data: bytes) -> None:
        for start in range(0, len(data), DATAGRAM):
            try:
                self.sock.sendto(data[start:start + DATAGRAM], self.address)
                self.counters["datagrams"] += 1
            except OSError:
                self.counters["send_errors"] += 1

    def close(self) -> None:
        self._close()
        self._send(self._out.take())
        self.sock.close()

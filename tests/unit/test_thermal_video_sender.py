"""The thermal video's I/O edge (autopilot/io/thermal_video.py) on a real UDP socket: what it sends
is an MPEG-TS of H.264 frames PyAV decodes at their size and timestamps (vehicle time), and it is
never down: a frame the encoder refuses and a datagram the socket refuses are counted, the stream
goes on, and a clock that starts again (a reboot) begins a new stream."""
from __future__ import annotations

import io
import socket

import av
import numpy as np
import pytest

from firefly.autopilot.io.thermal_video import DATAGRAM, TS_PACKET, VideoSender

FPS = 8.7


@pytest.fixture
def receiver():
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.bind(("127.0.0.1", 0))
    sock.settimeout(2.0)
    yield sock
    sock.close()


def received(sock) -> bytes:
    data = bytearray()
    sock.setblocking(False)
    while True:
        try:
            datagram = sock.recv(65536)
        except BlockingIOError:
            return bytes(data)
        assert len(datagram) <= DATAGRAM and len(datagram) % TS_PACKET == 0 and datagram[0] == 0x47
        data += datagram


def grey(level: int) -> np.ndarray:
    return np.full((120, 160, 3), level, np.uint8)


def decoded(data: bytes) -> list:
    with av.open(io.BytesIO(data), format="mpegts") as container:
        return [(f.width, f.height, f.time, f.to_ndarray(format="gray").mean()) for f in container.decode(video=0)]


def test_frames_arrive_decodable_with_vehicle_time_stamps(receiver):
    sender = VideoSender(receiver.getsockname(), 160, 120, FPS, 300_000)
    for k in range(20):
        sender.frame(grey(10 * k), k)
    sender.close()
    frames = decoded(received(receiver))
    assert len(frames) == 20 and {(w, h) for w, h, _, _ in frames} == {(160, 120)}
    assert [t for _, _, t, _ in frames] == pytest.approx([k / FPS for k in range(20)], abs=2e-4)
    assert frames[-1][3] > frames[1][3] + 100  # the pictures, not just their boxes
    assert sender.counters["encoder_errors"] == sender.counters["send_errors"] == 0


def test_a_bad_frame_is_counted_and_the_stream_goes_on(receiver):
    sender = VideoSender(receiver.getsockname(), 160, 120, FPS, 300_000)
    sender.frame(grey(50), 0)
    sender.frame(np.zeros((120, 160, 3), np.float64), 1)  # not RGB bytes: refused by the encoder
    sender.frame(grey(60), 2)
    sender.close()
    assert sender.counters["encoder_errors"] == 1 and sender.last_error
    assert sender.counters["frames"] == 2 and sender.counters["streams"] == 2  # opened again after it


def test_a_clock_that_starts_again_begins_a_new_stream(receiver):
    sender = VideoSender(receiver.getsockname(), 160, 120, FPS, 300_000)
    for k in (0, 1, 2, 0, 1):
        sender.frame(grey(40), k)
    assert sender.counters["streams"] == 2 and sender.counters["encoder_errors"] == 0
    sender.close()


def test_a_port_that_refuses_is_counted_and_nothing_raised():
    sender = VideoSender(("127.0.0.1", 0), 160, 120, FPS, 300_000)  # no datagram may go to port 0
    for k in range(3):
        sender.frame(grey(40), k)
    assert sender.counters["frames"] == 3 and sender.counters["send_errors"] >= 3
    assert sender.counters["datagrams"] == 0
    sender.close()

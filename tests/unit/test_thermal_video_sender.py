"""The thermal video's I/O edge (autopilot/io/thermal_video.py) on a real UDP socket: what it sends
is an MPEG-TS of H.264 frames PyAV decodes at their size and timestamps (vehicle time), and it is
never down: a frame the encoder refuses and a datagram the socket refuses are counted, the stream
goes on, and a clock that starts again (a reboot) begins a new stream."""
from __future__ import annotations

import io
import math
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


def test_a_vehicle_streams_in_vehicle_time_and_a_reboot_starts_a_new_stream(tmp_path, receiver):
    """The vehicle as `autopilot --thermal-camera --video-port` builds it, run flat out by the loop:
    one frame each 1/8.7 s of vehicle time on the wire; a reboot of the autopilot starts a second
    stream on the new clock once the vehicle speaks again (the frames of its silent boot skipped and
    counted), and nothing is refused on the way."""
    from firefly.autopilot.cli.main import build, build_parser
    from firefly.autopilot.io.runner import Runner
    from firefly.autopilot.testing.run import free_port_bases

    listen, out = free_port_bases(2, 1)
    args = build_parser().parse_args([
        "--thermal-camera", "--video-port", str(receiver.getsockname()[1]), "--quiet", "--wipe",
        "--listen", f"udp:127.0.0.1:{listen}", "--out", f"udp:127.0.0.1:{out}", "--state-dir", str(tmp_path)])
    (node, _), = build(args)
    video = node.session.camera_component.video
    runner = Runner([node], math.inf)
    try:
        runner.run(2.0)
        first = received(receiver)
        node.vehicle.reboot_requested = True  # as the command handler leaves it
        runner.run(4.0)
        second = received(receiver)
    finally:
        node.endpoint.close()
    assert node.reboots == 1 and node.session.camera_component.video is video  # the camera's, kept
    times = [t for _, _, t, _ in decoded(first)]
    assert times == pytest.approx([k / FPS for k in range(len(times))], abs=2e-4) and len(times) == 18  # 0..17
    after = [t for _, _, t, _ in decoded(second)]
    booted = round(after[0] * FPS)  # the first frame once the rebooted autopilot speaks (its boot: < 2 s)
    assert after == pytest.approx([k / FPS for k in range(booted, booted + len(after))], abs=2e-4)
    assert 0 < after[0] < 2.0 and after[-1] == pytest.approx(math.floor(node.vehicle.time_s * FPS) / FPS, abs=2e-4)
    assert video.schedule.skipped == booted  # the boot's frames, counted
    assert video.edge_counters["streams"] == 2 and video.edge_counters["encoder_errors"] == 0
    assert video.edge_counters["send_errors"] == 0

"""What telemetry costs: the real-time factor a connected client sees, and the cost of one message.

rtf_with_client: `autopilot --speedup inf` with one client on its --out, default streams. The
client reads raw datagrams and takes time_boot_ms out of each ATTITUDE and SYSTEM_TIME frame by
its offsets (no MAVLink parsing: a Python parser could not keep up with a vehicle at 1,000x and
would measure itself). It sends a GCS HEARTBEAT every wall second, as a ground station does. The
figure is the advance of those sim-time stamps per wall second over the window.

message_cost_us: one vehicle's session in process, no sockets: every message the default streams
send, built and packed (what the loop does per message before the send), timed over many rounds.
"""
from __future__ import annotations

import math
import socket
import subprocess
import sys
import time
from pathlib import Path

from report import summary  # bench/report.py, beside this script

ROOT = Path(__file__).resolve().parents[1]
STAMPED = {30: 0, 2: 8}  # ATTITUDE: time_boot_ms at payload offset 0; SYSTEM_TIME: after time_unix_usec


def frames_stamps(datagram: bytes) -> list[int]:
    """time_boot_ms of every ATTITUDE / SYSTEM_TIME frame in a datagram of MAVLink 2 frames."""
    out, i, n = [], 0, len(datagram)
    while i + 12 <= n and datagram[i] == 0xFD:
        length, incompat = datagram[i + 1], datagram[i + 2]
        msg_id = datagram[i + 7] | datagram[i + 8] << 8 | datagram[i + 9] << 16
        offset = STAMPED.get(msg_id)
        if offset is not None:
            payload = datagram[i + 10:i + 10 + length] + bytes(12)  # trailing zeros are trimmed on the wire
            out.append(int.from_bytes(payload[offset:offset + 4], "little"))
        i += 12 + length + (13 if incompat & 1 else 0)
    return out


def rtf_with_client_run(window_s: float, params: dict | None = None, request_hz: int = 0) -> float:
    """One run; with `params`, the vehicle starts with those parameter values (its saved file);
    with `request_hz`, the client asks for every stream at that rate (as MAVProxy does)."""
    import json
    state = ROOT / "bench" / "tmp" / "telemetry"
    if params is not None:
        (state / "instance-0").mkdir(parents=True, exist_ok=True)
        (state / "instance-0" / "params.json").write_text(json.dumps(params))

    def firefly(port: int) -> subprocess.Popen:
        return subprocess.Popen([sys.executable, "-m", "firefly.autopilot", "--speedup", "inf",
                                 "--listen", "udp:127.0.0.1:0", "--out", f"udp:127.0.0.1:{port}", "--quiet",
                                 *(() if params is not None else ("--wipe",)), "--state-dir", str(state)], cwd=ROOT)
    return client_rtf(firefly, window_s, request_hz)


def client_rtf(launch, window_s: float, request_hz: int = 0, settle_s: float = 0.0) -> float:
    """Sim seconds per wall second a ground station sees: `launch(port)` starts a vehicle sending
    to the client's port; the client answers with a GCS HEARTBEAT every wall second (and, with
    `request_hz`, REQUEST_DATA_STREAM for all streams at that rate, repeated with each heartbeat
    as a ground station keeps asking). The window opens `settle_s` after the first stamp."""
    from pymavlink.dialects.v20 import ardupilotmega as mavlink
    client = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    client.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 1 << 22)
    client.bind(("127.0.0.1", 0))
    client.settimeout(0.5)
    gcs = mavlink.MAVLink(None, srcSystem=255, srcComponent=190)
    hello = gcs.heartbeat_encode(6, 8, 0, 0, 0).pack(gcs)
    if request_hz:
        hello += gcs.request_data_stream_encode(1, 1, mavlink.MAV_DATA_STREAM_ALL, request_hz, 1).pack(gcs)
    proc = launch(client.getsockname()[1])
    try:
        first = last = opened = None
        sent_s = 0.0
        deadline = time.monotonic() + 60.0
        while time.monotonic() < deadline:
            try:
                datagram, sender = client.recvfrom(65535)
            except socket.timeout:
                continue
            now = time.monotonic()
            if now - sent_s >= 1.0:
                client.sendto(hello, sender)
                sent_s = now
            stamps = frames_stamps(datagram)
            if not stamps:
                continue
            if opened is None:
                opened = now + settle_s
                deadline = opened + window_s + 30.0
            if now < opened:
                continue
            if first is None:
                first = (now, max(stamps))
                deadline = now + window_s
            last = (now, max(stamps))
        if first is None or last[0] <= first[0]:
            raise RuntimeError("no telemetry")
        return (last[1] - first[1]) / 1000.0 / (last[0] - first[0])
    finally:
        proc.terminate()
        try:
            proc.wait(5)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
        client.close()


def rtf_with_client(runs: int, window_s: float = 5.0, progress=print) -> dict:
    values = []
    for i in range(runs):
        values.append(rtf_with_client_run(window_s))
        progress(f"rtf with a client, run {i + 1}/{runs}: {values[-1]:.0f}x")
    return summary(values)


def message_cost_us(runs: int, rounds: int = 2000, progress=print) -> dict:
    """Per message of the default streams: build (vehicle state -> message) and pack (-> frame)."""
    from firefly.autopilot.mavlink.dialect import new_codec
    from firefly.autopilot.mavlink.link import Link
    from firefly.autopilot.mavlink.session import Session
    from firefly.autopilot.mavlink.signing import LinkSigning
    from firefly.autopilot.params import ParamStore
    from firefly.autopilot.vehicle import Vehicle, VehicleConfig
    vehicle = Vehicle(VehicleConfig(), ParamStore(None))
    codec = new_codec(1)
    session = Session(vehicle, codec)
    link = Link(codec, LinkSigning(codec))
    streamed = [m for m in session.streams._interval_s if session.streams.interval_s(m) != math.inf]
    values = []
    for i in range(runs):
        t0 = time.perf_counter()
        for _ in range(rounds):
            link.pack([session.build(m) for m in streamed])
        values.append((time.perf_counter() - t0) / (rounds * len(streamed)) * 1e6)
        progress(f"message cost, run {i + 1}/{runs}: {values[-1]:.2f} us per message ({len(streamed)} kinds)")
    return summary(values) | {"kinds": len(streamed)}

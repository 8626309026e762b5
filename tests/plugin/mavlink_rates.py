"""How much MAVLink one `--out` of a vehicle receives, at a given speedup: datagrams and messages
per wall second and per vehicle second, and how fast pymavlink decodes them. The figures behind
mavlink_client.py (why `firefly.mavlink()` reads its socket from a thread).

    python -m tests.plugin.mavlink_rates 10 inf
"""
from __future__ import annotations

import collections
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from pymavlink.dialects.v20 import ardupilotmega

LISTEN_WALL_S = 3.0


def last_time_s(state_log: Path) -> float:
    """Vehicle time of the state log's last complete line (waits for the first)."""
    while True:
        lines = state_log.read_text().splitlines() if state_log.exists() else []
        if len(lines) >= 3:
            return float(lines[-2].split(",")[0])  # the last may be unfinished
        time.sleep(0.01)


def measure(speedup: str) -> str:
    with tempfile.TemporaryDirectory() as directory, \
            socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4 << 20)
        sock.bind(("127.0.0.1", 0))
        sock.settimeout(10)
        state_log = Path(directory, "state.csv")
        process = subprocess.Popen([sys.executable, "-m", "firefly.autopilot", "--listen", "udp:127.0.0.1:0",
                                    "--out", f"udp:127.0.0.1:{sock.getsockname()[1]}", "--speedup", speedup,
                                    "--state-dir", str(Path(directory, "state")), "--wipe", "--quiet",
                                    "--state-log", str(state_log)])
        try:
            sock.recv(65536)
            start_s, start = last_time_s(state_log), time.monotonic()
            datagrams = []
            while time.monotonic() - start < LISTEN_WALL_S:
                datagrams.append(sock.recv(65536))
            wall = time.monotonic() - start
            vehicle = last_time_s(state_log) - start_s
        finally:
            process.terminate()
            process.wait()
    codec = ardupilotmega.MAVLink(None)
    codec.robust_parsing = True
    kinds: collections.Counter = collections.Counter()
    decode_start = time.monotonic()
    for datagram in datagrams:
        kinds.update(m.get_type() for m in codec.parse_buffer(datagram) or [])
    decode = time.monotonic() - decode_start
    messages = sum(kinds.values())
    return (f"speedup {speedup}: {len(datagrams) / wall:.0f} datagrams/s ({sum(map(len, datagrams)) / wall / 1e6:.2f} MB/s), "
            f"{messages / wall:.0f} messages/s, {messages / vehicle:.0f} per vehicle second, vehicle at "
            f"{vehicle / wall:.0f}x; pymavlink decodes {messages / decode:.0f} messages/s")


if __name__ == "__main__":
    for speedup in sys.argv[1:] or ["10", "inf"]:
        print(measure(speedup), flush=True)

"""Start and stop an `autopilot` process for commands that bring their own vehicle."""
from __future__ import annotations

import socket
import subprocess
import sys
import tempfile


def free_udp_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class AutopilotProcess:
    def __init__(self, speedup: float, extra: tuple = ()):
        self.port = free_udp_port()
        self._state = tempfile.TemporaryDirectory(prefix="firefly-")
        self.process = subprocess.Popen(
            [sys.executable, "-m", "autopilot", "--listen", "udp:127.0.0.1:0",
             "--out", f"udp:127.0.0.1:{self.port}", "--speedup", str(speedup),
             "--state-dir", self._state.name, "--wipe", "--quiet", *extra])

    @property
    def url(self) -> str:
        return f"udpin://127.0.0.1:{self.port}"

    def stop(self) -> None:
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self.process.kill()
        self._state.cleanup()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.stop()

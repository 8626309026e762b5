"""Starting and stopping a real `autopilot` process on a free UDP port: for the commands that bring
their own vehicle, the SITL tests' fixtures and the bench alike.

The process listens on an ephemeral port and sends to `port`, where the client listens (udpin),
exactly as a user's MAVSDK or pymavlink script listens on 14540/14550. A flight run against a
process it started goes through `guard()`, so that a process that exits (a scenario table it
refuses, a crash) ends the flight at once with one line instead of a connection timeout.
"""
from __future__ import annotations

import asyncio
import os
import socket
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Awaitable, Callable, TypeVar

from .warm_start import WarmProcess, popen_autopilot

T = TypeVar("T")
EXIT_POLL_S = 0.05  # how often guard() looks at the process while the flight runs


INSTANCE_PORT_STEP = 10  # with --count, vehicle k sends to the --out port + 10k


def free_udp_port(count: int = 1) -> int:
    """A free UDP port that is also free + 10k for each further vehicle k < count."""
    for _ in range(100):
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
            s.bind(("127.0.0.1", 0))
            port = s.getsockname()[1]
        if all(_bindable(port + INSTANCE_PORT_STEP * k) for k in range(1, count)):
            return port
    raise OSError(f"found no free UDP ports for {count} vehicles")


def _bindable(port: int) -> bool:
    if port > 65535:
        return False
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        try:
            s.bind(("127.0.0.1", port))
        except OSError:
            return False
    return True


def stop_process(process: subprocess.Popen | WarmProcess, timeout_s: float = 10.0) -> None:
    """Terminate `process` and reap it; killed if it has not exited within `timeout_s`."""
    if process.poll() is None:
        process.terminate()
        try:
            process.wait(timeout=timeout_s)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


class AutopilotExited(RuntimeError):
    """The autopilot process ended while a flight still needed it."""


@dataclass
class AutopilotProcess:
    process: subprocess.Popen | WarmProcess
    port: int  # where the client listens (the autopilot's --out)
    state_dir: Path
    speedup: str
    stderr_log: object = None  # a file holding the process's stderr, when captured
    owned_dirs: list = field(default_factory=list)  # temporary directories removed by stop()
    exit_reported: bool = False  # guard() has said how it ended (with its last line)

    @property
    def mavsdk_url(self) -> str:
        return f"udpin://127.0.0.1:{self.port}"

    def mavsdk_urls(self, count: int) -> list[str]:
        """Of each vehicle of a --count process."""
        return [f"udpin://127.0.0.1:{self.port + INSTANCE_PORT_STEP * k}" for k in range(count)]

    @property
    def pymavlink_url(self) -> str:
        return f"udpin:127.0.0.1:{self.port}"

    def exit_line(self) -> str:
        """One line saying how the process ended, with the last line it wrote to stderr if captured."""
        said = [line for line in self._stderr_text().splitlines() if line.strip()]
        return f"autopilot exited with status {self.process.returncode}" + (f" ({said[-1].strip()})" if said else "")

    async def guard(self, flight: Awaitable[T]) -> T:
        """The result of `flight`, or AutopilotExited as soon as the process exits before it ends
        (the flight is then cancelled, so its own clean-up runs)."""
        task = asyncio.ensure_future(flight)
        try:
            while not task.done():
                if self.process.poll() is not None:
                    self.exit_reported = True
                    raise AutopilotExited(self.exit_line())
                await asyncio.wait({task}, timeout=EXIT_POLL_S)
            return task.result()
        finally:
            if not task.done():
                task.cancel()
                await asyncio.gather(task, return_exceptions=True)

    def stop(self) -> int:
        stop_process(self.process)
        if self.stderr_log is not None:
            if not self.exit_reported:
                sys.stderr.write(self._stderr_text())  # nothing the process said is lost
            self.stderr_log.close()
            self.stderr_log = None
        for directory in self.owned_dirs:
            directory.cleanup()
        self.owned_dirs.clear()
        return self.process.returncode

    def _stderr_text(self) -> str:
        if self.stderr_log is None:
            return ""
        self.stderr_log.seek(0)
        return self.stderr_log.read().decode(errors="replace")

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.stop()


def start_autopilot(state_dir: Path | None = None, speedup="10", extra: tuple = (), port: int | None = None,
                    wipe: bool = True, cwd: Path | None = None, capture_stderr: bool = False) -> AutopilotProcess:
    """Start `python -m firefly.autopilot` (warm_start.py: forked warm) sending to a free port (or `port`). Without `state_dir` its
    parameters and mission live in a temporary directory that stop() removes. With capture_stderr
    what it writes to stderr is kept for exit_line() and written out by stop()."""
    owned = []
    if state_dir is None:
        owned.append(tempfile.TemporaryDirectory(prefix="firefly-"))
        state_dir = Path(owned[0].name)
    count = int(extra[extra.index("--count") + 1]) if "--count" in extra else 1
    port = port or free_udp_port(count)
    args = ["--listen", "udp:127.0.0.1:0", "--out", f"udp:127.0.0.1:{port}", "--speedup", str(speedup),
            "--state-dir", str(state_dir), "--quiet", f"--exit-with-parent={os.getpid()}", *extra]
    if wipe:
        args.append("--wipe")
    log = tempfile.TemporaryFile() if capture_stderr else None
    process = popen_autopilot(args, cwd=cwd, env={**os.environ, "PYTHONUNBUFFERED": "1"}, stderr=log)
    return AutopilotProcess(process, port, Path(state_dir), str(speedup), log, owned)


def check_scenario(path: Path) -> None:
    """Ask the autopilot whether it flies scenario `path`, before any work depends on it: the
    companion reads only the world of a scenario (sim/scenario.py); the vehicle's own tables
    ([faults], [script], [signing]) are the autopilot's to judge. Raises ScenarioError with the
    autopilot's one line when it refuses them."""
    from firefly.sim.scenario import ScenarioError
    with tempfile.TemporaryDirectory(prefix="firefly-check-") as state:
        result = subprocess.run([sys.executable, "-m", "firefly.autopilot", "--scenario", str(path), "--duration", "0",
                                 "--quiet", "--listen", "udp:127.0.0.1:0", "--out", f"udp:127.0.0.1:{free_udp_port()}",
                                 "--state-dir", state, "--wipe"], capture_output=True, text=True, timeout=60)
    if result.returncode != 0:
        said = [line for line in result.stderr.splitlines() if line.strip()]
        raise ScenarioError(said[-1].removeprefix("autopilot: error: ") if said else
                            f"{path}: the autopilot refused it (status {result.returncode})")


def run_flight(flight: Callable[[str], Awaitable[T]], url: str | None, speedup: float,
               scenario: Path | None = None, say=print, extra: tuple = ()) -> T:
    """`flight(url)` against the vehicle at `url`, or, without one, against an autopilot process
    started for it (at `speedup`, on `scenario`, with `extra` options) and stopped after it."""
    return run_team_flight(lambda urls: flight(urls[0]), [url] if url else None, speedup, scenario, say, 1, extra)


def run_team_flight(flight: Callable[[list], Awaitable[T]], urls: list | None, speedup: float,
                    scenario: Path | None = None, say=print, count: int = 1, extra: tuple = ()) -> T:
    """`flight(urls)` against the vehicles at `urls`, or, without them, against one autopilot
    process with `count` vehicles started for it (at `speedup`, on `scenario`) and stopped after it."""
    if urls:
        return asyncio.run(flight(urls))
    extra += ("--scenario", str(scenario)) if scenario else ()
    if count > 1:
        extra += ("--count", str(count))
    with start_autopilot(speedup=speedup, extra=extra, capture_stderr=True) as ap:
        urls = ap.mavsdk_urls(count)
        say(f"started autopilot ({count} vehicle{'s' if count > 1 else ''}, speedup {speedup:g}"
            f"{', scenario ' + str(scenario) if scenario else ''}), MAVSDK connecting on {', '.join(urls)}")
        return asyncio.run(ap.guard(flight(urls)))

"""One test's autopilot process: started on free ports with its own state, logs and seed, made
ready as the test asked, stopped after it with a check of how it ended.

Everything the process writes (state directory, .tlog, state log, stderr, dataflash logs) lives
in one evidence directory per test (evidence.py); the plugin keeps it when the test fails and
removes it when it passes.
"""
from __future__ import annotations

import os
import shlex
import socket
import subprocess
import sys
import time
from pathlib import Path

from . import evidence
from .settings import FireflySettings
from .errors import FireflyError
from .vehicle import FireflyVehicle

PORT_KINDS = ("mavsdk", "mavlink", "control")
INSTANCE_PORT_STEP = 10  # the autopilot's --count gives vehicle k its --out ports + 10k
START_WALL_S = 20.0  # to the first state line; the process is normally there in ~0.15 s
STOP_WALL_S = 10.0

_running: set = set()  # every run not yet stopped, for the end-of-session sweep


def _bindable(port: int) -> bool:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        try:
            s.bind(("127.0.0.1", port))
        except OSError:
            return False
    return True


def free_port_bases(kinds: int, count: int) -> list[int]:
    """`kinds` free UDP ports such that each one plus 10k, for k < count, is free too and no two
    coincide: the --out ports of `count` vehicles of one process (vehicle k's are vehicle 0's + 10k)."""
    for _ in range(200):
        bases = []
        for _ in range(kinds):
            with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
                s.bind(("127.0.0.1", 0))
                bases.append(s.getsockname()[1])
        extra = [b + INSTANCE_PORT_STEP * k for b in bases for k in range(1, count)]
        every = bases + extra
        if len(set(every)) == len(every) and max(every) <= 65535 and all(_bindable(p) for p in extra):
            return bases
    raise FireflyError(f"firefly: found no free UDP ports for {count} vehicles")


def free_port_blocks(count: int) -> list[dict]:
    """For each of `count` vehicles, its port for each client kind."""
    bases = free_port_bases(len(PORT_KINDS), count)
    return [{kind: base + INSTANCE_PORT_STEP * k for kind, base in zip(PORT_KINDS, bases)} for k in range(count)]


class FireflyRun:
    def __init__(self, settings: FireflySettings, evidence_dir: Path):
        self.settings = settings
        self.evidence_dir = Path(evidence_dir)
        self.stderr_path = self.evidence_dir / "autopilot.stderr"
        self.state_dir = self.evidence_dir / "state"  # parameters, and the vehicles' logs/*.BIN
        ports = free_port_blocks(settings.count)
        several = settings.count > 1
        self.vehicles = [
            FireflyVehicle(self, k, ports[k],
                           self.evidence_dir / (f"state.{k}.csv" if several else "state.csv"),
                           self.evidence_dir / (f"vehicle.{k}.tlog" if several else "vehicle.tlog"))
            for k in range(settings.count)]
        self.command = self._command(ports[0])
        self.process: subprocess.Popen | None = None
        self.exit_code: int | None = None

    def _command(self, ports: dict) -> list[str]:
        s = self.settings
        cmd = [sys.executable, "-m", "firefly.autopilot", "--listen", "udp:127.0.0.1:0",
               *[a for kind in PORT_KINDS for a in ("--out", f"udp:127.0.0.1:{ports[kind]}")],
               "--speedup", s.speedup_text, "--seed", str(s.seed), "--count", str(s.count),
               "--startup", s.startup, "--state-dir", str(self.state_dir), "--wipe", "--quiet",
               f"--exit-with-parent={os.getpid()}",
               "--tlog", str(self.evidence_dir / "vehicle.tlog"),
               "--state-log", str(self.evidence_dir / "state.csv")]
        if s.scenario is not None:
            cmd += ["--scenario", str(s.scenario)]
        if s.home is not None:
            cmd.append(f"--home={s.home}")  # joined: argparse reads "-35.3,..." alone as an option
        return cmd

    # ----- life ----------------------------------------------------------------------------
    def start(self) -> "FireflyRun":
        self.evidence_dir.mkdir(parents=True, exist_ok=True)
        with open(self.stderr_path, "wb") as stderr:
            self.process = subprocess.Popen(self.command, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                            stderr=stderr, env={**os.environ, "PYTHONUNBUFFERED": "1"})
        _running.add(self)
        deadline = time.monotonic() + START_WALL_S
        for vehicle in self.vehicles:
            while vehicle._state.latest_state() is None:
                self.check_alive()
                if time.monotonic() > deadline:
                    raise FireflyError(f"firefly: the autopilot wrote no state within {START_WALL_S:g} s of start")
                time.sleep(0.002)
        return self

    def prepare(self) -> None:
        """The ready state the settings ask for: parameters, then the takeoff, then the faults."""
        s = self.settings
        for vehicle in self.vehicles:
            for name, value in s.params.items():
                vehicle.set_param(name, value)
        if s.airborne is not None:
            for vehicle in self.vehicles:
                vehicle.take_off(s.airborne)
        for vehicle in self.vehicles:
            for name, value in s.faults.items():
                vehicle.set_param(name, value)

    def check_alive(self) -> None:
        """FireflyError, with what the process last said, if it has exited."""
        if self.process is None or self.process.poll() is None:
            return
        raise FireflyError(f"firefly: the autopilot exited with status {self.process.returncode}"
                           + (f": {self.stderr_tail()}" if self.stderr_tail() else ""))

    def internal_errors(self) -> list[str]:
        """The internal errors the process reported (the lines it writes to stderr for each)."""
        try:
            said = self.stderr_path.read_text(errors="replace").splitlines()
        except OSError:
            return []
        return [line for line in said if ": internal error: " in line]

    def stderr_tail(self, lines: int = 20) -> str:
        try:
            said = [line for line in self.stderr_path.read_text(errors="replace").splitlines() if line.strip()]
        except OSError:
            return ""
        return "\n".join(said[-lines:])

    def stop(self) -> int | None:
        """Close every client, stop the process (SIGTERM, then SIGKILL) and return its exit status."""
        for vehicle in self.vehicles:
            vehicle.close()
        if self.process is not None and self.exit_code is None:
            if self.process.poll() is None:
                self.process.terminate()
                try:
                    self.process.wait(timeout=STOP_WALL_S)
                except subprocess.TimeoutExpired:
                    self.process.kill()
                    self.process.wait()
            self.exit_code = self.process.returncode
        _running.discard(self)
        return self.exit_code

    # ----- what a failure report says ------------------------------------------------------
    def describe(self) -> str:
        s = self.settings
        lines = [f"seed {s.seed}, speedup {s.speedup_text}, {s.count} vehicle{'s' if s.count > 1 else ''}"
                 + (f", scenario {s.scenario}" if s.scenario else ""),
                 f"evidence kept in {self.evidence_dir}"]
        for v in self.vehicles:
            lines.append(f"vehicle {v.system_id}: tlog {v.tlog_path}")
            lines.append(f"vehicle {v.system_id}: state log {v.state_log_path}")
            latest = v._state.latest_state() if v._state.path.exists() else None
            v._state.close()  # the run may be over: read once, hold nothing open
            if latest is not None:
                lines.append(f"vehicle {v.system_id}: last state {latest}")
        lines.append(f"autopilot stderr: {self.stderr_path}")
        for log in evidence.dataflash_logs(self.state_dir):  # copied when the process has stopped
            lines.append(f"dataflash log: {self.evidence_dir / evidence.copy_name(self.state_dir, log)}")
        lines.append("reproduce: " + shlex.join(self.reproduce_command()))
        if s.params or s.faults:
            lines.append("then set: " + ", ".join(f"{k}={v:g}" for k, v in {**s.params, **s.faults}.items()))
        return "\n".join(lines)

    def copy_dataflash_logs(self) -> list[Path]:
        """Copy the vehicles' dataflash logs (complete once the process has stopped) beside the .tlog."""
        return evidence.copy_dataflash_logs(self.state_dir, self.evidence_dir)

    def reproduce_command(self) -> list[str]:
        """The same vehicle for a person at a ground station: its seed, speed, scenario and home,
        sending to the usual 14550, with a state directory of its own so that the test's
        evidence is left as it is."""
        s = self.settings
        cmd = ["autopilot", "--out", "udp:127.0.0.1:14550", "--speedup", s.speedup_text, "--seed", str(s.seed),
               "--count", str(s.count), "--startup", s.startup,
               "--state-dir", str(self.evidence_dir / "reproduce-state"), "--wipe"]
        if s.scenario is not None:
            cmd += ["--scenario", str(s.scenario)]
        if s.home is not None:
            cmd.append(f"--home={s.home}")
        return cmd


def stop_all() -> None:
    """Stop every run still going (an interrupted session)."""
    for run in list(_running):
        run.stop()

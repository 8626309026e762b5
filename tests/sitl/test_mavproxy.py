"""The real MAVProxy flies the autopilot: `mode guided`, `arm throttle`, `takeoff 10`, `mode land`.

MAVProxy listens on the autopilot's first --out port and gets its commands on stdin, as a user
typing at the MAV> prompt would. A pymavlink observer listens on a second --out port and checks
what the vehicle really did, independently of what MAVProxy prints.

MAVProxy's --non-interactive and --daemon options make the main thread sleep instead of reading
stdin (mavproxy.py: `if opts.daemon or opts.non_interactive: time.sleep(0.1) else: input_loop()`),
so commands could not be fed through a pipe with them. MAVProxy is therefore started in its normal
interactive mode with a piped stdin; it reads one command per line and quits at end of file.
"""
from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from firefly.autopilot.params import SERVED

from .conftest import free_udp_port
from .pymav import Gcs

pytestmark = pytest.mark.sitl

STABILIZE, GUIDED, LAND = 0, 4, 9
ARMED_FLAG = 128  # MAV_MODE_FLAG_SAFETY_ARMED


class MavProxy:
    """MAVProxy as a subprocess: commands in on stdin, every output line collected by a thread."""

    def __init__(self, master_port: int | str, state_dir: Path):
        """`master_port`: the UDP port MAVProxy listens on, or a whole --master URL (tcp:HOST:PORT)."""
        state_dir.mkdir(parents=True, exist_ok=True)
        home = state_dir / "home"  # ~/.mavproxy and ~/.mavinit.scr: none of the user's own
        home.mkdir(exist_ok=True)
        self.state_dir = state_dir
        master = master_port if isinstance(master_port, str) else f"udpin:127.0.0.1:{master_port}"
        # Its terrain module would answer the vehicle's TERRAIN_REQUEST by forking a process to
        # download SRTM tiles; forked while the main thread reads stdin, that child deadlocks on
        # the stdin lock, and MAVProxy's exit then waits on it until killed. No terrain is sent.
        cmd = [sys.executable, "-m", "MAVProxy.mavproxy", "--master", master,
               "--state-basedir", str(state_dir), "--cmd", "terrain set terrain_data_rate 0"]
        env = {**os.environ, "HOME": str(home), "PYTHONUNBUFFERED": "1"}
        env.pop("DISPLAY", None)
        self.process = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                        stderr=subprocess.STDOUT, text=True, bufsize=1, cwd=state_dir,
                                        env=env, start_new_session=True)
        self.lines: list[str] = []
        self._cond = threading.Condition()
        self._reader = threading.Thread(target=self._read, name="mavproxy-stdout", daemon=True)
        self._reader.start()

    def _read(self) -> None:
        for line in self.process.stdout:
            with self._cond:
                self.lines.append(line.rstrip("\n"))
                self._cond.notify_all()
        with self._cond:
            self._cond.notify_all()

    def send(self, command: str) -> None:
        self.process.stdin.write(command + "\n")
        self.process.stdin.flush()

    def output(self) -> str:
        with self._cond:
            return "\n".join(self.lines)

    def wait_output(self, pattern: str, timeout: float, start: int = 0) -> re.Match:
        """First match of `pattern` in an output line numbered >= start, waiting up to `timeout`."""
        regex = re.compile(pattern)
        deadline = time.monotonic() + timeout
        with self._cond:
            seen = start
            while True:
                for line in self.lines[seen:]:
                    found = regex.search(line)
                    if found:
                        return found
                seen = max(seen, len(self.lines))
                remaining = deadline - time.monotonic()
                if remaining <= 0 or self.process.poll() is not None and not self._reader.is_alive():
                    raise AssertionError(f"MAVProxy never printed /{pattern}/ within {timeout:g} s; "
                                         f"output:\n" + "\n".join(self.lines[-40:]))
                self._cond.wait(min(remaining, 0.5))

    def mark(self) -> int:
        with self._cond:
            return len(self.lines)

    def stop(self) -> None:
        """End of input makes MAVProxy quit (within a second, with no terrain download child to
        wait on); if it does not within two (its exit can still hang on a backlog of its tlog
        queue), its process group (its own session, so only MAVProxy and its children) is killed
        while it is alive."""
        proc = self.process
        try:
            proc.stdin.close()
        except OSError:
            pass
        try:
            proc.wait(timeout=2)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)  # not reaped yet, so the group id is still its own
            proc.wait(timeout=10)
        self._reader.join(timeout=5)
        proc.stdout.close()


class Observer:
    """A pymavlink listener on the autopilot's second --out port, drained by a thread.

    Everything the vehicle sends is kept, so nothing is lost to a full socket buffer while the
    test waits on MAVProxy, and waits can look back at what already arrived.
    """

    def __init__(self, port: int, timeout: float = 15.0):
        self.gcs = Gcs(f"udpin:127.0.0.1:{port}", timeout=timeout)  # returns on the first HEARTBEAT
        self.messages: list = [self.gcs.heartbeat]
        self._cond = threading.Condition()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="observer", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while not self._stop.is_set():
            msg = self.gcs.conn.recv_match(blocking=True, timeout=0.2)
            if msg is None or msg.get_type() == "BAD_DATA":
                continue
            with self._cond:
                self.messages.append(msg)
                self._cond.notify_all()

    def mark(self) -> int:
        with self._cond:
            return len(self.messages)

    def of_type(self, mtype: str, start: int = 0) -> list:
        with self._cond:
            return [m for m in self.messages[start:] if m.get_type() == mtype]

    def until(self, predicate, timeout: float, what: str):
        """Wait (on arrivals, not a fixed sleep) until predicate() is truthy; return its value."""
        deadline = time.monotonic() + timeout
        with self._cond:
            while True:
                value = predicate()
                if value:
                    return value
                remaining = deadline - time.monotonic()
                if remaining <= 0:
                    raise AssertionError(f"observer: timed out after {timeout:g} s waiting for {what}")
                self._cond.wait(min(remaining, 0.5))

    def wait(self, mtype: str, condition, timeout: float, what: str, start: int = 0):
        """First message of `mtype` from index `start` on satisfying `condition`."""
        def found():
            return next((m for m in self.messages[start:]
                         if m.get_type() == mtype and m.get_srcComponent() == 1 and condition(m)), None)
        return self.until(found, timeout, what)

    def close(self) -> None:
        self._stop.set()
        self._thread.join(timeout=5)
        self.gcs.close()


@pytest.fixture
def two_port_autopilot(autopilot_factory):
    """The autopilot streaming to two ports: MAVProxy's (`.port`) and the observer's."""
    observer_port = free_udp_port()
    ap = autopilot_factory(extra=("--out", f"udp:127.0.0.1:{observer_port}"))
    return ap, observer_port


@pytest.fixture
def observer(two_port_autopilot):
    obs = Observer(two_port_autopilot[1])
    yield obs
    obs.close()


@pytest.fixture
def mavproxy_factory(tmp_path):
    started = []

    def start(master_port: int | str) -> MavProxy:
        mp = MavProxy(master_port, tmp_path / f"mavproxy{len(started)}")
        started.append(mp)
        return mp

    yield start
    for mp in started:
        mp.stop()
    for mp in started:
        assert mp.process.poll() is not None, "MAVProxy still running after stop()"


def armed(hb) -> bool:
    return bool(hb.base_mode & ARMED_FLAG)


def test_mavproxy_guided_takeoff_and_land(two_port_autopilot, observer, mavproxy_factory):
    ap, _ = two_port_autopilot
    mavproxy = mavproxy_factory(ap.port)

    # MAVProxy connects and downloads every parameter in one file over MAVLink FTP
    # (@PARAM/param.pck, as from ArduCopter); the replies go to MAVProxy's link alone, as
    # ArduCopter answers the link that asked: the observer on the other link sees none.
    received = mavproxy.wait_output(r"Received (\d+) parameters \(ftp\)", timeout=30)
    n_params = int(received.group(1))
    assert n_params == len(SERVED)
    assert not observer.of_type("FILE_TRANSFER_PROTOCOL")
    saved = mavproxy.wait_output(r"Saved (\d+) parameters to (\S+)", timeout=10)
    assert int(saved.group(1)) == n_params
    parm_file = Path(saved.group(2))
    assert parm_file.is_relative_to(mavproxy.state_dir)
    assert re.search(r"^WPNAV_SPEED\s+1000(\.0+)?$", parm_file.read_text(), re.M)

    # Ready to fly once home is set; the vehicle starts disarmed in STABILIZE.
    observer.wait("HOME_POSITION", lambda m: True, 15, "HOME_POSITION")
    hb = observer.wait("HEARTBEAT", lambda m: True, 5, "HEARTBEAT", start=observer.mark())
    assert not armed(hb) and hb.custom_mode == STABILIZE

    mark, seen = mavproxy.mark(), observer.mark()
    mavproxy.send("mode guided")
    observer.wait("HEARTBEAT", lambda m: m.custom_mode == GUIDED, 10, "GUIDED (custom_mode 4)", seen)
    mavproxy.wait_output(r"COMMAND_ACK: DO_SET_MODE: ACCEPTED", timeout=10, start=mark)

    # ArduCopter disarms after DISARM_DELAY on the ground (10 s sim = 1 s wall at speedup 10),
    # so `takeoff 10` goes out as soon as the observer sees the armed flag.
    mark, seen = mavproxy.mark(), observer.mark()
    mavproxy.send("arm throttle")
    hb = observer.wait("HEARTBEAT", armed, 10, "armed flag (base_mode & 128)", seen)
    mavproxy.send("takeoff 10")
    assert hb.custom_mode == GUIDED
    mavproxy.wait_output(r"COMMAND_ACK: COMPONENT_ARM_DISARM: ACCEPTED", timeout=10, start=mark)
    mavproxy.wait_output(r"COMMAND_ACK: NAV_TAKEOFF: ACCEPTED", timeout=10, start=mark)

    observer.wait("GLOBAL_POSITION_INT", lambda m: m.relative_alt >= 9500, 30,
                  "relative altitude >= 9.5 m", seen)
    hb = observer.wait("HEARTBEAT", lambda m: True, 5, "HEARTBEAT at altitude", observer.mark())
    assert armed(hb) and hb.custom_mode == GUIDED

    mark, seen = mavproxy.mark(), observer.mark()
    mavproxy.send("mode land")
    observer.wait("HEARTBEAT", lambda m: m.custom_mode == LAND, 10, "LAND (custom_mode 9)", seen)
    mavproxy.wait_output(r"COMMAND_ACK: DO_SET_MODE: ACCEPTED", timeout=10, start=mark)
    observer.wait("GLOBAL_POSITION_INT", lambda m: m.relative_alt < 500, 40,
                  "relative altitude < 0.5 m in LAND", seen)
    hb = observer.wait("HEARTBEAT", lambda m: not armed(m), 30, "disarm after landing", seen)
    assert hb.custom_mode == LAND
    later = observer.mark()
    last = observer.wait("GLOBAL_POSITION_INT", lambda m: True, 5, "position after disarm", later)
    assert abs(last.relative_alt) < 500
    mavproxy.wait_output(r"\bDISARMED\b", timeout=10, start=mark)


def test_mavproxy_reports_no_fence_breach_without_a_fence(autopilot, mavproxy_factory):
    mavproxy = mavproxy_factory(autopilot.port)
    mavproxy.wait_output(r"Received \d+ parameters", timeout=30)  # many SYS_STATUS by now
    assert "fence breach" not in mavproxy.output()

"""The `autopilot` process as a user meets it: flags, scenario files, start, Ctrl-C."""
from __future__ import annotations

import signal
import time
import subprocess
import sys

import pytest

from .conftest import REPO
from .pymav import Gcs

pytestmark = pytest.mark.sitl


def run_cli(*args, timeout=30):
    return subprocess.run([sys.executable, "-m", "firefly.autopilot", *args], cwd=REPO, capture_output=True,
                          text=True, timeout=timeout)


@pytest.mark.parametrize("args, mentions", [
    (("--speedup", "fast"), "--speedup"),
    (("--speedup", "-2"), "--speedup"),
    (("--home", "91,0,10"), "latitude"),
    (("--home", "1,2"), "--home"),
    (("--out", "udp:localhost"), "--out"),
    (("--out", "udp:127.0.0.1:99999"), "port"),
    (("--no-such-flag",), "--no-such-flag"),
    (("--instance", "-1"), "--instance"),
    (("--count", "5001"), "--count"),
    (("--instance", "5000"), "--instance"),
    (("--stats", "/proc/no-such-dir/stats.json"), "--stats"),
    (("--instance", "4990", "--count", "11"), "1..10"),
    (("--fleet", "3,2"), "--fleet"),
])
def test_bad_flags_get_one_line_not_a_traceback(args, mentions):
    result = run_cli(*args, "--duration", "0.1")
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in result.stderr, result.stderr
    assert mentions in lines[0]


@pytest.mark.parametrize("text, mentions", [
    ("[wind]\nspeed_m_s = 'strong'\n", "[wind].speed_m_s"),
    ("[airframe]\nmass_kg = -1.5\n", "mass_kg"),
    ("[home]\nlat = 10\n", "missing"),
    ("this is = = not toml", "TOML"),
    ("[noise]\ngps_typo = 1\n", "gps_typo"),
    ("seed = 1.5\n", "seed"),
    ("[params]\nEK3_DRAG_BCOEF = 9.5\n", "[params].EK3_DRAG_BCOEF"),
    ("[params]\nSIM_WIND_SPD = 3\n", "[faults]"),
])
def test_bad_scenario_gets_one_line_naming_the_key(tmp_path, text, mentions):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    result = run_cli("--scenario", str(path), "--duration", "0.1", "--state-dir", str(tmp_path))
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in result.stderr, result.stderr
    assert str(path) in lines[0] and mentions in lines[0]


def test_missing_scenario_file_is_named(tmp_path):
    result = run_cli("--scenario", str(tmp_path / "nope.toml"), "--duration", "0.1")
    assert result.returncode == 2 and "nope.toml" in result.stderr and "Traceback" not in result.stderr


def test_scenario_home_is_where_the_vehicle_starts(autopilot_factory, tmp_path):
    path = tmp_path / "home.toml"
    path.write_text("seed = 4\n[home]\nlat = 43.5615\nlon = 1.4838\nalt = 150.0\nyaw = 90.0\n")
    ap = autopilot_factory(extra=("--scenario", str(path)))
    gcs = Gcs(ap.pymavlink_url)
    home = gcs.recv("HOME_POSITION", 5)
    att = gcs.recv("ATTITUDE", 5)
    gcs.close()
    assert home is not None and abs(home.latitude / 1e7 - 43.5615) < 1e-6 and abs(home.longitude / 1e7 - 1.4838) < 1e-6
    assert abs(home.altitude / 1000 - 150.0) < 0.01
    assert abs(att.yaw - 1.5708) < 0.01


def test_ctrl_c_exits_cleanly(autopilot):
    gcs = Gcs(autopilot.pymavlink_url)  # running and talking
    gcs.close()
    autopilot.process.send_signal(signal.SIGINT)
    assert autopilot.process.wait(timeout=10) == 0


def test_instance_sets_system_id_and_port_offsets(autopilot_factory):
    ap = autopilot_factory(extra=("--instance", "2"))
    gcs = Gcs(ap.pymavlink_url)
    assert gcs.heartbeat.get_srcSystem() == 3
    gcs.close()


def _tlog_messages(path):
    from pymavlink import mavutil
    log = mavutil.mavlink_connection(str(path))
    out = []
    while (msg := log.recv_match()) is not None:
        out.append(msg)
    return out


def test_tlog_records_what_was_sent_and_received(autopilot_factory, tmp_path):
    tlog = tmp_path / "flight.tlog"
    ap = autopilot_factory(extra=("--tlog", str(tlog)))
    gcs = Gcs(ap.pymavlink_url)
    assert gcs.command(31999) == 3  # an UNSUPPORTED round trip to find in the log
    gcs.close()
    assert ap.stop() == 0
    msgs = _tlog_messages(tlog)
    types = {m.get_type() for m in msgs}
    assert {"HEARTBEAT", "GLOBAL_POSITION_INT", "COMMAND_LONG", "COMMAND_ACK"} <= types
    sent = [m for m in msgs if m.get_type() == "COMMAND_LONG"]
    assert sent[0].command == 31999 and sent[0].get_srcSystem() == 255
    stamps = [m._timestamp for m in msgs]
    assert stamps == sorted(stamps)


def test_tlog_survives_a_kill(autopilot_factory, tmp_path):
    tlog = tmp_path / "killed.tlog"
    ap = autopilot_factory(speedup="1", extra=("--tlog", str(tlog)))
    gcs = Gcs(ap.pymavlink_url)
    # Wait (on telemetry, in vehicle time) until 3 s of flight time have been logged, then kill -9.
    assert gcs.recv("GLOBAL_POSITION_INT", 10, lambda m: m.time_boot_ms >= 3000) is not None
    ap.process.kill()
    ap.process.wait()
    gcs.close()
    msgs = _tlog_messages(tlog)
    boot_ms = [m.time_boot_ms for m in msgs if m.get_type() == "GLOBAL_POSITION_INT"]
    assert boot_ms and max(boot_ms) >= 1500, "more than the last second was lost"


def test_exit_with_parent_stops_a_vehicle_whose_starter_was_killed(tmp_path):
    """A harness killed without its clean-up (a campaign worker, a test worker) must not leave its
    autopilot flying on: with --exit-with-parent the orphan stops by itself, and exits 0."""
    starter = subprocess.Popen([sys.executable, "-c", (
        "import subprocess, sys, time\n"
        "ap = subprocess.Popen([sys.executable, '-m', 'autopilot', '--listen', 'udp:127.0.0.1:0', "
        "'--out', 'udp:127.0.0.1:9', '--quiet', '--wipe', '--exit-with-parent', "
        f"'--state-dir', {str(tmp_path / 'state')!r}, '--state-log', {str(tmp_path / 'states.csv')!r}])\n"
        "print(ap.pid, flush=True)\n"
        "ap.wait()\n")], cwd=REPO, stdout=subprocess.PIPE, text=True)
    autopilot_pid = int(starter.stdout.readline())
    proc_stat = f"/proc/{autopilot_pid}/stat"
    deadline = time.monotonic() + 20
    states = tmp_path / "states.csv"
    while not (states.exists() and len(states.read_text().splitlines()) > 2):  # its loop runs
        assert time.monotonic() < deadline, "the autopilot never started its loop"
        time.sleep(0.02)
    starter.kill()
    starter.wait()

    def gone() -> bool:
        try:
            return open(proc_stat).read().rsplit(")", 1)[1].split()[0] == "Z"  # exited, not yet reaped by init
        except OSError:
            return True
    deadline = time.monotonic() + 10
    while not gone():
        assert time.monotonic() < deadline, "the orphaned autopilot was still running 10 s after its starter died"
        time.sleep(0.05)


def test_exit_with_parent_given_a_pid_that_has_already_gone_stops_at_once(tmp_path):
    """A harness that dies between starting the autopilot and the autopilot's first line must not
    leave it flying either: given the harness's PID, the autopilot stops when that process is
    gone, even if it was gone before the watch began. A bad PID is one line, not a traceback."""
    finished = subprocess.Popen([sys.executable, "-c", "pass"])
    finished.wait()
    started = time.monotonic()
    ap = subprocess.run([sys.executable, "-m", "firefly.autopilot", "--listen", "udp:127.0.0.1:0",
                         "--out", "udp:127.0.0.1:9", "--quiet", "--wipe", "--state-dir", str(tmp_path / "state"),
                         f"--exit-with-parent={finished.pid}"], cwd=REPO, capture_output=True, text=True, timeout=20)
    assert ap.returncode == 0, ap.stderr
    assert time.monotonic() - started < 10

    bad = subprocess.run([sys.executable, "-m", "firefly.autopilot", "--exit-with-parent=-3"], cwd=REPO,
                         capture_output=True, text=True, timeout=20)
    assert bad.returncode == 2 and "Traceback" not in bad.stderr
    assert "--exit-with-parent: expected a process id (a positive integer), got '-3'" in bad.stderr, bad.stderr

"""Same scenario and seed, same trajectory: bit-identical logged states whatever the speedup, the
load on the machine (the runs below compete for the CPU with each other) and whether the process
started cold or was forked warm (groundstation/flight/warm_start.py)."""
from __future__ import annotations

import hashlib
import subprocess
import sys

import pytest

from firefly.groundstation.flight.warm_start import WarmProcess, popen_autopilot

from .conftest import REPO, free_udp_port

pytestmark = pytest.mark.sitl


def start(tmp_path, speedup: str, seed: str, tag: str, warm: bool = False):
    # Telemetry goes to a port of its own that nobody listens on: a client that heard the vehicle
    # (say, another test's MAVSDK on a well-known port) could fly it and change the trajectory.
    log = tmp_path / f"states-{tag}.csv"
    args = ["--scenario", str(REPO / "scenarios" / "scripted_flight.toml"),
            "--speedup", speedup, "--duration", "60", "--seed", seed, "--state-log", str(log),
            "--listen", "udp:127.0.0.1:0", "--out", f"udp:127.0.0.1:{free_udp_port()}", "--quiet", "--wipe",
            "--state-dir", str(tmp_path / tag)]
    if warm:
        proc = popen_autopilot(args, cwd=REPO)
        assert isinstance(proc, WarmProcess)
    else:
        proc = subprocess.Popen([sys.executable, "-m", "firefly.autopilot", *args], cwd=REPO)
    return proc, log


def test_trajectory_is_bit_identical_across_speedups_and_load(tmp_path):
    # Three runs of one seed at once, two flat out and one paced: they load the CPU for each other.
    # The third is forked warm.
    runs = [start(tmp_path, speedup, "3", tag, warm) for speedup, tag, warm in
            (("inf", "a", False), ("30", "b", False), ("inf", "c", True))]
    for proc, _ in runs:
        assert proc.wait(timeout=120) == 0
    digests = {hashlib.sha256(log.read_bytes()).hexdigest() for _, log in runs}
    header, *lines = runs[0][1].read_text().splitlines()
    assert header.startswith("time_s,n_m,e_m,d_m,") and len(lines) == 600  # 60 s of sim time, a state every 0.1 s
    assert len(digests) == 1, "the same seed flew different trajectories"
    # The script really flew: it climbed to 10 m and went round the 30 m square.
    north = [float(x.split(",")[1]) for x in lines]
    down = [float(x.split(",")[3]) for x in lines]
    assert max(north) > 25.0 and min(down) < -9.0
    # So did its dataflash log (docs/logs.md): the same records, in sim time, but for the GPS
    # time of week, which follows the wall clock the vehicle started at, as a GPS's does, and
    # SIM_SPEEDUP's value, which is each run's speedup.
    logs = [dataflash_records(tmp_path / tag / "instance-0" / "logs" / "00000001.BIN") for tag in "abc"]
    assert len(logs[0]) > 10_000 and logs[0] == logs[1] == logs[2]


def dataflash_records(path) -> list:
    from pymavlink import DFReader
    log, out = DFReader.DFReader_binary(str(path)), []
    while (m := log.recv_msg()) is not None:
        fields = m.to_dict()
        if m.get_type() == "GPS":
            fields.pop("GMS"), fields.pop("GWk")
        if m.get_type() == "PARM" and fields["Name"] == "SIM_SPEEDUP":
            fields.pop("Value")
        out.append(repr(sorted(fields.items())))
    return out

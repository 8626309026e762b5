"""`make soak`: a simulated hour of the real autopilot process at speedup, with several clients at
once: a pilot flying it (GUIDED, arm, takeoff, gotos, RTL, over and over) and noisy clients sending
a random mix of valid and hostile datagrams (tests/fuzz/frames.py).

It checks, from the process's own exit report (--stats) and from outside: the process ran to the
end and exited 0, every control tick of the hour ran (10 ms ticks, 400 Hz physics steps), no
message handler raised, resident memory stayed flat, and the vehicle ended in a valid state.

    python -m tests.fuzz.soak --sim-hours 1 --speedup 60
"""
from __future__ import annotations

import argparse
import json
import math
import random
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

from firefly.autopilot.modes.numbers import ModeNumber

from ..sitl.conftest import free_udp_port
from .frames import PARAM_NAMES, FrameSource

REPO = Path(__file__).resolve().parents[2]
TICK_S = 0.01
PHYSICS_HZ = 400
MEMORY_GROWTH_LIMIT_MB = 8.0
NOISE_SYSTEM = 254  # the noisy clients' system id: anyone's but the ground station's (MAV_GCS_SYSID 255)
RADIO_PARAMS = (b"RC", b"FLTMODE", b"FS_THR_", b"MAV_GCS_SYSID", b"THR_DZ", b"PILOT_")
NOT_THE_RADIO = [name for name in PARAM_NAMES if not name.startswith(RADIO_PARAMS)]


def rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024.0
    return math.nan


class NoisyClient(threading.Thread):
    """Sends `rate` datagrams per wall second, valid and hostile, to the vehicle's port."""

    def __init__(self, seed: int, address: tuple, rate: float, stop: threading.Event):
        super().__init__(daemon=True)
        # Noise, not the ground station: from the GCS's id its random sticks (RC override, MANUAL_
        # CONTROL) and radio parameters would hold the throttle off neutral and turn the mode
        # switch, and the pilot could never arm, as on ArduCopter. The radio's hostile input is
        # walked in tests/sitl/test_state_attack.py and tests/fuzz/receive_fuzz.py.
        self.source = FrameSource(seed, source_system=NOISE_SYSTEM, param_names=NOT_THE_RADIO)
        self.address, self.rate, self.stop = address, rate, stop
        self.sent = 0

    def run(self) -> None:
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
            t0 = time.monotonic()
            while not self.stop.is_set():
                _, data = self.source.frame()
                try:
                    sock.sendto(data, self.address)
                except OSError:
                    pass
                self.sent += 1
                ahead = self.sent / self.rate - (time.monotonic() - t0)
                if ahead > 0:
                    self.stop.wait(ahead)


class Pilot(threading.Thread):
    """A pymavlink ground station that keeps flying the vehicle: heartbeats, and a round of
    GUIDED / arm / takeoff / two gotos / RTL whenever the vehicle is disarmed on the ground."""

    def __init__(self, listen_port: int, seed: int, stop: threading.Event, speedup: float = 1.0):
        super().__init__(daemon=True)
        self.port, self.rng, self.stop = listen_port, random.Random(seed), stop
        # a command round every 2 s of the vehicle's time: at 0.5 s of wall time, a soak at
        # speedup 40 gave the pilot only 6 rounds in two simulated minutes, and in about one run
        # in fifteen none of them armed the vehicle under the noisy clients' traffic
        self.round_wall_s = 2.0 / speedup
        self.rounds = 0  # arm-and-take-off attempts
        self.flights = 0  # times the vehicle was seen to go from disarmed to armed
        self.heartbeats_seen = 0

    def run(self) -> None:
        from pymavlink import mavutil
        conn = mavutil.mavlink_connection(f"udpin:127.0.0.1:{self.port}", source_system=255,
                                          source_component=190, dialect="ardupilotmega")
        mav = conn.mav
        last_hb, last_cmd, was_armed = 0.0, 0.0, False
        try:
            while not self.stop.is_set():
                msg = conn.recv_match(type="HEARTBEAT", blocking=True, timeout=0.5)
                now = time.monotonic()
                if now - last_hb >= 1.0:
                    mav.heartbeat_send(6, 8, 0, 0, 4)
                    last_hb = now
                if msg is None or msg.get_srcSystem() != 1:
                    continue
                self.heartbeats_seen += 1
                armed = bool(msg.base_mode & 128)
                self.flights += armed and not was_armed
                was_armed = armed
                if now - last_cmd < self.round_wall_s:
                    continue
                last_cmd = now
                if not armed:
                    mav.command_long_send(1, 1, 176, 0, 1, 4, 0, 0, 0, 0, 0)  # GUIDED
                    mav.command_long_send(1, 1, 400, 0, 1, 0, 0, 0, 0, 0, 0)  # arm
                    mav.command_long_send(1, 1, 22, 0, 0, 0, 0, 0, 0, 0, 20.0)  # takeoff 20 m
                    self.rounds += 1
                elif msg.custom_mode == 4 and self.rng.random() < 0.3:
                    mav.command_long_send(1, 1, 20, 0, 0, 0, 0, 0, 0, 0, 0)  # RTL
                elif msg.custom_mode == 4:
                    n, e = self.rng.uniform(-80, 80), self.rng.uniform(-80, 80)
                    mav.set_position_target_local_ned_send(0, 1, 1, 1, 0b110111111000, n, e, -20,
                                                           0, 0, 0, 0, 0, 0, 0, 0)
        finally:
            conn.close()


def soak(sim_hours: float, speedup: float, noisy_clients: int, rate: float, seed: int, progress=print) -> dict:
    duration = 3600.0 * sim_hours
    listen, out = free_udp_port(), free_udp_port()
    stop = threading.Event()
    with tempfile.TemporaryDirectory(prefix="firefly-soak-") as tmp:
        stats_path = Path(tmp) / "stats.json"
        proc = subprocess.Popen([sys.executable, "-m", "firefly.autopilot", "--listen", f"udp:127.0.0.1:{listen}",
                                 "--out", f"udp:127.0.0.1:{out}", "--speedup", str(speedup),
                                 "--duration", str(duration), "--stats", str(stats_path),
                                 "--state-dir", str(Path(tmp) / "state"), "--wipe", "--quiet"], cwd=REPO)
        pilot = Pilot(out, seed, stop, speedup)
        noisy = [NoisyClient(seed + 1 + k, ("127.0.0.1", listen), rate, stop) for k in range(noisy_clients)]
        for t in [pilot, *noisy]:
            t.start()
        rss, t0 = [], time.monotonic()
        expected_wall = duration / speedup
        try:
            while proc.poll() is None:
                if time.monotonic() - t0 > 3 * expected_wall + 60:
                    proc.kill()
                    raise RuntimeError(f"the autopilot had not finished the simulated {duration:g} s after "
                                       f"{time.monotonic() - t0:.0f} wall seconds")
                try:
                    rss.append((time.monotonic() - t0, rss_mb(proc.pid)))
                except OSError:
                    break
                if len(rss) % 10 == 0:
                    progress(f"soak: {time.monotonic() - t0:5.0f} s wall of ~{expected_wall:.0f}, "
                             f"rss {rss[-1][1]:.1f} MB, pilot rounds {pilot.rounds}, "
                             f"noise sent {sum(c.sent for c in noisy):,}")
                stop.wait(1.0)
        finally:
            stop.set()
            if proc.poll() is None:
                proc.terminate()
            code = proc.wait()
        stats = json.loads(stats_path.read_text()) if stats_path.exists() else None
    return {"exit_code": code, "stats": stats, "rss_mb": rss, "pilot_rounds": pilot.rounds,
            "pilot_flights": pilot.flights,
            "pilot_heartbeats_seen": pilot.heartbeats_seen, "noise_datagrams": sum(c.sent for c in noisy),
            "sim_s": duration, "wall_s": time.monotonic() - t0}


def verdict(result: dict) -> list[str]:
    """Every way the soak failed; empty when it passed."""
    problems = []
    if result["exit_code"] != 0:
        problems.append(f"the autopilot exited with {result['exit_code']}")
    stats = result["stats"]
    if stats is None:
        return problems + ["no exit report (--stats) was written"]
    if stats.get("exception"):
        problems.append(f"an exception escaped the loop: {stats['exception']}")
    duration = result["sim_s"]
    if stats["ticks"] != round(duration / TICK_S):
        problems.append(f"{stats['ticks']} control ticks ran, {round(duration / TICK_S)} expected")
    for v in stats["vehicles"]:
        if v["physics_steps"] != round(duration * PHYSICS_HZ):
            problems.append(f"vehicle {v['system_id']}: {v['physics_steps']} physics steps, "
                            f"{round(duration * PHYSICS_HZ)} expected")
        if v["counters"].get("handler_errors"):
            problems.append(f"vehicle {v['system_id']}: handlers raised {v['counters']['handler_errors']} "
                            f"times, last: {v.get('last_handler_error')}")
        if not v["state_finite"] or v["mode"] not in set(ModeNumber):
            problems.append(f"vehicle {v['system_id']} ended invalid: {v}")
    samples = [mb for t, mb in result["rss_mb"] if t > 10.0]  # after start-up and imports
    if len(samples) >= 8:
        quarter = len(samples) // 4
        growth = statistics.median(samples[-quarter:]) - statistics.median(samples[quarter:2 * quarter])
        result["rss_growth_mb"] = growth
        if growth > MEMORY_GROWTH_LIMIT_MB:
            problems.append(f"resident memory grew {growth:.1f} MB from the second quarter to the last")
    if result["pilot_flights"] < 1:
        problems.append("the pilot never got the vehicle armed")
    return problems


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="soak", description=__doc__.splitlines()[0])
    p.add_argument("--sim-hours", type=float, default=1.0)
    p.add_argument("--speedup", type=float, default=60.0)
    p.add_argument("--clients", type=int, default=3, help="noisy clients besides the pilot")
    p.add_argument("--rate", type=float, default=300.0, help="datagrams per wall second per noisy client")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--json", default=None)
    args = p.parse_args(argv)
    result = soak(args.sim_hours, args.speedup, args.clients, args.rate, args.seed,
                  lambda text: print(text, file=sys.stderr, flush=True))
    problems = verdict(result)
    stats = result["stats"] or {}
    summary = {k: v for k, v in result.items() if k != "rss_mb"} | {
        "rss_first_mb": result["rss_mb"][0][1] if result["rss_mb"] else None,
        "rss_last_mb": result["rss_mb"][-1][1] if result["rss_mb"] else None, "problems": problems}
    summary["stats"] = stats
    print(json.dumps(summary, indent=1))
    if args.json:
        Path(args.json).parent.mkdir(parents=True, exist_ok=True)
        Path(args.json).write_text(json.dumps(summary | {"rss_mb": result["rss_mb"]}, indent=1))
    print("soak: " + ("PASSED" if not problems else "FAILED: " + "; ".join(problems)), file=sys.stderr)
    return 0 if not problems else 1


if __name__ == "__main__":
    sys.exit(main())

"""`make bench`: Firefly's figures, measured, each a median of several runs with min and max.

Writes bench/results.json and BENCHMARKS.md. Nothing here is asserted; CI never times anything.
Run from the repository root: python bench/run.py [--runs 5] [--quick]
"""
from __future__ import annotations

import argparse
import asyncio
import datetime
import json
import math
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

from firefly.autopilot.control import compiled as compiled_cascade
from firefly.autopilot.rates import LoopRates
from firefly.autopilot.vehicle import Vehicle, VehicleConfig
from report import summary, write_markdown  # bench/report.py, beside this script

ROOT = Path(__file__).resolve().parents[1]


def progress(text: str) -> None:
    print(f"  {text}", flush=True)


# ----- control performance (deterministic: one run is the figure) ---------------------------------
def step_response() -> dict:
    v = Vehicle(VehicleConfig())
    v.run_until(0.1)
    v.set_mode(4)
    v.arm()
    t0 = v.time_s
    v.takeoff(10.0)
    samples = []
    while v.time_s < t0 + 20.0:
        v.step()
        samples.append((v.time_s - t0, -v.body.d_m))
    alt = [a for _, a in samples]
    peak = max(alt)
    rise_10 = next(t for t, a in samples if a >= 1.0)
    rise_90 = next(t for t, a in samples if a >= 9.0)
    outside = [t for t, a in samples if abs(a - 10.0) > 0.3]
    settle = max(outside) if outside else 0.0
    # 30 m GUIDED move north from the hover.
    t1 = v.time_s
    v.guided_goto(30.0, 0.0, -10.0)
    track = []
    while v.time_s < t1 + 30.0:
        v.step()
        b = v.body
        track.append((v.time_s - t1, b.n_m, math.hypot(b.n_m - 30.0, b.e_m)))
    arrive = next(t for t, _, err in track if err < 1.0)
    stays = max((t for t, _, err in track if err >= 1.0), default=0.0)
    return {
        "takeoff_10m": {"overshoot_pct": max(0.0, (peak - 10.0) / 10.0 * 100), "peak_m": peak,
                        "rise_time_10_90_s": rise_90 - rise_10, "settling_time_0p3m_s": settle,
                        "final_error_m": abs(alt[-1] - 10.0)},
        "guided_30m": {"first_within_1m_s": arrive, "stays_within_1m_after_s": stays,
                       "overshoot_m": max(n for _, n, _ in track) - 30.0,
                       "final_error_m": track[-1][2]},
    }


# ----- raw speed -----------------------------------------------------------------------------------
def headless_pattern(v: Vehicle) -> None:
    """Takeoff 10 m, a 20 m square, land: driven through the vehicle API, no MAVLink, no pacing."""
    v.set_mode(4)
    v.arm()
    v.takeoff(10.0)
    v.run_until(v.time_s + 8.0)
    for n, e in ((20, 0), (20, 20), (0, 20), (0, 0)):
        v.guided_goto(n, e, -10.0)
        v.run_until(v.time_s + 8.0)
    v.set_mode(9)
    while v.armed and v.time_s < 200:
        v.run_until(v.time_s + 1.0)


def rtf_headless(runs: int, compiled: bool = True) -> dict:
    values = []
    for i in range(runs):
        v = Vehicle(VehicleConfig(compiled=compiled))
        t0 = time.perf_counter()
        headless_pattern(v)
        wall = time.perf_counter() - t0
        values.append(v.time_s / wall)
        progress(f"rtf run {i + 1}/{runs} ({'compiled' if compiled else 'Python reference'}): "
                 f"{v.time_s:.1f} sim s in {wall:.2f} wall s = {values[-1]:.0f}x")
    return summary(values)


# ----- process start-up ------------------------------------------------------------------------------
def startup(runs: int) -> dict:
    from pymavlink import mavutil
    from firefly.groundstation.flight.autopilot_process import free_udp_port
    hb_times, armable_times = [], []
    # Byte-compile first, as a (non-editable) pip install does: a user's second start never
    # compiles sources, and this machine's PYTHONDONTWRITEBYTECODE=1 would otherwise make every run pay it.
    subprocess.run([sys.executable, "-m", "compileall", "-q", "sim", "autopilot", "groundstation"], cwd=ROOT,
                   check=True)
    for i in range(runs):
        port = free_udp_port()
        conn = mavutil.mavlink_connection(f"udpin:127.0.0.1:{port}", source_system=255)
        t0 = time.monotonic()
        proc = subprocess.Popen([sys.executable, "-m", "firefly.autopilot", "--listen", "udp:127.0.0.1:0",
                                 "--out", f"udp:127.0.0.1:{port}", "--quiet", "--wipe",
                                 "--state-dir", str(ROOT / "bench" / "tmp")], cwd=ROOT)
        hb = armable = None
        while (hb is None or armable is None) and time.monotonic() - t0 < 10:
            msg = conn.recv_match(type=["HEARTBEAT", "SYS_STATUS"], blocking=True, timeout=1)
            if msg is None:
                continue
            if hb is None and msg.get_type() == "HEARTBEAT":
                hb = time.monotonic() - t0
            if msg.get_type() == "SYS_STATUS" and msg.onboard_control_sensors_health & 0x10000000:
                armable = time.monotonic() - t0
        proc.terminate()
        proc.wait()
        conn.close()
        hb_times.append(hb)
        armable_times.append(armable)
        progress(f"start-up run {i + 1}/{runs}: heartbeat {hb:.3f} s, armable {armable:.3f} s")
    return {"startup_heartbeat_s": summary(hb_times), "startup_armable_s": summary(armable_times)}


# ----- the pytest plugin's fixture --------------------------------------------------------------------
def plugin_fixture(runs: int, speedups=("10", "inf")) -> dict:
    """Seconds from the `firefly` fixture's request to a connected MAVSDK System, through the
    plugin's own code (autopilot/testing): settings, a fresh process on free ports, its first
    state line, then `await firefly.mavsdk()`. And the same to a pymavlink connection that has
    seen a HEARTBEAT."""
    import tempfile
    from firefly.autopilot.testing.run import FireflyRun
    from firefly.autopilot.testing.settings import FireflySettings, parse_speedup
    from mavsdk import LogLevel, log_subscribe
    log_subscribe(lambda level, *_: level < LogLevel.WARN)
    subprocess.run([sys.executable, "-m", "compileall", "-q", "sim", "autopilot", "groundstation"], cwd=ROOT,
                   check=True)
    out = {}
    for speedup in speedups:
        to_mavsdk, to_pymavlink = [], []
        for i in range(runs + 1):  # the first run warms the imports (mavsdk, pymavlink): not counted
            for client in ("mavsdk", "pymavlink"):
                with tempfile.TemporaryDirectory(prefix="firefly-bench-") as tmp:
                    t0 = time.monotonic()
                    run = FireflyRun(FireflySettings(speedup=parse_speedup(speedup, "speedup"), seed=i), Path(tmp))
                    try:
                        run.start()
                        run.prepare()
                        vehicle = run.vehicles[0]
                        if client == "mavsdk":
                            asyncio.run(vehicle.mavsdk())
                        else:
                            vehicle.mavlink()
                        wall = time.monotonic() - t0
                    finally:
                        run.stop()
                if i > 0:
                    (to_mavsdk if client == "mavsdk" else to_pymavlink).append(wall)
            if i > 0:
                progress(f"fixture at speedup {speedup}, run {i}/{runs}: MAVSDK {to_mavsdk[-1]:.3f} s, "
                         f"pymavlink {to_pymavlink[-1]:.3f} s")
        out[speedup] = {"to_mavsdk_s": summary(to_mavsdk), "to_pymavlink_s": summary(to_pymavlink)}
    return out


# ----- campaigns: episodes per wall second ----------------------------------------------------------
CAMPAIGN_BENCH = """
[campaign]
scenario = "{scenario}"
policies = ["gig"]
episodes = {episodes}
flown = {flown}
speedup = 50
seed = 5
"""


def campaign_throughput(decided: int = 60, flown: int = 8) -> dict:
    """Episodes per wall second through the campaign backends (groundstation/campaign), decision-level
    (gig on the default world) and flown (at speedup 50), with 1 and 2 local workers and on a local
    Ray with 2 CPUs (its start-up included)."""
    import tempfile
    from firefly.groundstation.campaign.pool import run_local
    from firefly.groundstation.campaign.ray_backend import run_ray
    from firefly.groundstation.campaign.run import work
    from firefly.groundstation.campaign.spec import load_campaign
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "bench.toml"
        path.write_text(CAMPAIGN_BENCH.format(scenario=ROOT / "scenarios" / "default.toml", episodes=decided,
                                              flown=flown))
        campaign = load_campaign(path)
        kinds = {"decided": [t for t in campaign.tasks() if not t.flown],
                 "flown": [t for t in campaign.tasks() if t.flown]}
        for kind, tasks in kinds.items():
            jobs = [(t.id, (campaign, t)) for t in tasks]
            for backend, run in (("local 1 worker", lambda j, d: run_local(j, work, d, 1)),
                                 ("local 2 workers", lambda j, d: run_local(j, work, d, 2)),
                                 ("ray 2 CPUs", lambda j, d: run_ray(j, work, d, workers=2))):
                failed = []
                t0 = time.monotonic()
                run(jobs, lambda key, ok, value, attempts: failed.append(key) if not ok else None)
                wall = time.monotonic() - t0
                out[f"{kind}, {backend}"] = {"episodes": len(jobs), "wall_s": wall,
                                             "episodes_per_s": len(jobs) / wall, "failed": len(failed)}
                progress(f"campaign {kind}, {backend}: {len(jobs)} episodes in {wall:.1f} s = "
                         f"{len(jobs) / wall:.2f}/s ({len(failed)} failed)")
    return out


# ----- the MAVSDK flight of the SITL tests -----------------------------------------------------------
def mavsdk_flight(speedup: str) -> float | None:
    """Wall seconds for the flight at this speedup, or None if it failed."""
    from firefly.groundstation.flight.autopilot_process import start_autopilot
    from firefly.groundstation.flight.reference_flight import fly_takeoff_goto_rtl, north_east_m
    ap = start_autopilot(ROOT / "bench" / "tmp" / "state", speedup, cwd=ROOT)
    t0 = time.monotonic()
    try:
        seen = asyncio.run(fly_takeoff_goto_rtl(ap.mavsdk_url, timeout_scale=max(1.0, 10.0 / float(speedup))))
        wall = time.monotonic() - t0
        return wall if math.hypot(*north_east_m(seen["final"], seen["home"])) < 2.0 else None
    except (AssertionError, Exception) as exc:  # noqa: BLE001 - a failed flight is a data point
        progress(f"speedup {speedup}: flight failed ({exc})")
        return None
    finally:
        ap.stop()


def mavsdk_flights(runs: int, ladder: list[str], reference_runs: int) -> dict:
    from mavsdk import LogLevel, log_subscribe
    log_subscribe(lambda level, *_: level < LogLevel.WARN)
    best = None
    for speedup in ladder:
        walls = [mavsdk_flight(speedup) for _ in range(2)]
        progress(f"speedup {speedup}: {walls}")
        if any(w is None for w in walls):
            break
        best = speedup
    result = {"ladder_tried": ladder, "highest_passing_speedup": best}
    if best is not None:
        walls = [mavsdk_flight(best) for _ in range(runs)]
        ok = [w for w in walls if w is not None]
        progress(f"speedup {best}: {len(ok)}/{runs} passed, walls {[round(w, 2) for w in ok]}")
        result["at_highest"] = summary(ok) | {"passed": len(ok)}
    walls = []
    for i in range(reference_runs):
        walls.append(mavsdk_flight("1"))
        progress(f"speedup 1 run {i + 1}/{reference_runs}: {walls[-1]}")
    ok = [w for w in walls if w is not None]
    result["at_speedup_1"] = (summary(ok) | {"passed": len(ok)}) if ok else {"passed": 0}
    return result


# ----- many vehicles in one process at speedup 1 ------------------------------------------------------
def _children(pid: int) -> list[int]:
    try:
        return [int(c) for c in Path(f"/proc/{pid}/task/{pid}/children").read_text().split()]
    except OSError:
        return []


def _tree_sum(pid: int, own) -> float:
    """own(pid) summed over process `pid` and the processes it started (a fleet's parts)."""
    total = own(pid)
    for child in _children(pid):
        try:
            total += _tree_sum(child, own)
        except OSError:  # gone meanwhile
            pass
    return total


def _own_cpu_s(pid: int) -> float:
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def _own_rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024.0
    return math.nan


def _proc_cpu_s(pid: int) -> float:
    return _tree_sum(pid, _own_cpu_s)


def _proc_rss_mb(pid: int) -> float:
    return _tree_sum(pid, _own_rss_mb)


def swarm_trial(count: int, window_s: float, segments: int = 6) -> dict:
    """Run `autopilot --count N` at 1x; sim time against wall time over the window, and over each
    of its `segments` equal parts (for median, min and max), from SYSTEM_TIME of the first vehicle
    and of the last (past 255 vehicles the fleet runs in several processes, fleet.py: the slower
    of the two counts)."""
    from pymavlink import mavutil
    from firefly.autopilot.testing.run import free_port_bases
    # Every vehicle's own listening and --out ports (each base + 10k), all free and apart: with
    # ephemeral listening ports, one vehicle's --out could be another's socket, and the two
    # would talk to each other.
    listen, port = free_port_bases(2, count)
    watched = sorted({0, count - 1})
    conns = [mavutil.mavlink_connection(f"udpin:127.0.0.1:{port + 10 * k}", source_system=255) for k in watched]
    proc = subprocess.Popen([sys.executable, "-m", "firefly.autopilot", "--count", str(count), "--speedup", "1",
                             "--listen", f"udp:127.0.0.1:{listen}", "--out", f"udp:127.0.0.1:{port}", "--quiet",
                             "--serial0", "none", "--wipe", "--state-dir", str(ROOT / "bench" / "tmp" / "swarm")],
                            cwd=ROOT)
    import threading
    tracks: list[list[tuple[float, int]]] = [[] for _ in conns]  # (wall time at receipt, sim ms), per watched vehicle
    stop = threading.Event()

    def listen_to(conn, track):
        # one reader per vehicle: a socket read only now and then would hand over stale stamps
        while not stop.is_set():
            msg = conn.recv_match(type="SYSTEM_TIME", blocking=True, timeout=0.5)
            if msg is not None:
                track.append((time.monotonic(), msg.time_boot_ms))
    readers = [threading.Thread(target=listen_to, args=pair, daemon=True) for pair in zip(conns, tracks)]
    for reader in readers:
        reader.start()
    try:
        deadline = time.monotonic() + 300  # a fleet of 1,000 takes a while to build
        while not all(tracks) and time.monotonic() < deadline and proc.poll() is None:
            time.sleep(0.1)
        if not all(tracks):
            return {"count": count, "ok": False, "why": "no telemetry"}
        time.sleep(5.0)  # warm up
        t0 = time.monotonic()
        cpu_marks = [(t0, _proc_cpu_s(proc.pid))]
        for k in range(1, segments + 1):
            time.sleep(max(0.0, t0 + window_s * k / segments - time.monotonic()))
            cpu_marks.append((time.monotonic(), _proc_cpu_s(proc.pid)))
        last_mark = cpu_marks[-1][0]
        deadline = time.monotonic() + 60.0
        while time.monotonic() < deadline and not all(track[-1][0] >= last_mark for track in tracks):
            time.sleep(0.1)  # a stamp after the last mark (SYSTEM_TIME comes once a vehicle second)

        def at(track, wall):
            """The first stamp received at or after `wall`."""
            return next(((w, ms) for w, ms in track if w >= wall), None)
        bounds = [[at(track, wall) for wall, _ in cpu_marks] for track in tracks]
        if any(None in b for b in bounds):
            return {"count": count, "ok": False, "why": "telemetry stopped"}

        def ratio(a, b):  # the same stamp at both ends: none came within the segment, far behind
            return (b[1] - a[1]) / 1000.0 / (b[0] - a[0]) if b[0] > a[0] else 0.0

        def cpu(a, b):
            return (b[1] - a[1]) / (b[0] - a[0])
        wholes = [ratio(b[0], b[-1]) for b in bounds]
        points = bounds[max(range(len(bounds)), key=lambda i: abs(wholes[i] - 1.0))]  # the one further from 1x
        return {"count": count, "ratio": wholes[bounds.index(points)], "ok": all(abs(r - 1.0) <= 0.02 for r in wholes),
                "ratio_watched": wholes, "segment_s": window_s / segments,
                "ratio_segments": summary([ratio(a, b) for a, b in zip(points, points[1:])]),
                "cpu_core_fraction": cpu(cpu_marks[0], cpu_marks[-1]),
                "cpu_segments": summary([cpu(a, b) for a, b in zip(cpu_marks, cpu_marks[1:])]),
                "rss_mb": _proc_rss_mb(proc.pid)}
    finally:
        stop.set()
        for reader in readers:
            reader.join()
        proc.terminate()
        proc.wait()
        for conn in conns:
            conn.close()


def swarm(counts: list[int], window_s: float) -> dict:
    trials = []
    for count in counts:
        trial = swarm_trial(count, window_s)
        trials.append(trial)
        progress(f"swarm {count}: sim/wall {trial.get('ratio', 0):.3f}, cpu {trial.get('cpu_core_fraction', 0):.2f} "
                 f"core, rss {trial.get('rss_mb', 0):.0f} MB {trial.get('why', '')}")
        if not trial["ok"]:
            break
    passing = [t for t in trials if t["ok"]]
    best = passing[-1] if passing else None
    for _ in range(3):  # the reference for memory per added vehicle; a rare start fails to stream
        one = swarm_trial(1, min(window_s, 20.0))
        if one["ok"]:
            break
        progress(f"swarm 1: {one.get('why', 'sim/wall off by more than 2 %')}; again")
    out = {"trials": trials, "window_s": window_s, "single_vehicle": one}
    for t in passing if one["ok"] else ():
        # Per vehicle: the CPU share of the whole process; memory above a one-vehicle process.
        t["cpu_per_vehicle_core"] = t["cpu_core_fraction"] / t["count"]
        t["rss_per_added_vehicle_mb"] = (t["rss_mb"] - one["rss_mb"]) / max(t["count"] - 1, 1)
    if best:
        out["swarm_max_realtime"] = best["count"]
        out["cpu_per_vehicle_core"] = best.get("cpu_per_vehicle_core")
        out["rss_per_added_vehicle_mb"] = best.get("rss_per_added_vehicle_mb")
    return out


# ----- the 4-waypoint mission flown by `groundstation mission` ---------------------------------------
def mission_flight(speedup: str) -> float | None:
    t0 = time.monotonic()
    result = subprocess.run([sys.executable, "-m", "firefly.groundstation", "mission", str(ROOT / "examples" / "square.plan"),
                             "--speedup", speedup, "--plot", str(ROOT / "bench" / "tmp" / "mission.png")],
                            cwd=ROOT, capture_output=True, text=True, timeout=600)
    wall = time.monotonic() - t0
    return wall if result.returncode == 0 and "item 6/6" in result.stdout else None


def mission_flights(runs: int, speedups: list[str]) -> dict:
    out = {}
    for speedup in speedups:
        walls = [mission_flight(speedup) for _ in range(runs if speedup != "1" else max(1, runs // 2))]
        ok = [w for w in walls if w is not None]
        progress(f"mission at speedup {speedup}: {[round(w, 2) for w in ok]} ({len(ok)}/{len(walls)} passed)")
        out[speedup] = (summary(ok) | {"passed": len(ok)}) if ok else {"passed": 0}
    return out


# ----- report ----------------------------------------------------------------------------------------
def machine() -> dict:
    cpu = "unknown"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return {"cpu": cpu, "cores": os.cpu_count(), "python": platform.python_version(),
            "platform": platform.platform()}


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--reference-runs", type=int, default=None, help="runs of the speedup-1 flight (default --runs)")
    ap.add_argument("--ladder", default="10,20,50,100,200,500,inf")
    ap.add_argument("--skip", default="", help="comma list of: rtf,gcs,telemetry,dataflash,startup,plugin,campaign,mavsdk,mission,swarm")
    ap.add_argument("--swarm", default="50,100,150,200,250,500,750,1000",
                    help="vehicle counts tried, in order (past 255, a process per 255: autopilot/cli/fleet.py)")
    ap.add_argument("--batch", default="1,10,100,1000", help="vehicle counts of the batched step cost")
    ap.add_argument("--swarm-window", type=float, default=60.0, help="seconds each count is held")
    args = ap.parse_args()
    skip = set(filter(None, args.skip.split(",")))
    (ROOT / "bench" / "tmp").mkdir(parents=True, exist_ok=True)
    rates = LoopRates()
    results = {"date": datetime.date.today().isoformat(), "machine": machine(),
               "rates": {"physics_hz": rates.physics_hz, "attitude_hz": rates.attitude_hz,
                         "position_hz": rates.position_hz, "mode_hz": rates.mode_hz},
               "cascade": "compiled" if compiled_cascade.available() else "python"}
    print("step response ...", flush=True)
    results["step_response"] = step_response()
    save(results)
    if "rtf" not in skip:
        print("headless real-time factor ...", flush=True)
        results["rtf_headless"] = rtf_headless(args.runs)
        results["rtf_headless_python_reference"] = rtf_headless(args.runs, compiled=False)
        from instructions import headless_pattern_instructions
        print("instructions of the headless pattern (callgrind) ...", flush=True)
        results["headless_instructions"] = headless_pattern_instructions()
        if compiled_cascade.available():
            from step_cost import batched, single
            print("step cost ...", flush=True)
            results["step_cost_us"] = single(args.runs)
            results["step_cost_batched_us"] = batched([int(n) for n in args.batch.split(",")], args.runs)
        save(results)
    if "gcs" not in skip:
        from ground_station import measure as ground_station_load
        print("a ground station's load: all streams at 4 Hz, Firefly and (REF_DIR) ArduCopter ...", flush=True)
        results["ground_station"] = ground_station_load(args.runs, progress=progress)
        save(results)
    if "telemetry" not in skip:
        from telemetry import message_cost_us, rtf_with_client
        print("telemetry: real-time factor with a client, cost per message ...", flush=True)
        results["rtf_with_client"] = rtf_with_client(args.runs, progress=progress)
        results["telemetry_message_cost_us"] = message_cost_us(args.runs, progress=progress)
        save(results)
    if "dataflash" not in skip:
        from dataflash_cost import measure
        print("dataflash log cost: logging against not, headless and with a client ...", flush=True)
        results["dataflash_cost"] = measure(args.runs, progress=progress)
        save(results)
    if "startup" not in skip:
        print("start-up ...", flush=True)
        results["startup"] = startup(args.runs)
        save(results)
    if "plugin" not in skip:
        print("pytest plugin fixture start-up ...", flush=True)
        results["plugin_fixture"] = plugin_fixture(max(args.runs, 9))
        save(results)
    if "campaign" not in skip:
        print("campaign throughput ...", flush=True)
        results["campaign_throughput"] = campaign_throughput()
        save(results)
    if "mavsdk" not in skip:
        print("MAVSDK flight ...", flush=True)
        results["mavsdk_flight"] = mavsdk_flights(args.runs, args.ladder.split(","),
                                                  args.reference_runs or args.runs)
        save(results)
    if "swarm" not in skip:
        print("many vehicles at 1x ...", flush=True)
        results["swarm"] = swarm([int(c) for c in args.swarm.split(",")], args.swarm_window)
        save(results)
    if "mission" not in skip:
        print("4-waypoint mission ...", flush=True)
        results["mission_flight"] = mission_flights(args.runs, ["1", "10", "50"])
    save(results)
    print((ROOT / "BENCHMARKS.md").read_text())
    return 0


RESULTS = ROOT / "bench" / "results.json"
EARLIER = json.loads(RESULTS.read_text()) if RESULTS.exists() else {}  # as it was before this run


def save(results: dict) -> None:
    """Write results.json and BENCHMARKS.md; figures not measured this time keep their values from
    an earlier run, and `measured` says when and on what each section was last measured. Called
    after every section, so a section that crashes loses only itself."""
    stamp = f"{results['date']} on {results['machine']['cpu']}"
    fresh = {k: stamp for k in results if k not in ("date", "machine", "rates", "cascade", "measured")}
    merged = EARLIER | results
    merged["measured"] = EARLIER.get("measured", {}) | fresh
    RESULTS.write_text(json.dumps(merged, indent=1, default=str))
    write_markdown(merged, ROOT / "BENCHMARKS.md")


if __name__ == "__main__":
    sys.exit(main())

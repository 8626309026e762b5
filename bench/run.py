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
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from autopilot.rates import LoopRates  # noqa: E402
from autopilot.vehicle import Vehicle, VehicleConfig  # noqa: E402


def summary(values: list[float]) -> dict:
    return {"median": statistics.median(values), "min": min(values), "max": max(values), "runs": len(values)}


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


def rtf_headless(runs: int) -> dict:
    values = []
    for i in range(runs):
        v = Vehicle(VehicleConfig())
        t0 = time.perf_counter()
        headless_pattern(v)
        wall = time.perf_counter() - t0
        values.append(v.time_s / wall)
        progress(f"rtf run {i + 1}/{runs}: {v.time_s:.1f} sim s in {wall:.2f} wall s = {values[-1]:.0f}x")
    return summary(values)


def step_cost_us(n: int = 20000) -> dict:
    v = Vehicle(VehicleConfig())
    v.set_mode(4)
    v.arm()
    v.takeoff(10.0)
    v.run_until(5.0)
    cmd = v.cascade.omega_cmd
    t0 = time.perf_counter()
    for _ in range(n):
        v.sim.step(cmd)
    physics = (time.perf_counter() - t0) / n * 1e6
    t0 = time.perf_counter()
    for _ in range(n):
        v.step()
    total = (time.perf_counter() - t0) / n * 1e6
    return {"physics_step_us": physics, "control_per_physics_step_us": total - physics,
            "vehicle_step_us": total}


# ----- process start-up ------------------------------------------------------------------------------
def startup(runs: int) -> dict:
    from pymavlink import mavutil
    sys.path.insert(0, str(ROOT / "tests"))
    from sitl.conftest import free_udp_port
    hb_times, armable_times = [], []
    for i in range(runs):
        port = free_udp_port()
        conn = mavutil.mavlink_connection(f"udpin:127.0.0.1:{port}", source_system=255)
        t0 = time.monotonic()
        proc = subprocess.Popen([sys.executable, "-m", "autopilot", "--listen", "udp:127.0.0.1:0",
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


# ----- the MAVSDK flight of the SITL tests -----------------------------------------------------------
def mavsdk_flight(speedup: str) -> float | None:
    """Wall seconds for the flight at this speedup, or None if it failed."""
    sys.path.insert(0, str(ROOT))
    from tests.sitl.conftest import start_autopilot
    from tests.sitl.test_mavsdk_flight import fly_takeoff_goto_rtl
    ap = start_autopilot(ROOT / "bench" / "tmp", speedup)
    t0 = time.monotonic()
    try:
        seen = asyncio.run(fly_takeoff_goto_rtl(ap.mavsdk_url, timeout_scale=max(1.0, 10.0 / float(speedup))))
        wall = time.monotonic() - t0
        home, final = seen["home"], seen["final"]
        n = (final.latitude_deg - home.latitude_deg) * 111_320
        e = (final.longitude_deg - home.longitude_deg) * 111_320 * math.cos(math.radians(home.latitude_deg))
        return wall if math.hypot(n, e) < 2.0 else None
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
def _proc_cpu_s(pid: int) -> float:
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def _proc_rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024.0
    return math.nan


def swarm_trial(count: int, window_s: float) -> dict:
    """Run `autopilot --count N` at 1x; sim time of vehicle 1 (SYSTEM_TIME) against wall time."""
    from pymavlink import mavutil
    sys.path.insert(0, str(ROOT / "tests"))
    from sitl.conftest import free_udp_port
    port = free_udp_port()
    conn = mavutil.mavlink_connection(f"udpin:127.0.0.1:{port}", source_system=255)
    proc = subprocess.Popen([sys.executable, "-m", "autopilot", "--count", str(count), "--speedup", "1",
                             "--listen", "udp:127.0.0.1:0", "--out", f"udp:127.0.0.1:{port}", "--quiet",
                             "--wipe", "--state-dir", str(ROOT / "bench" / "tmp" / "swarm")], cwd=ROOT)
    try:
        def boot_ms():
            msg = conn.recv_match(type="SYSTEM_TIME", blocking=True, timeout=10)
            return msg.time_boot_ms if msg else None
        first = boot_ms()
        if first is None:
            return {"count": count, "ok": False, "why": "no telemetry"}
        warm_until = time.monotonic() + 5.0
        while time.monotonic() < warm_until:
            boot_ms()
        conn.recv_match(type="SYSTEM_TIME", blocking=True, timeout=10)
        w0, b0, c0 = time.monotonic(), boot_ms(), _proc_cpu_s(proc.pid)
        end = w0 + window_s
        while time.monotonic() < end:
            conn.recv_match(type="SYSTEM_TIME", blocking=True, timeout=1)
        w1, b1, c1 = time.monotonic(), boot_ms(), _proc_cpu_s(proc.pid)
        ratio = (b1 - b0) / 1000.0 / (w1 - w0)
        return {"count": count, "ratio": ratio, "ok": ratio >= 0.98, "cpu_core_fraction": (c1 - c0) / (w1 - w0),
                "rss_mb": _proc_rss_mb(proc.pid)}
    finally:
        proc.terminate()
        proc.wait()
        conn.close()


def swarm(counts: list[int], window_s: float) -> dict:
    trials = []
    for count in counts:
        trial = swarm_trial(count, window_s)
        trials.append(trial)
        progress(f"swarm {count}: sim/wall {trial.get('ratio', 0):.3f}, cpu {trial.get('cpu_core_fraction', 0):.2f} "
                 f"core, rss {trial.get('rss_mb', 0):.0f} MB")
        if not trial["ok"]:
            break
    passing = [t for t in trials if t["ok"]]
    best = passing[-1] if passing else None
    one = swarm_trial(1, min(window_s, 20.0))
    out = {"trials": trials, "window_s": window_s, "single_vehicle": one}
    if best:
        out["swarm_max_realtime"] = best["count"]
        out["cpu_per_vehicle_core"] = best["cpu_core_fraction"] / best["count"]
        out["rss_per_added_vehicle_mb"] = (best["rss_mb"] - one["rss_mb"]) / max(best["count"] - 1, 1)
    return out


# ----- the 4-waypoint mission flown by `groundstation mission` ---------------------------------------
def mission_flight(speedup: str) -> float | None:
    t0 = time.monotonic()
    result = subprocess.run([sys.executable, "-m", "groundstation", "mission", str(ROOT / "examples" / "square.plan"),
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


def write_markdown(results: dict, path: Path) -> None:
    r = results
    m, rates = r["machine"], r["rates"]
    sr = r["step_response"]
    lines = [
        "# Firefly benchmarks", "",
        f"Last run {r['date']} on {m['cpu']} ({m['cores']} cores), Python {m['python']}, {m['platform']}.",
        f"Rates: physics {rates['physics_hz']} Hz, attitude/rate loops {rates['attitude_hz']} Hz, "
        f"position loop {rates['position_hz']} Hz, flight modes {rates.get('mode_hz', rates['position_hz'])} Hz. "
        "Timing figures: median (min–max) of the runs shown.",
        "", "| figure | value |", "|---|---|",
    ]

    def fmt(s, unit="", digits=2):
        return f"{s['median']:.{digits}f}{unit} ({s['min']:.{digits}f}–{s['max']:.{digits}f}, n={s['runs']})"

    t = sr["takeoff_10m"]
    g = sr["guided_30m"]
    lines += [
        f"| 10 m takeoff: overshoot | {t['overshoot_pct']:.2f} % |",
        f"| 10 m takeoff: rise time 10–90 % | {t['rise_time_10_90_s']:.2f} s |",
        f"| 10 m takeoff: settling time (±0.3 m) | {t['settling_time_0p3m_s']:.2f} s |",
        f"| 30 m GUIDED move: first within 1 m | {g['first_within_1m_s']:.2f} s |",
        f"| 30 m GUIDED move: overshoot | {g['overshoot_m']:.2f} m |",
        f"| 30 m GUIDED move: final error | {g['final_error_m']:.3f} m |",
    ]
    if "rtf_headless" in r:
        lines.append(f"| rtf_headless (sim s per wall s, speedup inf, no client) | {fmt(r['rtf_headless'], '', 0)} |")
    if "step_cost_us" in r:
        c = r["step_cost_us"]
        lines.append(f"| step_cost_us: physics step / control per physics step | {c['physics_step_us']:.1f} µs / "
                     f"{c['control_per_physics_step_us']:.1f} µs |")
    if "startup" in r:
        lines.append(f"| startup_heartbeat_s | {fmt(r['startup']['startup_heartbeat_s'], ' s', 3)} |")
        lines.append(f"| startup_armable_s | {fmt(r['startup']['startup_armable_s'], ' s', 3)} |")
    if "mavsdk_flight" in r:
        f = r["mavsdk_flight"]
        if f.get("at_highest"):
            lines.append(f"| mavsdk_flight_wall_s at speedup {f['highest_passing_speedup']} (highest passing of "
                         f"{', '.join(f['ladder_tried'])}) | {fmt(f['at_highest'], ' s')} |")
        if f.get("at_speedup_1", {}).get("passed"):
            lines.append(f"| mavsdk_flight_wall_s at speedup 1 | {fmt(f['at_speedup_1'], ' s')} |")
    sw = r.get("swarm")
    if sw and sw.get("swarm_max_realtime"):
        lines.append(f"| swarm_max_realtime (vehicles in one process at 1x, sim time within 2 % of wall over "
                     f"{sw['window_s']:g} s; counts tried {', '.join(str(t['count']) for t in sw['trials'])}) | "
                     f"{sw['swarm_max_realtime']} |")
        lines.append(f"| swarm: CPU per vehicle / resident memory per added vehicle | "
                     f"{100 * sw['cpu_per_vehicle_core']:.2f} % of a core / {sw['rss_per_added_vehicle_mb']:.2f} MB |")
    for speedup, s in r.get("mission_flight", {}).items():
        if s.get("passed"):
            lines.append(f"| mission_4wp_wall_s (groundstation mission square.plan, process start to landed) "
                         f"at speedup {speedup} | {fmt(s, ' s')} |")
    path.write_text("\n".join(lines) + "\n")


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--reference-runs", type=int, default=None, help="runs of the speedup-1 flight (default --runs)")
    ap.add_argument("--ladder", default="10,20,50,100,200,inf")
    ap.add_argument("--skip", default="", help="comma list of: rtf,startup,mavsdk,mission,swarm")
    ap.add_argument("--swarm", default="25,50,75,100,125,150", help="vehicle counts tried, in order")
    ap.add_argument("--swarm-window", type=float, default=60.0, help="seconds each count is held")
    args = ap.parse_args()
    skip = set(filter(None, args.skip.split(",")))
    (ROOT / "bench" / "tmp").mkdir(parents=True, exist_ok=True)
    rates = LoopRates()
    results = {"date": datetime.date.today().isoformat(), "machine": machine(),
               "rates": {"physics_hz": rates.physics_hz, "attitude_hz": rates.attitude_hz,
                         "position_hz": rates.position_hz, "mode_hz": rates.mode_hz}}
    print("step response ...", flush=True)
    results["step_response"] = step_response()
    if "rtf" not in skip:
        print("headless real-time factor ...", flush=True)
        results["rtf_headless"] = rtf_headless(args.runs)
        results["step_cost_us"] = step_cost_us()
    if "startup" not in skip:
        print("start-up ...", flush=True)
        results["startup"] = startup(args.runs)
    if "mavsdk" not in skip:
        print("MAVSDK flight ...", flush=True)
        results["mavsdk_flight"] = mavsdk_flights(args.runs, args.ladder.split(","),
                                                  args.reference_runs or args.runs)
    if "swarm" not in skip:
        print("many vehicles at 1x ...", flush=True)
        results["swarm"] = swarm([int(c) for c in args.swarm.split(",")], args.swarm_window)
    if "mission" not in skip:
        print("4-waypoint mission ...", flush=True)
        results["mission_flight"] = mission_flights(args.runs, ["1", "10", "50"])
    # Figures skipped this time keep their last measured values from an earlier run.
    path = ROOT / "bench" / "results.json"
    previous = json.loads(path.read_text()) if path.exists() else {}
    results = previous | results
    path.write_text(json.dumps(results, indent=1, default=str))
    write_markdown(results, ROOT / "BENCHMARKS.md")
    print((ROOT / "BENCHMARKS.md").read_text())
    return 0


if __name__ == "__main__":
    sys.exit(main())

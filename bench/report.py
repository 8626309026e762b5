"""BENCHMARKS.md from bench/results.json: the machine, the loop rates, and each figure as
median (min–max, n) of its runs. Sections whose figures were never measured are left out."""
from __future__ import annotations

import statistics
from pathlib import Path


def summary(values: list[float]) -> dict:
    """A figure's record: median, min, max and the number of runs."""
    return {"median": statistics.median(values), "min": min(values), "max": max(values), "runs": len(values)}


def fmt(s: dict, unit: str = "", digits: int = 2) -> str:
    return f"{s['median']:.{digits}f}{unit} ({s['min']:.{digits}f}–{s['max']:.{digits}f}, n={s['runs']})"


def header(r: dict) -> list[str]:
    m, rates = r["machine"], r["rates"]
    mode_hz = rates.get("mode_hz", rates["position_hz"])
    how = {"compiled": "compiled (C, autopilot/control/_cascade.c)",
           "python": "the Python reference (the extension was not built)"}.get(r.get("cascade"), "Python")
    lines = ["# Firefly benchmarks", "",
            f"Last run {r['date']} on {m['cpu']} ({m['cores']} cores, shared with other work: timings are noisy), "
            f"Python {m['python']}, {m['platform']}.", "",
            f"Loop rates: physics {rates['physics_hz']} Hz; position and altitude loops {rates['position_hz']} Hz, "
            f"attitude (angle) and rate loops {rates['attitude_hz']} Hz, allocation with them — the cascade runs "
            f"{how}; flight modes (setpoint generation) and the land detector {mode_hz} Hz; failsafe checks "
            f"{mode_hz // 10} Hz.", "",
            "Timing figures: median (min–max, n = runs). Where a vehicle's time goes, and what was done "
            "about it: docs/performance.md."]
    if r.get("measured"):
        when = {}
        for section, stamp in r["measured"].items():
            when.setdefault(stamp, []).append(section)
        last = f"{r['date']} on {m['cpu']}"
        older = [f"{', '.join(sections)}: {stamp}" for stamp, sections in when.items() if stamp != last]
        if older:
            lines += ["", "Sections measured in an earlier run: " + "; ".join(older) + "."]
    return lines + [""]


def control_rows(sr: dict) -> list[str]:
    t, g = sr["takeoff_10m"], sr["guided_30m"]
    return [f"| 10 m takeoff: overshoot | {t['overshoot_pct']:.2f} % |",
            f"| 10 m takeoff: rise time 10–90 % | {t['rise_time_10_90_s']:.2f} s |",
            f"| 10 m takeoff: settling time (±0.3 m) | {t['settling_time_0p3m_s']:.2f} s |",
            f"| 30 m GUIDED move: first within 1 m | {g['first_within_1m_s']:.2f} s |",
            f"| 30 m GUIDED move: overshoot | {g['overshoot_m']:.2f} m |",
            f"| 30 m GUIDED move: final error | {g['final_error_m']:.3f} m |"]


def speed_rows(r: dict) -> list[str]:
    rows = []
    if "rtf_headless" in r:
        rows.append(f"| rtf_headless (sim s per wall s, speedup inf, no client) | {fmt(r['rtf_headless'], '', 0)} |")
    if "rtf_headless_python_reference" in r:
        rows.append(f"| rtf_headless with the Python reference cascade | "
                    f"{fmt(r['rtf_headless_python_reference'], '', 0)} |")
    if r.get("headless_instructions"):
        h = r["headless_instructions"]
        rows.append(f"| instructions of the headless pattern (callgrind, PYTHONHASHSEED=0; compare commits by this, "
                    f"not by wall time, on a busy machine) | {h['instructions_M']:.0f} M for {h['sim_s']:.0f} sim s "
                    f"= {h['per_sim_s_M']:.2f} M per sim s |")
    if "dataflash_cost" in r:
        d = r["dataflash_cost"]
        rows.append(f"| dataflash .BIN log cost: headless flight ticked at 100 Hz, logging / not (the recorder's tick "
                    f"{d['recorder_tick_us']:.1f} µs) | {fmt(d['headless_logging'], 'x', 0)} / {fmt(d['headless_none'], 'x', 0)} |")
        rows.append(f"| dataflash .BIN log cost: speedup inf with one client, disarmed, LOG_DISARMED 1 / "
                    f"LOG_BACKEND_TYPE 0 | {fmt(d['client_logging'], 'x', 0)} / {fmt(d['client_none'], 'x', 0)} |")
    if "rtf_with_client" in r:
        rows.append(f"| rtf_with_client (sim s per wall s, speedup inf, one client on --out, default streams, "
                    f"from the sim-time stamps the client receives) | {fmt(r['rtf_with_client'], '', 0)} |")
    if "telemetry_message_cost_us" in r:
        m = r["telemetry_message_cost_us"]
        rows.append(f"| telemetry cost per message sent (build + pack, the {m['kinds']} kinds of the default "
                    f"streams, no socket) | {fmt(m, ' µs', 2)} |")
    b = r.get("telemetry_before")
    if b:
        rows.append(f"| before the fast telemetry path (commit {b['commit']}): rtf_with_client / cost per message / "
                    f"250 vehicles at 1x, CPU / MAVSDK flight at speedup inf | {fmt(b['rtf_with_client'], '', 0)} / "
                    f"{fmt(b['telemetry_message_cost_us'], ' µs', 2)} / {b['swarm_250_cpu_core']:.2f} of a core / "
                    f"{fmt(b['mavsdk_flight_inf_wall_s'], ' s', 2)} |")
    b = r.get("telemetry_before_this_machine")
    if b:
        rows.append(f"| the same, alternated on this machine ({b['how'].split(', ')[-1]}): commit {b['commit']} against "
                    f"this tree: rtf_with_client / 250 vehicles at 1x, CPU (20 s trials) | "
                    f"{fmt(b['rtf_with_client'], '', 0)} against {fmt(b['rtf_with_client_now'], '', 0)} / "
                    f"{fmt(b['swarm_250_cpu_core'], '', 2)} against {fmt(b['swarm_250_cpu_core_now'], '', 2)} of a core |")
    c = r.get("step_cost_us")
    if c and "cascade_step_us" in c:
        rows += [f"| step_cost_us, one vehicle: physics step (compiled) | {fmt(c['physics_step_us'], ' µs', 3)} |",
                 f"| step_cost_us, one vehicle: control step (position + attitude + rate + allocation; "
                 f"cascade minus physics medians) | {c['control_step_us']:.3f} µs |",
                 f"| step_cost_us, one vehicle: physics + control (compiled cascade, 4 steps per call) | "
                 f"{fmt(c['cascade_step_us'], ' µs', 3)} |",
                 f"| step_cost_us, one vehicle: whole headless vehicle per physics step (cascade + Python at 100 Hz) | "
                 f"{fmt(c['vehicle_step_us'], ' µs', 2)} |",
                 f"| step_cost_us, Python reference: physics step / whole vehicle per physics step | "
                 f"{fmt(c['python_reference_physics_step_us'], ' µs', 2)} / "
                 f"{fmt(c['python_reference_vehicle_step_us'], ' µs', 2)} |"]
    return rows


def batched_table(b: dict) -> list[str]:
    lines = ["", "step_cost_us per vehicle and physics step when N hovering vehicles step together:", "",
             "| N | one C call for all (run_many) | one C call per vehicle | whole vehicles in turn (Python at 100 Hz included) |",
             "|---|---|---|---|"]
    for n, row in b.items():
        lines.append(f"| {n} | {fmt(row['run_many_us'], ' µs', 3)} | {fmt(row['one_call_each_us'], ' µs', 3)} | "
                     f"{fmt(row['whole_vehicles_us'], ' µs', 2)} |")
    return lines


def swarm_rows(sw: dict) -> list[str]:
    rows = [f"| swarm_max_realtime (vehicles of one `autopilot --count N` at 1x, default telemetry each, "
            f"sim time within 2 % of wall over {sw['window_s']:g} s; counts tried "
            f"{', '.join(str(t['count']) for t in sw['trials'])}; past 255, a process per 255: the first vehicle and the last watched) | "
            f"{sw['swarm_max_realtime']} |"]
    for t in sw["trials"]:
        if "cpu_per_vehicle_core" not in t:
            rows.append(f"| swarm at {t['count']}: sim/wall over the window (fails the 2 % test) | "
                        f"{t.get('ratio', 0):.3f} |")
            continue
        per = f"per {t.get('segment_s', 10):g} s"
        rows.append(f"| swarm at {t['count']}: sim/wall over the window; {per} | {t['ratio']:.4f}; "
                    f"{fmt(t['ratio_segments'], '', 4)} |")
        rows.append(f"| swarm at {t['count']}: CPU per vehicle (process CPU / N; {per}) / resident memory per "
                    f"added vehicle | {100 * t['cpu_per_vehicle_core']:.3f} % of a core "
                    f"({fmt({k: 100 * v / t['count'] if k != 'runs' else v for k, v in t['cpu_segments'].items()}, ' %', 3)}) "
                    f"/ {t['rss_per_added_vehicle_mb']:.2f} MB |")
    return rows


def flight_rows(r: dict) -> list[str]:
    rows = []
    throughput = r.get("campaign_throughput", {})
    for name, t in throughput.items():
        rows.append(f"| campaign throughput, {name} (gig, default world{', speedup 50' if 'flown' in name else ''}) | "
                    f"{t['episodes_per_s']:.2f} episodes/s ({t['episodes']} in {t['wall_s']:.1f} s, {t['failed']} failed) |")
    for kind in ("decided", "flown"):
        one, two = throughput.get(f"{kind}, local 1 worker"), throughput.get(f"{kind}, local 2 workers")
        if one and two:
            rows.append(f"| campaign {kind}: local 2 workers / 1 worker | {two['episodes_per_s'] / one['episodes_per_s']:.2f}x |")
    for speedup, figures in r.get("plugin_fixture", {}).items():
        rows.append(f"| pytest plugin at speedup {speedup}: `firefly` fixture request to a connected MAVSDK System "
                    f"(`await firefly.mavsdk()`) / to a pymavlink connection that saw a HEARTBEAT | "
                    f"{fmt(figures['to_mavsdk_s'], ' s', 3)} / {fmt(figures['to_pymavlink_s'], ' s', 3)} |")
    if "startup" in r:
        rows.append(f"| startup_heartbeat_s (process start to first HEARTBEAT on loopback; sources byte-compiled, as after a pip install) | {fmt(r['startup']['startup_heartbeat_s'], ' s', 3)} |")
        rows.append(f"| startup_armable_s (to SYS_STATUS with the PREARM bit healthy) | {fmt(r['startup']['startup_armable_s'], ' s', 3)} |")
    f = r.get("mavsdk_flight", {})
    if f.get("at_highest"):
        rows.append(f"| mavsdk_flight_wall_s at speedup {f['highest_passing_speedup']} (highest passing of "
                    f"{', '.join(f['ladder_tried'])}) | {fmt(f['at_highest'], ' s')} |")
    if f.get("at_speedup_1", {}).get("passed"):
        rows.append(f"| mavsdk_flight_wall_s at speedup 1 | {fmt(f['at_speedup_1'], ' s')} |")
    for speedup, s in r.get("mission_flight", {}).items():
        if s.get("passed"):
            rows.append(f"| mission_4wp_wall_s (groundstation mission square.plan, process start to landed) "
                        f"at speedup {speedup} | {fmt(s, ' s')} |")
    return rows


def ground_station_lead(g: dict | None) -> list[str]:
    """The user's case first: a ground station asking for every stream, against ArduCopter."""
    if not g:
        return []
    hz = g["request_hz"]
    lines = ["## Under a ground station's load", "",
             f"One client sending a GCS HEARTBEAT every second and asking for every stream at {hz} Hz "
             "(MAVProxy's request), reading time_boot_ms from raw frames; sim seconds per wall second, "
             "runs alternating vehicle by vehicle in one `make bench` (bench/ground_station.py).", "",
             "| vehicle | sim s per wall s |", "|---|---|"]
    if "arducopter_all_streams" in g:
        a = g["arducopter_all_streams"]
        lines.append(f"| ArduCopter SITL (`--speedup {a['speedup']}`), all streams at {hz} Hz | {fmt(a, 'x', 0)} |")
    lines += [f"| Firefly (`--speedup inf`), all streams at {hz} Hz | {fmt(g['firefly_all_streams'], 'x', 0)} |",
              f"| Firefly, default streams, no request | {fmt(g['firefly_no_request'], 'x', 0)} |"]
    if "ratio" in g:
        lines += ["", f"**Firefly / ArduCopter with every stream asked for: {g['ratio']:.1f}×** (medians)."]
    else:
        lines += ["", "ArduCopter was not measured in this run (set REF_DIR to build-arducopter-sitl's OUT_DIR)."]
    return lines + ["", "## Every figure", ""]


def write_markdown(r: dict, path: Path) -> None:
    lines = header(r) + ground_station_lead(r.get("ground_station")) + ["| figure | value |", "|---|---|"] \
        + control_rows(r["step_response"]) + speed_rows(r)
    sw = r.get("swarm")
    if sw and sw.get("swarm_max_realtime"):
        lines += swarm_rows(sw)
    lines += flight_rows(r)
    if r.get("step_cost_batched_us"):
        lines += batched_table(r["step_cost_batched_us"])
    path.write_text("\n".join(lines) + "\n")

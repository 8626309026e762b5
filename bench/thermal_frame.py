"""thermal_frame: the thermal camera (sim/thermal_camera.py) over the default scenario's fire.

Renders one frame looking straight down from 30 m above the fire, and the same with the scenario's
fire under a 5 m/s west wind (the plume, rising at 2 m/s, leans east); prints the cost per frame
(median, min and max of several timed runs of many frames) and the footprint; saves a false-colour
PNG (docs/thermal_frame.png). Then the live video's cost per frame, step by step as the vehicle
pays it (payload/thermal_video.py, io/thermal_video.py): render, false colour, H.264 encode and
MPEG-TS mux, sent by UDP to a port nobody reads. Nothing is asserted. Run from the repository root:
    python bench/thermal_frame.py [--runs 5] [--frames 200] [--png docs/thermal_frame.png]
"""
from __future__ import annotations

import argparse
import dataclasses
import time
from pathlib import Path

import numpy as np

from firefly.autopilot.io.thermal_video import VideoSender
from firefly.autopilot.payload.thermal_palette import colour
from firefly.autopilot.payload.thermal_video import BIT_RATE
from firefly.sim.scenario import load_scenario
from firefly.sim.thermal_camera import ThermalCameraSpec, footprint_corners, pose_from_attitude, render
from report import summary  # bench/report.py, beside this script

ROOT = Path(__file__).resolve().parents[1]
HEIGHT_M = 30.0


def cost_ms(world, spec, pose, runs: int, frames: int) -> dict:
    rng = np.random.default_rng(0)
    render(world, spec, pose, rng)  # warm: the rays are cached per spec
    per_frame = []
    for _ in range(runs):
        t0 = time.perf_counter()
        for _ in range(frames):
            render(world, spec, pose, rng)
        per_frame.append((time.perf_counter() - t0) / frames * 1e3)
    return summary(per_frame)


def video_cost_ms(world, spec, pose, runs: int, frames: int) -> dict:
    """Per frame [ms]: render, colour, encode (and send), and the three together, as the vehicle
    pays them each 1/fps of vehicle time; the encoder is warmed first (its first frames cost more)."""
    rng = np.random.default_rng(0)
    sender = VideoSender(("127.0.0.1", 9), spec.width_px, spec.height_px, spec.frame_rate_hz, BIT_RATE)
    index = 0
    for _ in range(20):
        sender.frame(colour(render(world, spec, pose, rng)), index)
        index += 1
    parts: dict[str, list[float]] = {"render": [], "colour": [], "encode": [], "total": []}
    for _ in range(runs):
        spent = dict.fromkeys(parts, 0.0)
        for _ in range(frames):
            t0 = time.perf_counter()
            image = render(world, spec, pose, rng)
            t1 = time.perf_counter()
            rgb = colour(image)
            t2 = time.perf_counter()
            sender.frame(rgb, index)
            t3 = time.perf_counter()
            index += 1
            spent["render"] += t1 - t0
            spent["colour"] += t2 - t1
            spent["encode"] += t3 - t2
            spent["total"] += t3 - t0
        for name, seconds in spent.items():
            parts[name].append(seconds / frames * 1e3)
    sent_kb = sender.counters["datagrams"] * 1316 / 1024
    sender.close()
    out = {name: summary(values) for name, values in parts.items()}
    out["kb_per_frame"] = sent_kb / index
    out["errors"] = sender.counters["encoder_errors"] + sender.counters["send_errors"]
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--frames", type=int, default=200)
    ap.add_argument("--png", type=Path, default=ROOT / "docs" / "thermal_frame.png")
    args = ap.parse_args()

    world = load_scenario(ROOT / "scenarios" / "default.toml").world
    fire = world.fires[0]
    windy = dataclasses.replace(world, plume_rise_m_s=2.0, wind_tilt=5.0 / 2.0, wind_to_deg=90.0)
    spec = ThermalCameraSpec()
    pose = pose_from_attitude(fire.n_m, fire.e_m, HEIGHT_M)

    cost = cost_ms(world, spec, pose, args.runs, args.frames)
    corners = footprint_corners(spec, pose)
    width, height = corners[1, 1] - corners[0, 1], corners[0, 0] - corners[3, 0]
    print(f"render {spec.width_px}x{spec.height_px}: {cost['median']:.2f} ms per frame "
          f"({cost['min']:.2f}-{cost['max']:.2f}, {args.runs} runs of {args.frames} frames)")
    print(f"footprint at {HEIGHT_M:g} m: {width:.2f} m east-west x {height:.2f} m north-south, "
          f"{width / spec.width_px * 100:.1f} cm per pixel")
    video = video_cost_ms(world, spec, pose, args.runs, args.frames)
    print("video per frame: " + ", ".join(
        f"{name} {video[name]['median']:.2f} ms ({video[name]['min']:.2f}-{video[name]['max']:.2f})"
        for name in ("render", "colour", "encode", "total"))
        + f"; {video['kb_per_frame']:.1f} kB sent a frame, {video['errors']} errors")
    per_s = video["total"]["median"] * spec.frame_rate_hz
    print(f"  at {spec.frame_rate_hz:g} frames per vehicle second: {per_s:.0f} ms of work per vehicle second "
          f"(the video alone caps a run at {1000 / per_s:.0f}x real time)")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    frames = [(world, "default scenario, no wind"), (windy, "west wind 5 m/s, plume rise 2 m/s")]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.4), constrained_layout=True)
    extent = (corners[0, 1], corners[1, 1], corners[3, 0], corners[0, 0])  # west, east, south, north
    for ax, (w, title) in zip(axes, frames):
        image = render(w, spec, pose, np.random.default_rng(1))
        shown = ax.imshow(image, cmap="inferno", extent=extent, origin="upper")
        ax.plot(fire.e_m, fire.n_m, "c+", markersize=12, label="fire")
        ax.set_title(f"{title}\npeak {image.max():.1f} C", fontsize=10)
        ax.set_xlabel("east [m]")
        ax.set_ylabel("north [m]")
        ax.legend(loc="lower left", fontsize=8)
        fig.colorbar(shown, ax=ax, label="temperature [deg C]")
    fig.suptitle(f"Thermal camera ({spec.width_px}x{spec.height_px}, {spec.hfov_deg:g} deg), "
                 f"nadir from {HEIGHT_M:g} m over the fire", fontsize=11)
    args.png.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.png, dpi=90)
    print(f"wrote {args.png}")


if __name__ == "__main__":
    main()

"""`groundstation demo`: take off, fly a square, land — the flight `make run` shows until the
fire-localization mission exists. Prints each leg in vehicle terms and writes a PNG of the track."""
from __future__ import annotations

import asyncio
import time
from pathlib import Path

from .vehicle_link import VehicleLink


async def fly_square(url: str, side_m: float, alt_m: float, plot: Path | None, timeout_scale: float) -> int:
    t0 = time.monotonic()
    link = await VehicleLink.connect(url)
    track = []
    record = lambda p: track.append(link.north_east_m(p) + (p.relative_altitude_m,))  # noqa: E731
    try:
        await link.wait_armable(15 * timeout_scale)
        print(f"[{time.monotonic() - t0:5.1f} s] vehicle armable, home "
              f"{link.home.latitude_deg:.6f}, {link.home.longitude_deg:.6f}, {link.home.absolute_altitude_m:.1f} m AMSL")
        await link.takeoff(alt_m, 30 * timeout_scale)
        print(f"[{time.monotonic() - t0:5.1f} s] took off to {alt_m:g} m")
        corners = [(side_m, 0.0), (side_m, side_m), (0.0, side_m), (0.0, 0.0)]
        for i, (n, e) in enumerate(corners, 1):
            reached = await link.goto_ned(n, e, alt_m, 1.0, 60 * timeout_scale, record, settle_m_s=0.5)
            rn, re = link.north_east_m(reached)
            print(f"[{time.monotonic() - t0:5.1f} s] corner {i}/4 reached: N {rn:6.2f} m  E {re:6.2f} m  "
                  f"alt {reached.relative_altitude_m:5.2f} m")
        await link.land_and_disarm(120 * timeout_scale, on_position=record)
        final = await link.position()
        fn, fe = link.north_east_m(final)
        print(f"[{time.monotonic() - t0:5.1f} s] landed and disarmed at N {fn:.2f} m E {fe:.2f} m "
              f"({(fn * fn + fe * fe) ** 0.5:.2f} m from home)")
    finally:
        link.close()
    if plot is not None and track:
        write_track_png(track, corners, plot)
        print(f"track plot: {plot}")
    return 0


def write_track_png(track, corners, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5, 5))
    ax.plot([p[1] for p in track], [p[0] for p in track], lw=1.5, label="flown")
    ax.plot([0] + [c[1] for c in corners], [0] + [c[0] for c in corners], "k--", lw=0.8, label="planned")
    ax.plot(0, 0, "g^", ms=10, label="home")
    ax.set_xlabel("east [m]")
    ax.set_ylabel("north [m]")
    ax.set_aspect("equal")
    ax.legend(loc="best")
    ax.set_title("Firefly demo flight")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def run(url: str | None, speedup: float, side_m: float, alt_m: float, plot: Path | None) -> int:
    from .autopilot_process import AutopilotProcess
    if url:
        return asyncio.run(fly_square(url, side_m, alt_m, plot, 1.0))
    with AutopilotProcess(speedup) as ap:
        print(f"started autopilot (speedup {speedup:g}), MAVSDK connecting on {ap.url}")
        return asyncio.run(fly_square(ap.url, side_m, alt_m, plot, 1.0))

"""`groundstation demo`: take off, fly a square, land — a first look at the vehicle flying. Prints
each leg in vehicle terms and writes a PNG of the track."""
from __future__ import annotations

import time
from pathlib import Path

from .autopilot_process import run_flight
from .mission import write_plot
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
        write_plot([(0.0, 0.0)] + corners, track, plot, "Firefly demo flight")
        print(f"track plot: {plot}")
    return 0


def run(url: str | None, speedup: float, side_m: float, alt_m: float, plot: Path | None) -> int:
    return run_flight(lambda at: fly_square(at, side_m, alt_m, plot, 1.0), url, speedup)

"""Fly a square waypoint mission over MAVLink and reduce the flown track to a few figures.

The same code flies the reference ArduCopter SITL (to record its figures) and Firefly (the SITL
test compares them), so both are measured alike:

    python -m tests.parity.square --url udpin:127.0.0.1:14903 [--speed 500] [--side 40]

Mission: take off to ALT_M, then the corners C1..C4 of a square (C1 north of home, turning
clockwise) and back to C1, which ends the mission (a stop). Each corner but the last is flown
through (the next waypoint is known), so it is where the navigator blends the two legs.

Figures (metres, seconds of the vehicle's own time_boot_ms):
- corners: per blended corner, the closest approach of the track to it and the side it was
  passed on (negative = inside the square, positive = outside);
- legs: per leg, the time from reaching its start to reaching its end (MISSION_ITEM_REACHED),
  the largest cross-track error along the middle of the leg (more than MID_MARGIN_M from both
  ends) and over the whole leg window;
- path_m: horizontal path flown from the takeoff's end to the last waypoint reached.
"""
from __future__ import annotations

import argparse
import json
import math
import time

from pymavlink import mavutil

from tests.sitl.pymav import Gcs

mav = mavutil.mavlink
ALT_M = 10.0
MID_MARGIN_M = 10.0
EARTH_RADIUS_M = 6378137.0
GUIDED, AUTO = 4, 3
FRAME_RELATIVE_ALT = 3


def corners(side_m: float, turn_deg: float = 90.0) -> list[tuple[float, float]]:
    """Corner points (north, east) of the course relative to home: C1 side_m north of home, then
    legs of side_m each turning right by turn_deg (90 = a square), closed back to C1."""
    if turn_deg == 90.0:
        pts = [(side_m, 0.0), (side_m, side_m), (0.0, side_m), (0.0, 0.0)]
    else:  # a triangle-like course: C1 north, C2 after turning turn_deg, C3 back towards home
        heading = math.radians(turn_deg)
        c2 = (side_m + side_m * math.cos(heading), side_m * math.sin(heading))
        pts = [(side_m, 0.0), c2, (0.0, 0.0)]
    return pts + [pts[0]]


def ne_to_latlon(home: tuple[float, float], n: float, e: float) -> tuple[int, int]:
    lat0, lon0 = home
    lat = lat0 + math.degrees(n / EARTH_RADIUS_M)
    lon = lon0 + math.degrees(e / (EARTH_RADIUS_M * math.cos(math.radians(lat0))))
    return round(lat * 1e7), round(lon * 1e7)


def latlon_to_ne(home: tuple[float, float], lat: float, lon: float) -> tuple[float, float]:
    lat0, lon0 = home
    return (math.radians(lat - lat0) * EARTH_RADIUS_M,
            math.radians(lon - lon0) * EARTH_RADIUS_M * math.cos(math.radians(lat0)))


class Link(Gcs):
    """A ground station that also hands every message it reads to `on_message` (the recorder)."""

    def __init__(self, url: str, timeout: float = 60.0):
        super().__init__(url, timeout)
        self.sys, self.comp = self.conn.target_system, self.conn.target_component
        self.on_message = None

    def recv(self, types, timeout: float = 5.0, condition=None):
        types = (types,) if isinstance(types, str) else types
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            m = self.conn.recv_match(blocking=True, timeout=min(0.5, deadline - time.monotonic()))
            if m is None:
                continue
            if self.on_message is not None:
                self.on_message(m)
            if m.get_type() in types and (condition is None or condition(m)):
                return m
        return None

    def set_param(self, name: str, value: float) -> None:
        for _ in range(5):
            self.mav.param_set_send(self.sys, self.comp, name.encode(), value, mav.MAV_PARAM_TYPE_REAL32)
            echo = self.recv(("PARAM_VALUE",), 3, lambda m: m.param_id == name)
            if echo is not None and math.isclose(echo.param_value, value, rel_tol=1e-5):
                return
        raise RuntimeError(f"{name} not set")

    def upload(self, items: list[tuple]) -> None:
        """items: (command, frame, p1..p4, lat_e7, lon_e7, alt); seq 0 is home."""
        self.mav.mission_count_send(self.sys, self.comp, len(items), 0)
        while True:
            m = self.recv(("MISSION_REQUEST_INT", "MISSION_REQUEST", "MISSION_ACK"), 10)
            if m is None:
                raise RuntimeError("mission upload stalled")
            if m.get_type() == "MISSION_ACK":
                if m.type != 0:
                    raise RuntimeError(f"mission refused: {m.type}")
                return
            cmd, frame, p1, p2, p3, p4, x, y, z = items[m.seq]
            self.mav.mission_item_int_send(self.sys, self.comp, m.seq, frame, cmd, 0, 1, p1, p2, p3, p4,
                                           x, y, z, 0)


def wait_home(link: Link, deadline: float):
    """The vehicle's HOME_POSITION, asked for until it has one (a position fix)."""
    while time.monotonic() < deadline:
        link.mav.command_long_send(link.sys, link.comp, mav.MAV_CMD_REQUEST_MESSAGE, 0,
                                   mav.MAVLINK_MSG_ID_HOME_POSITION, 0, 0, 0, 0, 0, 0)
        hp = link.recv(("HOME_POSITION",), 3)
        if hp is not None:
            return hp
    raise RuntimeError("no HOME_POSITION")


def arm_in_guided(link: Link, deadline: float) -> None:
    """GUIDED and armed, retried: the reference arms only once its EKF is happy."""
    while time.monotonic() < deadline:
        if link.command(mav.MAV_CMD_DO_SET_MODE, 1, GUIDED) == 0 and \
                link.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1) == 0:
            return
        link.recv(("HEARTBEAT",), 2)
    raise RuntimeError("could not arm")


def record_positions(link: Link, home: tuple, samples: list) -> None:
    """Append (time_s, north, east, relative alt) of every GLOBAL_POSITION_INT to `samples`,
    at 20 Hz of the vehicle's time."""
    def on_message(m) -> None:
        if m.get_type() == "GLOBAL_POSITION_INT":
            n, e = latlon_to_ne(home, m.lat * 1e-7, m.lon * 1e-7)
            samples.append((m.time_boot_ms / 1000.0, n, e, m.relative_alt / 1000.0))
    link.on_message = on_message
    link.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_GLOBAL_POSITION_INT, 50000)


def fly(url: str, speed_cms: float = 500.0, side_m: float = 40.0, turn_deg: float = 90.0,
        timeout: float = 600.0) -> dict:
    """Fly the course; returns the raw record: home, corner points, samples and item times."""
    link = Link(url)
    link.set_param("WPNAV_SPEED", speed_cms)
    deadline = time.monotonic() + timeout
    hp = wait_home(link, deadline)
    home_ll = (hp.latitude * 1e-7, hp.longitude * 1e-7)
    samples: list[tuple[float, float, float, float]] = []  # (t_s, n, e, relative alt)
    reached: dict[int, float] = {}
    record_positions(link, home_ll, samples)
    positions = link.on_message

    def on_message(m) -> None:
        positions(m)
        if m.get_type() == "MISSION_ITEM_REACHED" and m.seq not in reached and samples:
            reached[m.seq] = samples[-1][0]

    link.on_message = on_message
    pts = corners(side_m, turn_deg)
    items = [(16, 0, 0, 0, 0, 0, hp.latitude, hp.longitude, 0.0),
             (22, FRAME_RELATIVE_ALT, 0, 0, 0, 0, 0, 0, ALT_M)]
    for n, e in pts:
        lat, lon = ne_to_latlon(home_ll, n, e)
        items.append((16, FRAME_RELATIVE_ALT, 0, 0, 0, 0, lat, lon, ALT_M))
    link.upload(items)
    arm_in_guided(link, deadline)
    if link.command(mav.MAV_CMD_DO_SET_MODE, 1, AUTO) != 0:
        raise RuntimeError("AUTO refused")
    if link.command(mav.MAV_CMD_MISSION_START, 0, 0) != 0:
        raise RuntimeError("MISSION_START refused")
    last = len(items) - 1
    while last not in reached and time.monotonic() < deadline:
        link.recv(("MISSION_ITEM_REACHED",), 5)
    if last not in reached:
        raise RuntimeError(f"mission not finished: reached {sorted(reached)}")
    end = reached[last] + 3.0
    link.recv(("GLOBAL_POSITION_INT",), 30, lambda m: m.time_boot_ms / 1000.0 >= end)
    link.command(mav.MAV_CMD_DO_SET_MODE, 1, GUIDED)
    link.conn.close()
    return {"corners": pts, "samples": samples, "reached": reached, "first_wp_seq": 2}


def _point_segment(p, a, b) -> tuple[float, float]:
    """(along-track distance from a, signed cross-track: + = right of a->b) of p."""
    dn, de = b[0] - a[0], b[1] - a[1]
    length = math.hypot(dn, de)
    un, ue = dn / length, de / length
    rn, re = p[0] - a[0], p[1] - a[1]
    return rn * un + re * ue, re * un - rn * ue


def reduce(record: dict) -> dict:
    """The figures of one flight (see the module's docstring)."""
    pts = [tuple(p) for p in record["corners"]]
    samples = record["samples"]
    reached = {int(k): v for k, v in record["reached"].items()}
    first = record["first_wp_seq"]
    home = (0.0, 0.0)
    starts = [home] + pts[:-1]
    # The square is flown clockwise (turning right), so inside = right of every leg.
    legs, corner_figs = [], []
    for i, (a, b) in enumerate(zip(starts, pts)):
        seq = first + i
        t0, t1 = reached[seq - 1], reached[seq]
        window = [s for s in samples if t0 <= s[0] <= t1]
        length = math.hypot(b[0] - a[0], b[1] - a[1])
        xt_mid = xt_all = 0.0
        for s in window:
            along, cross = _point_segment((s[1], s[2]), a, b)
            xt_all = max(xt_all, abs(cross))
            if MID_MARGIN_M <= along <= length - MID_MARGIN_M:
                xt_mid = max(xt_mid, abs(cross))
        legs.append({"from": list(a), "to": list(b), "time_s": round(t1 - t0, 2),
                     "cross_track_mid_m": round(xt_mid, 2), "cross_track_max_m": round(xt_all, 2)})
        if i + 1 < len(pts):  # a blended corner: flown through towards the next leg
            t_next = reached[seq + 1]
            near = [s for s in samples if t0 <= s[0] <= t_next]
            best = min(near, key=lambda s: math.hypot(s[1] - b[0], s[2] - b[1]))
            dist = math.hypot(best[1] - b[0], best[2] - b[1])
            _, cross_in = _point_segment((best[1], best[2]), a, b)
            _, cross_out = _point_segment((best[1], best[2]), b, pts[i + 1])
            inside = cross_in + cross_out > 0.0
            corner_figs.append({"corner": list(b), "closest_m": round(dist, 2),
                                "signed_m": round(-dist if inside else dist, 2)})
    t_start, t_end = reached[first - 1], reached[first + len(pts) - 1]
    flown = [s for s in samples if t_start <= s[0] <= t_end]
    path = sum(math.hypot(q[1] - p[1], q[2] - p[2]) for p, q in zip(flown, flown[1:]))
    planned = sum(math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip(starts, pts))
    return {"corners": corner_figs, "legs": legs, "path_m": round(path, 1),
            "planned_m": round(planned, 1), "mission_time_s": round(t_end - t_start, 2)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--url", required=True)
    ap.add_argument("--speed", type=float, default=500.0, help="WPNAV_SPEED [cm/s]")
    ap.add_argument("--side", type=float, default=40.0)
    ap.add_argument("--turn", type=float, default=90.0)
    ap.add_argument("--raw", help="also write the raw record (samples) here")
    args = ap.parse_args()
    record = fly(args.url, args.speed, args.side, args.turn)
    if args.raw:
        with open(args.raw, "w") as f:
            json.dump(record, f)
    print(json.dumps(reduce(record), indent=1))


if __name__ == "__main__":
    main()

"""The ground stations' plans (examples/plans/, made by groundstation/plans/ with QGroundControl's
and Mission Planner's rules) flown in AUTO from a fresh boot at the same home: a QGC survey with
the camera triggered by distance, a corridor scan, a structure scan and a Mission Planner mission
with spline waypoints and a landing sequence after DO_LAND_START.

Each plan is uploaded as the ground station would upload it (MISSION_ITEM_INT, NaN where QGC
leaves a parameter unset), armed in GUIDED and started by MISSION_START, and watched until the
vehicle has landed and disarmed. Before the flight CAM1_TYPE is set to 1 (a servo camera) and the
vehicle rebooted, as a user does, so that DO_SET_CAM_TRIGG_DIST triggers the camera and each
photo shows in CAMERA_FEEDBACK.

Facts per plan: the items reached in order (the vehicle's "Reached command #N" texts; its
MISSION_ITEM_REACHED messages in the same order), the vehicle seconds from MISSION_START to the
takeoff's end and from there to each item reached, the height at each, MISSION_CURRENT as it changed, the texts; the flown track
(points 2 m apart along it, metres north and east of home) compared as a path; where it landed.
The camera's facts are apart, under triggers.*: how many CAMERA_FEEDBACKs and where.
"""
from __future__ import annotations

import math
import time
from pathlib import Path

from firefly.groundstation.flight.mission_files import load_mission

from ..client import Client, ProbeTimeout, mav
from ..facts import PathTol, Tol, Trace
from ..targets import HOME, ready
from .mission_navgeo import fly, streaming
from .surface_mission import Geometry, held_seqs
from .texts import said

AREA = "mission_plans"
PLANS_DIR = Path(__file__).resolve().parents[3] / "examples" / "plans"
PLANS = {"survey": "survey.plan", "corridor": "corridor.plan", "structure": "structure.plan",
         "structure_roi": "structure_roi.waypoints", "splines": "splines.waypoints"}
CAMERA_TYPE = 1  # a servo camera: DO_SET_CAM_TRIGG_DIST triggers it, CAMERA_FEEDBACK reports each photo
REBOOT_WAIT_S = 60.0  # wall seconds for a rebooted vehicle to speak again
CLOCK_BEFORE_REBOOT_MS = 6000
LIMIT_S = 400.0
TRACK_STEP_M = 2.0

TOL_TRACK = PathTol(abs=1.0, why="the flown tracks, legs, turns and splines: issue 29's bar")
TOL_PHOTOS = Tol(abs=1.0, rel=0.1, why="photos taken: ArduCopter itself took 57 and then 62 on structure_roi in "
                                      "two recordings (when a distance counts as travelled depends on its timing)")
TOL_TRIGGERS = PathTol(abs=1.0, points=True, why="each photo taken within a metre of one of the other's")
TOL_TAKEOFF_S = Tol(abs=1.0, why="the climb at the same WPNAV_SPEED_UP; where each starts braking for the height")
TOL_REACHED_S = Tol(abs=1.5, rel=0.02, why="time from the takeoff's end: the same speeds and accelerations, shaped "
                                           "by each controller's jerk limits at starts, stops and corners")
TOL_ALT = Tol(abs=1.0, why="height when an item counts as reached: the climb's shape near its end differs")
TOL_LANDED = Tol(abs=1.0, why="where it touched down: the descent's drift")


def _boot(target) -> tuple[Client, bool]:
    """A fresh vehicle with CAM1_TYPE set and rebooted to take it (ArduCopter makes its camera
    backends at boot; a parameter file at boot did not set it on the reference); whether the
    parameter was taken."""
    client = target.boot()
    client.request_streams(2)  # fewer messages to read past for the echo
    # asked again if its echo was missed: another PARAM_VALUE can come between
    taken = any(client.set_param("CAM1_TYPE", CAMERA_TYPE) for _ in range(3))
    # the old clock well past the new one's first seconds, so that its going back shows
    client.wait(lambda: client.now_ms > CLOCK_BEFORE_REBOOT_MS, 10, what="vehicle time")
    if taken and client.command(mav.MAV_CMD_PREFLIGHT_REBOOT_SHUTDOWN, 1) == mav.MAV_RESULT_ACCEPTED:
        client = _rebooted(client)
    return streaming(client), taken


def _rebooted(client: Client) -> Client:
    """A new client once the vehicle's boot clock has gone back (it has restarted), ready to arm.
    In wall time: the restarted vehicle's clock starts below this client's and streams nothing
    until asked, so it is asked often."""
    before, restarted = client.now_ms, []

    def watch(msg):
        stamp = getattr(msg, "time_boot_ms", None)
        if stamp is not None and msg.get_type() != "TIMESYNC" and stamp + 2000 < before:
            restarted.append(stamp)
    wall0 = asked = time.monotonic()
    with client.listening(watch):
        while not restarted:
            if time.monotonic() - wall0 > REBOOT_WAIT_S:
                raise ProbeTimeout(f"not back within {REBOOT_WAIT_S:g} s of a reboot")
            client.pump(0.05)
            if time.monotonic() - asked > 0.5:
                client.request_streams(2)
                asked = time.monotonic()
    url = client.url
    client.close()
    return ready(Client(url, 2), 2)


def wire_items(plan) -> list[tuple]:
    """(command, frame, p1..p4, x, y, z) as MISSION_ITEM_INT carries them."""
    out = []
    for it in plan.items:
        scale = 1 if it.frame == mav.MAV_FRAME_MISSION else 1e7
        out.append((it.command, it.frame, *it.params, int(round(it.lat_deg * scale)),
                    int(round(it.lon_deg * scale)), it.alt_m))
    return out


def along_track(points: list, step: float = TRACK_STEP_M) -> list:
    """The track thinned to points `step` metres apart (and its last point), to 0.1 m."""
    kept = points[:1]
    for p in points[1:]:
        if math.dist(p, kept[-1]) >= step:
            kept.append(p)
    if points and kept[-1] != points[-1]:
        kept.append(points[-1])
    return [[round(n, 1), round(e, 1)] for n, e in kept]


def flight_facts(trace: Trace, geo: Geometry, start_ms: int, log: list) -> None:
    of = {}
    for t, m in log:
        of.setdefault(m.get_type(), []).append((t, m))
    positions = [(t, geo.ne(m.lat, m.lon), m.relative_alt / 1000.0) for t, m in of.get("GLOBAL_POSITION_INT", [])]
    texts = [m.text for _, m in of.get("STATUSTEXT", [])]
    disarmed = next((t for t, m in of.get("STATUSTEXT", []) if m.text == "Disarming motors"), log[-1][0] if log else 0)
    # Reached items by the vehicle's own "Reached command #N" texts, said in the tick an item is
    # reached: ArduCopter sends MISSION_ITEM_REACHED from a single deferred slot, so of two items
    # reached close together only the later's message may come (which ones differed between two
    # recordings of the same plan); those messages only have to be in the same order.
    reached = [(t, int(m.text.split("#")[1])) for t, m in of.get("STATUSTEXT", [])
               if m.text.startswith("Reached command #") and m.text.split("#")[1].isdigit()]
    trace.fact("reached", [seq for _, seq in reached])
    messages = [m.seq for _, m in of.get("MISSION_ITEM_REACHED", [])]
    trace.fact("reached_messages_in_order", messages == sorted(messages))
    # the takeoff on its own (until item 2 starts): how long a climb takes is not the legs' business
    aloft = next((t for t, m in of.get("STATUSTEXT", []) if m.text.startswith("Mission: 2 ")), start_ms)
    trace.fact("takeoff_s", round((aloft - start_ms) / 1000.0, 1), TOL_TAKEOFF_S)
    trace.fact("reached_s", [round((t - aloft) / 1000.0, 1) for t, _ in reached], TOL_REACHED_S)

    def height_at(t_ms: int) -> float:
        return min(positions, key=lambda p: abs(p[0] - t_ms))[2] if positions else math.nan
    trace.fact("reached_alt_m", [round(height_at(t), 1) for t, _ in [(aloft, 1)] + reached], TOL_ALT)
    trace.fact("current_seq_seen", held_seqs([m.seq for t, m in of.get("MISSION_CURRENT", []) if t <= disarmed and m.seq]))
    trace.fact("said", said(texts))
    flown = [p[1] for p in positions if start_ms <= p[0] <= disarmed]
    trace.fact("track", along_track(flown), TOL_TRACK)
    if flown:
        trace.fact("landed_north_m", round(flown[-1][0], 1), TOL_LANDED)
        trace.fact("landed_east_m", round(flown[-1][1], 1), TOL_LANDED)
    shots = [geo.ne(m.lat, m.lng) for _, m in of.get("CAMERA_FEEDBACK", [])]
    trace.fact("triggers.count", len(shots), TOL_PHOTOS)
    trace.fact("triggers.positions", [[round(n, 1), round(e, 1)] for n, e in shots], TOL_TRIGGERS)


def run(target) -> dict[str, Trace]:
    traces: dict[str, Trace] = {}
    lat, lon = (float(v) for v in HOME.split(",")[:2])
    geo = Geometry(int(round(lat * 1e7)), int(round(lon * 1e7)))
    try:
        for name, file in PLANS.items():
            client, camera = _boot(target)
            trace = traces[name] = Trace()
            trace.fact("triggers.cam1_type_set", camera)
            result, log = fly(client, wire_items(load_mission(PLANS_DIR / file)), LIMIT_S)
            trace.fact("upload", result)
            # from the vehicle time of MISSION_START's answer, not of when this client read it
            start_ms = next((t for t, m in log if m.get_type() == "COMMAND_ACK"
                             and m.command == mav.MAV_CMD_MISSION_START), log[0][0] if log else 0)
            flight_facts(trace, geo, start_ms, log)
    finally:
        target.close()
    return traces

"""A companion computer steering AUTO's guided items (issue 29): ArduCopter's AUTO is "in guided
mode" while NAV_GUIDED_ENABLE or NAV_SCRIPT_TIME runs, so the SET_POSITION_TARGET_* a companion
sends then fly the vehicle; the same targets sent during a waypoint leg change nothing.

Each probe flies surface_mission's mission (takeoff 10 m, waypoint A 20 m north, the item(s) under
test, waypoint B 20 m north 20 m east, land), and a companion (a listener on the ground station's
link) sends a velocity target 2 m/s east on every GLOBAL_POSITION_INT (10 Hz) while the item it
steers is current. Facts: the items reached, how long the item was current, how far east and how
far from its start the vehicle went while it was, and where it was when the item ended.
"""
from __future__ import annotations

import math

from ..client import mav
from ..facts import Tol, Trace
from .missions import REL
from .surface_mission import STREAMS_US, Geometry, _spec, boot_watched, build, fly_mission, held_seqs

AREA = "mission_companion"

VELOCITY_NED = 0x7 | 0x1C0 | 0x800 | 0x400  # velocity only: position, acceleration, yaw, yaw rate ignored
EAST_M_S = 2.0

# probe -> (the command under test, its spec, DO_GUIDED_LIMITS' params before it or None)
PROBES = {
    # ends when the companion has taken it 15 m from where the item began
    "guided_enable_15m": ("MAV_CMD_NAV_GUIDED_ENABLE", _spec(1, limit_s=90.0), (0, 0, 0, 15)),
    # a script's item with a 6 s timeout: flown by the companion meanwhile
    "script_time_6s": ("MAV_CMD_NAV_SCRIPT_TIME", _spec(0, 6, 0, 0, limit_s=90.0), None),
    # a plain waypoint leg (the item a waypoint at B's corner): the companion is not listened to
    "waypoint_leg": ("MAV_CMD_NAV_WAYPOINT", _spec(0, at=(20.0, -20.0), alt=10.0, limit_s=90.0), None),
}

TOL_S = Tol(abs=1.5, rel=0.1, why="the companion's stream is read at 10 Hz beats and each airframe speeds up "
                                  "to 2 m/s at its own rate; not listened to differs by the whole item")
TOL_M = Tol(abs=1.5, why="read at 10 Hz beats while flying 2 m/s; a target not taken differs by metres")


class Companion:
    """Sends the velocity target on every position report while item `seq` is current."""

    def __init__(self, client, seq: int):
        self.c, self.seq, self.current = client, seq, None

    def __call__(self, msg) -> None:
        kind = msg.get_type()
        if kind == "MISSION_CURRENT":
            self.current = msg.seq
        elif kind == "GLOBAL_POSITION_INT" and self.current == self.seq:
            self.c.conn.mav.set_position_target_local_ned_send(
                self.c.now_ms, 1, 1, mav.MAV_FRAME_LOCAL_NED, VELOCITY_NED, 0, 0, 0, 0.0, EAST_M_S, 0.0,
                0, 0, 0, 0, 0)


def fly(client, command: str, spec, limits, trace: Trace) -> None:
    pos0 = client.last["GLOBAL_POSITION_INT"]
    geo = Geometry(pos0.lat, pos0.lon)
    items, seq, b_seq = build(command, spec, geo)
    if limits is not None:
        items.insert(seq - 1, (mav.MAV_CMD_DO_GUIDED_LIMITS, REL, *limits, 0, 0, 0.0))
        seq, b_seq = seq + 1, b_seq + 1
    with client.listening(Companion(client, seq)):
        uploaded, _, log = fly_mission(client, items, spec, seq)
    trace.fact("upload", uploaded)

    def of(kind):
        return [(t, m) for t, m in log if m.get_type() == kind]

    currents = of("MISSION_CURRENT")
    trace.fact("reached", [m.seq for _, m in of("MISSION_ITEM_REACHED")])
    trace.fact("current_seq_seen", held_seqs([m.seq for _, m in currents]))
    end_ms = log[-1][0] if log else client.now_ms
    first = next((t for t, m in currents if m.seq == seq), None)
    last = next((t for t, m in currents if first is not None and t > first and m.seq != seq), end_ms)
    trace.fact("seconds_current", round((last - first) / 1000.0, 1) if first is not None else None, TOL_S)
    during = [geo.ne(m.lat, m.lon) for t, m in of("GLOBAL_POSITION_INT") if first is not None and first <= t <= last]
    if during:
        (n0, e0), (n1, e1) = during[0], during[-1]
        trace.fact("east_moved_m", round(max(e - e0 for _, e in during), 1), TOL_M)
        trace.fact("moved_max_m", round(max(math.hypot(n - n0, e - e0) for n, e in during), 1), TOL_M)
        trace.fact("end_ne_m", [round(n1, 1), round(e1, 1)], TOL_M)


def run(target) -> dict[str, Trace]:
    traces: dict[str, Trace] = {}
    try:
        for probe, (command, spec, limits) in PROBES.items():
            fly(boot_watched(target, STREAMS_US), command, spec, limits, traces.setdefault(probe, Trace()))
    finally:
        target.close()
    return traces

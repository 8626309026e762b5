"""AUTO's takeoff from the ground, as a mission starts it (issue 29's last gap): how long the
vehicle stays on the ground after MISSION_START, how its motors come up, how it climbs and when the
takeoff item is done. ArduCopter waits out its 2 s arming delay (the motors at ground idle), slews
the throttle up until the climb starts, then flies a jerk-limited climb and calls the takeoff done
when that profile ends.

Two probes: MISSION_START at once after arming, and 3 s after the arm command. The mission: a takeoff to 20 m,
then a waypoint 30 m north. A third: GUIDED's NAV_TAKEOFF to 10 m at once after arming. Watched at 20 Hz: GLOBAL_POSITION_INT, SERVO_OUTPUT_RAW (motor 1),
EXTENDED_SYS_STATE, MISSION_CURRENT.
"""
from __future__ import annotations

from ..client import mav
from ..facts import Tol, Trace
from .missions import upload
from .states import GUIDED
from .surface_mission import Geometry, boot_watched, item

AREA = "takeoff"
ALT_M = 20.0
STREAMS_US = {mav.MAVLINK_MSG_ID_GLOBAL_POSITION_INT: 50_000, mav.MAVLINK_MSG_ID_SERVO_OUTPUT_RAW: 50_000,
              mav.MAVLINK_MSG_ID_EXTENDED_SYS_STATE: 100_000, mav.MAVLINK_MSG_ID_MISSION_CURRENT: 100_000}
PROBES = {"start_at_once": 0.0, "start_after_3s": 3.0}  # probe -> seconds from arming to MISSION_START
OFF_GROUND_M = 0.1

TOL_S = Tol(abs=0.5, rel=0.08, why="read at 20 Hz beats; the arming delay alone is 2 s")
TOL_PWM = Tol(abs=60, why="each airframe's own hover throttle; ground idle against flying power is 500")
TOL_CLIMB = Tol(abs=0.3, why="read at 20 Hz while the climb changes by 1 m/s each second")
TOL_ALT = Tol(abs=0.3, why="read at 20 Hz in the last half-metre of a braking climb")
GUIDED_ALT_M = 10.0


def arm(client) -> int:
    """Arm; the vehicle time the command went out [ms]: times are counted from there, as the armed
    HEARTBEAT comes up to a second later."""
    t0 = client.now_ms
    client.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    client.try_wait(lambda: client.armed, 10)
    return t0


def recorder(client, t0: int, rows: list):
    """A listener adding (seconds since t0, what, values...) rows: height and climb, the mission's
    current item, the landed state."""
    def listen(m) -> None:
        t, kind = (client.now_ms - t0) / 1000.0, m.get_type()
        if kind == "GLOBAL_POSITION_INT":
            rows.append((t, "alt", m.relative_alt / 1000.0, -m.vz / 100.0))
        elif kind == "MISSION_CURRENT":
            rows.append((t, "cur", m.seq))
        elif kind == "EXTENDED_SYS_STATE":
            rows.append((t, "landed", m.landed_state))
    return listen


def fly(client, wait_s: float, trace: Trace) -> None:
    p0 = client.last["GLOBAL_POSITION_INT"]
    geo = Geometry(p0.lat, p0.lon)
    trace.fact("upload", upload(client, [item(mav.MAV_CMD_NAV_TAKEOFF, geo, alt=ALT_M),
                                         item(mav.MAV_CMD_NAV_WAYPOINT, geo, at=(30.0, 0.0), alt=ALT_M)]))
    client.set_mode(GUIDED)
    t0 = arm(client)
    if wait_s > (client.now_ms - t0) / 1000.0:
        client.idle(wait_s - (client.now_ms - t0) / 1000.0)
    idle_pwm = client.last["SERVO_OUTPUT_RAW"].servo1_raw
    rows: list = []
    with client.listening(recorder(client, t0, rows)):
        client.command(mav.MAV_CMD_MISSION_START)
        client.wait(lambda: any(r[1] == "cur" and r[2] == 2 for r in rows), 60, what="the takeoff's end")
        client.idle(1.0)  # the landed state the takeoff's end sets may come a message later
    trace.fact("idle_pwm_armed", idle_pwm, TOL_PWM)
    alts = [r for r in rows if r[1] == "alt"]
    off = next((r[0] for r in alts if r[2] > OFF_GROUND_M), None)
    trace.fact("off_ground_s", round(off, 2) if off is not None else None, TOL_S)
    if off is not None:  # the climb 1 s and 2 s after leaving the ground
        for after in (1.0, 2.0):
            climb = next((r[3] for r in alts if r[0] >= off + after), None)
            trace.fact(f"climb_{after:.0f}s_after_m_s", round(climb, 2) if climb is not None else None, TOL_CLIMB)
    done = next((r[0] for r in rows if r[1] == "cur" and r[2] == 2), None)
    trace.fact("takeoff_done_s", round(done, 2) if done is not None else None, TOL_S)
    landed = []
    for r in rows:
        if r[1] == "landed" and (not landed or landed[-1] != r[2]):
            landed.append(r[2])
    trace.fact("landed_states", landed)


def guided_takeoff(client, trace: Trace) -> None:
    """GUIDED's NAV_TAKEOFF to GUIDED_ALT_M sent as soon as the vehicle is armed: ArduCopter flies
    it with the same auto takeoff; the takeoff ends when the landed state turns IN_AIR."""
    client.set_mode(GUIDED)
    t0 = arm(client)
    rows: list = []
    with client.listening(recorder(client, t0, rows)):
        trace.fact("takeoff", client.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, GUIDED_ALT_M))
        client.wait(lambda: any(r[1] == "landed" and r[2] == mav.MAV_LANDED_STATE_IN_AIR for r in rows), 60,
                    what="the takeoff's end")
        client.idle(1.0)
    alts = [r for r in rows if r[1] == "alt"]
    off = next((r[0] for r in alts if r[2] > OFF_GROUND_M), None)
    trace.fact("off_ground_s", round(off, 2) if off is not None else None, TOL_S)
    if off is not None:
        climb = next((r[3] for r in alts if r[0] >= off + 1.0), None)
        trace.fact("climb_1s_after_m_s", round(climb, 2) if climb is not None else None, TOL_CLIMB)
    done = next((r[0] for r in rows if r[1] == "landed" and r[2] == mav.MAV_LANDED_STATE_IN_AIR), None)
    trace.fact("takeoff_done_s", round(done, 2) if done is not None else None, TOL_S)
    at_done = next((r[2] for r in alts if done is not None and r[0] >= done), None)
    trace.fact("alt_at_done_m", round(at_done, 1) if at_done is not None else None, TOL_ALT)
    trace.fact("alt_after_1s_m", round(alts[-1][2], 1) if alts else None, TOL_ALT)


def run(target) -> dict[str, Trace]:
    traces: dict[str, Trace] = {}
    try:
        for probe, wait_s in PROBES.items():
            fly(boot_watched(target, STREAMS_US), wait_s, traces.setdefault(probe, Trace()))
        guided_takeoff(boot_watched(target, STREAMS_US), traces.setdefault("guided_at_once", Trace()))
    finally:
        target.close()
    return traces

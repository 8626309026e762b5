"""Record how a vehicle sequences missions, as normalised message traces, to compare Firefly with
ArduCopter's SITL (issue 12, "Missions").

    python -m tests.parity.record_mission udpin:127.0.0.1:14902 out.json [scenario ...]

tests/parity/recorded/mission_*.json are its traces of ArduCopter SITL, one file per scenario.

Each scenario is a list of steps; a step is what the ground station did ("step", with the
COMMAND_ACK result where there is one) followed by what the vehicle said until the step's
condition held: STATUSTEXTs, MISSION_ITEM_REACHED, and MISSION_CURRENT / HEARTBEAT only when
their fields changed. Texts about sensors and pre-arm checks are left out: they are not mission
progress and differ between a simulator with an EKF and one without.
"""
from __future__ import annotations

import json
import math
import sys
import time

from pymavlink import mavutil

mav = mavutil.mavlink
STABILIZE, AUTO, GUIDED, LOITER, RTL, LAND = 0, 3, 4, 5, 6, 9
MODE_NAMES = {0: "STABILIZE", 3: "AUTO", 4: "GUIDED", 5: "LOITER", 6: "RTL", 9: "LAND"}
NOISE = ("EKF", "AHRS", "PreArm", "GPS", "Field Elevation", "Arm:", "IMU", "Barometer", "SIM",
         "ArduCopter", "Frame", "RCOut", "u-blox", "Throttle", "Initialising", "Ready to FLY",
         "Calibrating", "Home set", "Firefly", "Mode change to")
REL = mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT


class Recorder:
    def __init__(self, url: str):
        self.conn = mavutil.mavlink_connection(url, source_system=255, source_component=190,
                                               dialect="ardupilotmega")
        hb = self.conn.recv_match(type="HEARTBEAT", blocking=True, timeout=60)
        if hb is None:
            raise SystemExit("no HEARTBEAT")
        self.ts, self.tc = hb.get_srcSystem(), hb.get_srcComponent()
        self.trace: list = []
        self.last_current = None
        self.last_hb = None
        self.armed = False
        self.mode = None
        self.rel_alt = 0.0
        self.pos = None
        self.reached: list[int] = []
        self.texts: list[str] = []
        self.current = None
        self.ack = None

    # ----- receiving --------------------------------------------------------------------------
    def _take(self, m) -> None:
        t = m.get_type()
        if t == "HEARTBEAT" and m.get_srcComponent() == self.tc and m.type != mav.MAV_TYPE_GCS:
            self.armed = bool(m.base_mode & mav.MAV_MODE_FLAG_SAFETY_ARMED)
            self.mode = m.custom_mode
            key = (MODE_NAMES.get(m.custom_mode, m.custom_mode), self.armed)
            if key != self.last_hb:
                self.last_hb = key
                self.trace.append(["HEARTBEAT", {"mode": key[0], "armed": key[1]}])
        elif t == "MISSION_CURRENT":
            key = {"seq": m.seq, "total": m.total, "mission_state": m.mission_state,
                   "mission_mode": m.mission_mode}
            self.current = key
            if key != self.last_current:
                self.last_current = key
                self.trace.append(["MISSION_CURRENT", key])
        elif t == "MISSION_ITEM_REACHED":
            self.reached.append(m.seq)
            self.trace.append(["MISSION_ITEM_REACHED", {"seq": m.seq}])
        elif t == "STATUSTEXT":
            self.texts.append(m.text)
            if not m.text.startswith(NOISE):
                self.trace.append(["STATUSTEXT", {"severity": m.severity, "text": m.text}])
        elif t == "COMMAND_ACK":
            self.ack = m
        elif t == "GLOBAL_POSITION_INT":
            self.rel_alt = m.relative_alt / 1000.0
            self.pos = (m.lat, m.lon)

    def pump(self, until=None, timeout: float = 60.0, what: str = "") -> None:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            m = self.conn.recv_match(blocking=True, timeout=0.2)
            if m is not None:
                self._take(m)
            if until is not None and until():
                return
        if until is not None:
            raise TimeoutError(f"timed out: {what}")

    def drain(self, seconds: float) -> None:
        """Keep recording for a while (wall seconds) to see what follows a step."""
        self.pump(None, seconds)

    # ----- doing ------------------------------------------------------------------------------
    def step(self, name: str, **info) -> None:
        self.trace.append(["STEP", {"name": name, **info}])

    def command(self, name: str, command: int, *params, record: bool = True) -> int:
        p = list(params) + [0.0] * (7 - len(params))
        self.ack = None
        self.conn.mav.command_long_send(self.ts, self.tc, command, 0, *p)
        self.pump(lambda: self.ack is not None and self.ack.command == command, 10, f"ack {name}")
        result = self.ack.result
        if record:
            self.step(name, result=result)
        return result

    def set_mode(self, mode: int) -> int:
        return self.command(f"mode {MODE_NAMES[mode]}", mav.MAV_CMD_DO_SET_MODE, 1, mode)

    def set_param(self, name: str, value: float) -> None:
        self.conn.mav.param_set_send(self.ts, self.tc, name.encode(), value, mav.MAV_PARAM_TYPE_REAL32)
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline:
            m = self.conn.recv_match(blocking=True, timeout=0.2)
            if m is None:
                continue
            self._take(m)
            if m.get_type() == "PARAM_VALUE" and m.param_id == name:
                self.step(f"param {name}={value:g}")
                return
        self.step(f"param {name} not set")

    def arm(self) -> None:
        """Arm, retrying while the vehicle is not yet ready (a real EKF takes its time)."""
        deadline = time.monotonic() + 180
        while time.monotonic() < deadline:
            if self.command("arm", mav.MAV_CMD_COMPONENT_ARM_DISARM, 1, record=False) == 0:
                self.step("arm", result=0)
                self.pump(lambda: self.armed, 10, "armed in HEARTBEAT")
                return
            self.pump(None, 2.0)
        raise TimeoutError("arm")

    def upload(self, items: list) -> None:
        """items: (command, frame, p1, p2, p3, p4, lat_e7, lon_e7, alt); seq 0 (home) is prepended."""
        full = [(mav.MAV_CMD_NAV_WAYPOINT, mav.MAV_FRAME_GLOBAL_INT, 0, 0, 0, 0, 0, 0, 0)] + list(items)
        self.conn.mav.mission_count_send(self.ts, self.tc, len(full), mav.MAV_MISSION_TYPE_MISSION)
        deadline = time.monotonic() + 20
        while time.monotonic() < deadline:
            m = self.conn.recv_match(blocking=True, timeout=0.2)
            if m is None:
                continue
            self._take(m)
            t = m.get_type()
            if t in ("MISSION_REQUEST", "MISSION_REQUEST_INT"):
                c, f, p1, p2, p3, p4, x, y, z = full[m.seq]
                self.conn.mav.mission_item_int_send(self.ts, self.tc, m.seq, f, c, 0, 1, p1, p2, p3, p4,
                                                    x, y, z, mav.MAV_MISSION_TYPE_MISSION)
            elif t == "MISSION_ACK":
                self.step(f"upload {len(items)} items", result=m.type)
                return
        raise TimeoutError("upload")

    def set_current(self, seq: int) -> None:
        self.step(f"MISSION_SET_CURRENT {seq}")
        self.conn.mav.mission_set_current_send(self.ts, self.tc, seq)

    def wait_landed_disarmed(self, timeout=300) -> None:
        self.pump(lambda: not self.armed, timeout, "disarmed")

    # ----- mission geometry -------------------------------------------------------------------
    def here(self) -> tuple:
        self.pump(lambda: self.pos is not None, 30, "position")
        return self.pos

    def wp(self, n_m: float, e_m: float, alt: float = 10.0, command=mav.MAV_CMD_NAV_WAYPOINT, p1=0.0):
        lat, lon = self.home
        dlat = n_m / 6_371_000.0 * 180 / math.pi
        dlon = e_m / (6_371_000.0 * math.cos(math.radians(lat * 1e-7))) * 180 / math.pi
        return (command, REL, p1, 0, 0, 0, int(lat + dlat * 1e7), int(lon + dlon * 1e7), alt)


def takeoff(alt=10.0):
    return (mav.MAV_CMD_NAV_TAKEOFF, REL, 0, 0, 0, 0, 0, 0, alt)


def rtl():
    return (mav.MAV_CMD_NAV_RETURN_TO_LAUNCH, REL, 0, 0, 0, 0, 0, 0, 0)


def land_here():
    return (mav.MAV_CMD_NAV_LAND, REL, 0, 0, 0, 0, 0, 0, 0)


def jump(seq, repeat):
    return (mav.MAV_CMD_DO_JUMP, REL, seq, repeat, 0, 0, 0, 0, 0)


def change_speed(speed):
    return (mav.MAV_CMD_DO_CHANGE_SPEED, REL, 1, speed, -1, 0, 0, 0, 0)


def reached(r: Recorder, seq: int):
    n = len(r.reached)
    return lambda: seq in r.reached[n:]


def land(r: Recorder) -> None:
    r.set_mode(LAND)
    r.wait_landed_disarmed()
    r.step("disarmed")
    r.drain(3)


def wait_current(r: Recorder, seq: int) -> None:
    r.pump(lambda: r.current is not None and r.current["seq"] == seq, 120, f"current {seq}")
    r.step(f"current {seq}")


def wait_complete(r: Recorder) -> None:
    r.current = None  # a MISSION_CURRENT sent after the last step's ACK
    r.pump(lambda: r.current is not None and r.current["mission_state"] == mav.MISSION_STATE_COMPLETE,
           120, "complete")
    r.step("complete")


def guided_takeoff(r: Recorder, alt=10.0) -> None:
    r.set_mode(GUIDED)
    r.arm()
    r.command("takeoff", mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, alt)
    r.pump(lambda: r.rel_alt > alt - 0.7, 90, "takeoff altitude")
    r.step("at altitude")


# ----- scenarios -------------------------------------------------------------------------------
def scenario_reupload_after_landing(r: Recorder) -> None:
    """The divergence of issue 12: fly a mission, land, upload a new one, take off in GUIDED, AUTO."""
    r.set_param("MIS_RESTART", 0)
    r.upload([takeoff(), r.wp(15, 0), rtl()])
    r.set_mode(GUIDED)
    r.arm()
    r.command("MISSION_START", mav.MAV_CMD_MISSION_START)
    r.wait_landed_disarmed()
    r.step("disarmed")
    r.drain(3)
    r.upload([takeoff(), r.wp(0, 15), r.wp(15, 15), rtl()])
    r.drain(2)
    guided_takeoff(r)
    r.set_mode(AUTO)
    mark = len(r.reached)
    r.pump(lambda: 2 in r.reached[mark:], 120, "reached 2 of the new mission")
    r.step("reached 2")
    r.set_mode(GUIDED)
    r.drain(3)
    land(r)


def scenario_interrupted_resume(r: Recorder, restart: int) -> None:
    """Leave AUTO mid-mission, upload a new list while flying, come back: MIS_RESTART decides."""
    r.set_param("MIS_RESTART", restart)
    r.upload([takeoff(), r.wp(12, 0), r.wp(12, 12), r.wp(0, 12), rtl()])
    guided_takeoff(r)
    r.set_mode(AUTO)
    mark = len(r.reached)
    r.pump(lambda: 2 in r.reached[mark:], 120, "reached 2")
    r.step("reached 2")
    r.set_mode(GUIDED)
    r.drain(3)
    r.set_mode(AUTO)  # same list: resume or restart
    r.drain(4)
    r.set_mode(GUIDED)
    r.drain(2)
    r.upload([takeoff(), r.wp(-10, 0), r.wp(-10, -10), r.wp(0, -10), r.wp(5, 5), rtl()])
    r.drain(2)
    r.set_mode(AUTO)  # new list, never disarmed
    r.drain(4)
    land(r)


def scenario_completed_then_auto(r: Recorder) -> None:
    """A mission that ends in the air completes (LOITER-like hold in AUTO); AUTO again restarts it."""
    r.set_param("MIS_RESTART", 0)
    r.upload([takeoff(), r.wp(10, 0)])
    guided_takeoff(r)
    r.set_mode(AUTO)
    wait_complete(r)
    r.drain(3)
    r.set_current(2)  # in a completed mission
    r.drain(3)
    r.set_mode(GUIDED)
    r.drain(2)
    r.set_mode(AUTO)
    r.drain(6)
    r.set_mode(GUIDED)
    r.drain(1)
    land(r)


def scenario_set_current(r: Recorder) -> None:
    """MISSION_SET_CURRENT disarmed, in AUTO running, in GUIDED flying; seq 0, out of range, a do item."""
    r.set_param("MIS_RESTART", 0)
    r.upload([takeoff(), r.wp(10, 0), change_speed(3), r.wp(10, 10), r.wp(0, 10), rtl()])
    r.set_mode(STABILIZE)
    r.drain(2)
    r.set_current(4)
    r.drain(2)
    r.set_current(9)
    r.drain(2)
    r.set_current(3)
    r.drain(2)
    r.set_current(0)
    r.drain(2)
    guided_takeoff(r)
    r.set_current(4)
    r.drain(2)
    r.set_mode(AUTO)
    wait_current(r, 5)
    r.set_current(2)
    wait_current(r, 4)
    r.set_current(0)
    wait_current(r, 2)
    r.set_current(9)
    r.drain(2)
    land(r)


def scenario_do_jump(r: Recorder) -> None:
    """DO_JUMP twice back to a waypoint, with a DO_CHANGE_SPEED in the loop; ends with LAND."""
    r.set_param("MIS_RESTART", 0)
    r.upload([takeoff(), r.wp(6, 0), change_speed(4), r.wp(6, 6), jump(2, 2), r.wp(0, 0), land_here()])
    r.set_mode(GUIDED)
    r.arm()
    r.command("MISSION_START", mav.MAV_CMD_MISSION_START)
    r.wait_landed_disarmed()
    r.step("disarmed")
    r.drain(4)


def scenario_no_takeoff(r: Recorder) -> None:
    """A mission without takeoff: AUTO disarmed, MISSION_START on the ground armed (refused),
    then in the air; MISSION_START again once it completed."""
    r.set_param("MIS_RESTART", 0)
    r.set_mode(STABILIZE)
    r.upload([r.wp(8, 0), r.wp(8, 8)])
    r.drain(2)
    r.set_mode(AUTO)  # disarmed
    r.drain(3)
    r.set_mode(GUIDED)
    r.arm()
    r.command("MISSION_START", mav.MAV_CMD_MISSION_START)
    r.command("takeoff", mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 10)
    r.pump(lambda: r.rel_alt > 9.3, 90, "takeoff altitude")
    r.step("at altitude")
    r.command("MISSION_START", mav.MAV_CMD_MISSION_START)
    wait_complete(r)
    r.drain(2)
    r.command("MISSION_START", mav.MAV_CMD_MISSION_START)  # completed: starts over
    wait_complete(r)
    r.drain(2)
    land(r)


SCENARIOS = {
    "reupload_after_landing": scenario_reupload_after_landing,
    "interrupted_resume_restart0": lambda r: scenario_interrupted_resume(r, 0),
    "interrupted_resume_restart1": lambda r: scenario_interrupted_resume(r, 1),
    "completed_then_auto": scenario_completed_then_auto,
    "set_current": scenario_set_current,
    "do_jump": scenario_do_jump,
    "no_takeoff": scenario_no_takeoff,
}


def main(argv: list[str]) -> None:
    url, out = argv[0], argv[1]
    names = argv[2:] or list(SCENARIOS)
    r = Recorder(url)
    r.command("MISSION_CURRENT at 10 Hz", mav.MAV_CMD_SET_MESSAGE_INTERVAL,
              mav.MAVLINK_MSG_ID_MISSION_CURRENT, 100_000, record=False)
    r.command("GLOBAL_POSITION_INT at 10 Hz", mav.MAV_CMD_SET_MESSAGE_INTERVAL,
              mav.MAVLINK_MSG_ID_GLOBAL_POSITION_INT, 100_000, record=False)
    r.home = r.here()
    try:
        results = json.load(open(out))
    except (OSError, ValueError):
        results = {}
    for name in names:
        r.trace, r.last_current, r.last_hb = [], None, None
        print("scenario", name, flush=True)
        try:
            SCENARIOS[name](r)
        except TimeoutError as e:
            r.step("ABORTED", reason=str(e))
            print(" ", e, flush=True)
        results[name] = r.trace
        with open(out, "w") as f:
            json.dump(results, f, indent=1)
        if r.armed:  # leave the vehicle on the ground for the next scenario
            r.set_mode(LAND)
            r.wait_landed_disarmed()


if __name__ == "__main__":
    main(sys.argv[1:])

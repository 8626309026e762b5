"""The state-space attack on the real process, over UDP: the messages reported to kill it, and a few
hundred hostile ones, sent in three states of a realistic start-up (before home is set, ready on
the ground, flying in GUIDED). The process must stay up and keep its HEARTBEAT, answer every
command exactly once, and its exit report (--stats) must show no handler error, no internal error
and no exception. The sans-IO walk over every state is tests/unit/test_state_space.py.
"""
from __future__ import annotations

import json
import math
import random
import time
from collections import Counter
from pathlib import Path

import pytest
from pymavlink import mavutil

from firefly.autopilot.params import ParamStore
from firefly.groundstation.flight.autopilot_process import start_autopilot
from firefly.sim.geo import GeoPoint
from firefly.sim.scenario import DEFAULT_HOME

from ..fuzz import hostile
from ..fuzz.state_machine import describe_message

pytestmark = [pytest.mark.sitl, pytest.mark.serial]  # a HEARTBEAT is due within 3 s of wall time
mav = mavutil.mavlink
REPO = Path(__file__).resolve().parents[2]
SPEEDUP = 5  # home is set at 19.9 s of sim time: 4 s of wall time to attack the vehicle before it
HOSTILE_PER_STATE = 100
SEED = 11
HOME = GeoPoint(*DEFAULT_HOME[:3])  # where the process's vehicle starts (no --home, no scenario)
ACK_TIMEOUT_S = 3.0
STABILIZE, GUIDED, AUTO = 0, 4, 3
MAV_RESULT_FAILED = 4


class Attacker:
    """A ground station that reads everything the vehicle sends and keeps count: the COMMAND_ACKs
    per command, the status texts, the last HEARTBEAT, the height."""

    def __init__(self, url: str, process=None):
        self.process = process  # the AutopilotProcess: a failure says how it ended, if it did
        self.conn = mavutil.mavlink_connection(url, source_system=255, source_component=190,
                                               dialect="ardupilotmega")
        self.mav = self.conn.mav
        self.acks: Counter = Counter()  # command id -> COMMAND_ACKs received
        self.asked: Counter = Counter()  # command id -> commands sent to the vehicle
        self.results: dict = {}  # command id -> the last result
        self.texts: list[str] = []
        self.last_heartbeat = None
        self.last_heartbeat_wall = -math.inf
        self.relative_alt_m = 0.0
        self.sent: list[str] = []  # what was sent, for a failure message
        self.params_set: set[str] = set()  # names of the parameters a PARAM_SET was sent for
        self.state = "connecting"

    def pump(self, seconds: float = 0.0, until=None):
        """Read everything for `seconds` (or until `until(msg)`), keeping count; the message that
        satisfied `until`, or None."""
        deadline = time.monotonic() + seconds
        while True:
            msg = self.conn.recv_match(blocking=True, timeout=max(0.0, min(0.05, deadline - time.monotonic())))
            if msg is not None:
                kind = msg.get_type()
                if kind == "COMMAND_ACK":
                    self.acks[msg.command] += 1
                    self.results[msg.command] = msg.result
                elif kind == "STATUSTEXT":
                    self.texts.append(msg.text)
                elif kind == "HEARTBEAT" and msg.get_srcSystem() == 1:
                    self.last_heartbeat, self.last_heartbeat_wall = msg, time.monotonic()
                elif kind == "GLOBAL_POSITION_INT":
                    self.relative_alt_m = msg.relative_alt / 1000.0
                if until is not None and until(msg):
                    return msg
            if time.monotonic() >= deadline:
                return None

    def send(self, msg) -> None:
        self.sent.append(f"[{self.state}] {describe_message(msg)}")
        self.mav.send(msg)
        kind = msg.get_type()
        if kind == "PARAM_SET":
            name = msg.param_id.encode() if isinstance(msg.param_id, str) else msg.param_id
            self.params_set.add(name.split(b"\0", 1)[0].decode("ascii", "replace"))
        if kind in ("COMMAND_LONG", "COMMAND_INT") and msg.target_system in (0, 1):
            self.asked[msg.command] += 1
            before = self.acks[msg.command]
            got = self.pump(ACK_TIMEOUT_S, lambda m: m.get_type() == "COMMAND_ACK" and m.command == msg.command)
            assert got is not None or self.acks[msg.command] > before, self.failure(f"no COMMAND_ACK for {kind} "
                                                                                    f"{msg.command}")

    def command(self, command: int, *params) -> int:
        p = [float(x) for x in params] + [0.0] * (7 - len(params))
        self.send(self.mav.command_long_encode(1, 1, command, 0, *p))
        return self.results.get(command)

    def set_param(self, name: str, value: float) -> None:
        self.send(self.mav.param_set_encode(1, 1, name.encode(), value, mav.MAV_PARAM_TYPE_REAL32))
        self.pump(1.0, lambda m: m.get_type() == "PARAM_VALUE" and m.param_id == name)

    def upload(self, kind: int, items: list) -> None:
        """MISSION_COUNT, each item asked for, up to the MISSION_ACK (whatever it says)."""
        self.send(self.mav.mission_count_encode(1, 1, len(items), kind))
        while True:
            msg = self.pump(ACK_TIMEOUT_S, lambda m: m.get_type() in ("MISSION_REQUEST_INT", "MISSION_REQUEST",
                                                                      "MISSION_ACK") and m.mission_type == kind)
            assert msg is not None, self.failure(f"upload of list {kind} stalled")
            if msg.get_type() == "MISSION_ACK":
                return
            command, frame, p1, p2, p3, p4, x, y, z = items[msg.seq]
            self.send(self.mav.mission_item_int_encode(1, 1, msg.seq, frame, command, 0, 1, p1, p2, p3, p4, x, y, z,
                                                       kind))

    def failure(self, what: str) -> str:
        text = f"{self.state}: {what}; the last messages sent:\n  " + "\n  ".join(self.sent[-8:])
        if self.process is not None and self.process.process.poll() is not None:
            text += (f"\nthe autopilot died (status {self.process.process.returncode}); its stderr ends:\n"
                     f"{stderr_of(self.process)}")
        return text


def harmless_to_the_link(msg) -> bool:
    """Hostile, but not what would cut this test off from the vehicle by design: a signing key
    (the vehicle then refuses unsigned messages), the link-fault parameters, the HEARTBEAT
    switched off with SET_MESSAGE_INTERVAL, or a reboot (the vehicle that was, and the state this
    test built, are gone: tests/sitl/test_reboot.py attacks reboots). The sans-IO walk sends
    those too."""
    kind = msg.get_type()
    if kind == "SETUP_SIGNING":
        return False
    if kind == "PARAM_SET":
        name = msg.param_id if isinstance(msg.param_id, bytes) else msg.param_id.encode()
        return not name.startswith(b"SIM_LINK")
    if kind in ("COMMAND_LONG", "COMMAND_INT") and msg.command == mav.MAV_CMD_SET_MESSAGE_INTERVAL:
        return msg.param1 != 0
    if kind in ("COMMAND_LONG", "COMMAND_INT") and msg.command == mav.MAV_CMD_PREFLIGHT_REBOOT_SHUTDOWN:
        return False
    return True


def attack(gcs: Attacker, rng: random.Random, count: int) -> None:
    sent = 0
    while sent < count:
        msg = hostile.hostile_message(gcs.mav, rng)
        if harmless_to_the_link(msg):
            gcs.send(msg)
            sent += 1


def assert_alive(ap, gcs: Attacker) -> None:
    assert ap.process.poll() is None, gcs.failure("the autopilot is no longer running")
    hb = gcs.pump(3.0, lambda m: m.get_type() == "HEARTBEAT" and m.get_srcSystem() == 1)
    assert hb is not None, gcs.failure("no HEARTBEAT for 3 s of wall time (15 s of sim time)")


def stderr_of(ap) -> str:
    if ap.stderr_log is None:
        return ""
    ap.stderr_log.seek(0)
    return ap.stderr_log.read().decode(errors="replace")[-3000:]


def origin_items(origin_lat: float, origin_lon: float):
    lat, lon = int(round(origin_lat * 1e7)), int(round(origin_lon * 1e7))
    rel = mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT
    mission = [(16, 0, 0, 0, 0, 0, lat, lon, 0.0), (16, rel, 0, 0, 0, math.nan, lat + 300, lon, 10.0),
               (177, 2, math.nan, math.nan, 0, 0, 0, 0, 0.0), (16, rel, 0, 0, 0, math.nan, lat, lon + 300, 10.0)]
    square = [(lat + 300, lon + 400), (lat + 300, lon - 400), (lat - 300, lon - 400), (lat - 300, lon + 400)]
    fence = [(5001, rel, math.nan, 0, 0, 0, x, y, 0.0) for x, y in square]
    return mission, fence


def test_hostile_messages_in_three_states_leave_the_process_up_and_answering(tmp_path):
    stats = tmp_path / "exit-report.json"
    ap = start_autopilot(tmp_path / "state", str(SPEEDUP), ("--startup", "realistic", "--stats", str(stats)),
                         wipe=True, cwd=REPO, capture_stderr=True)
    rng = random.Random(SEED)
    gcs = None
    try:
        gcs = Attacker(ap.pymavlink_url, ap)
        assert gcs.pump(10.0, lambda m: m.get_type() == "HEARTBEAT") is not None, "no HEARTBEAT from the autopilot"
        gcs.mav.heartbeat_send(mav.MAV_TYPE_GCS, mav.MAV_AUTOPILOT_INVALID, 0, 0, 0)
        known = hostile.known_reproductions(gcs.mav, HOME)

        # --- before home: the modes and commands that need home, then the 3e6 m home ------------------
        gcs.state = "before home"
        assert gcs.command(mav.MAV_CMD_GET_HOME_POSITION) == MAV_RESULT_FAILED, "home is already set"
        home_3e6 = [m for m in known if m.get_type() == "COMMAND_LONG" and m.command == mav.MAV_CMD_DO_SET_HOME]
        for msg in known:
            if msg not in home_3e6:
                gcs.send(msg)
                gcs.pump(0.1)  # 0.5 s of sim time in that mode
        assert gcs.command(mav.MAV_CMD_GET_HOME_POSITION) == MAV_RESULT_FAILED, \
            gcs.failure("home was set before the attack on a vehicle without home was over: attack faster")
        gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, STABILIZE)
        attack(gcs, rng, HOSTILE_PER_STATE)
        gcs.send(home_3e6[0])
        gcs.pump(1.0)  # HOME_POSITION and GLOBAL_POSITION_INT are built and packed from it
        assert_alive(ap, gcs)
        gcs.command(mav.MAV_CMD_DO_SET_HOME, 1)  # home back where the vehicle is

        # --- on the ground, ready to arm ------------------------------------------------------------
        gcs.state = "ready on the ground"
        ready = gcs.pump(30.0, lambda m: m.get_type() == "STATUSTEXT" and "is using GPS" in m.text) or \
            any("is using GPS" in t for t in gcs.texts)
        assert ready, gcs.failure("the start-up never reached 'EKF3 IMU0 is using GPS'")
        gcs.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0, 21196)
        gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, STABILIZE)
        for msg in known:
            gcs.send(msg)
            gcs.pump(0.05)
        attack(gcs, rng, HOSTILE_PER_STATE)
        assert_alive(ap, gcs)

        # --- flying in GUIDED: a mission whose DO_JUMP is NaN flown in AUTO, a fence whose vertex
        # count is NaN enabled, then the rest -----------------------------------------------------------
        gcs.state = "flying in GUIDED"
        defaults = ParamStore()
        for name in sorted(gcs.params_set):
            if name in defaults:
                gcs.set_param(name, float(defaults[name]))  # what the attack changed, back to its default
        # The pilot's state the attack may have left, as a pilot would undo it: sticks released (0
        # releases channels 1-8, UINT16_MAX - 1 channels 9-16), the motor emergency stop off. A
        # released mode channel that moves back to its SITL value turns the flight-mode switch
        # (after a 0.2 s debounce): two HEARTBEATs, a vehicle second, let it act before GUIDED.
        gcs.send(gcs.mav.rc_channels_override_encode(1, 1, *[0] * 8, *[65534] * 10))
        gcs.command(mav.MAV_CMD_DO_AUX_FUNCTION, 31, 0)
        for _ in range(2):
            gcs.pump(5.0, lambda m: m.get_type() == "HEARTBEAT" and m.get_srcSystem() == 1)
        gcs.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0, 21196)
        gcs.command(mav.MAV_CMD_DO_SET_HOME, 1)
        gcs.send(gcs.mav.mission_clear_all_encode(1, 1, 0))
        assert gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, GUIDED) == 0, gcs.failure("GUIDED refused")
        armed = gcs.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
        if armed != 0:
            gcs.pump(0.5)  # the refusal's text follows its ACK
        assert armed == 0, gcs.failure(f"ARM refused: {gcs.texts[-3:]}")
        assert gcs.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 10) == 0, gcs.failure("takeoff refused")
        gcs.pump(15.0, lambda m: m.get_type() == "GLOBAL_POSITION_INT" and m.relative_alt > 5000)
        assert gcs.relative_alt_m > 5, gcs.failure(f"did not climb: {gcs.relative_alt_m:.1f} m; {gcs.texts[-6:]}")
        mission, fence = origin_items(HOME.lat_deg, HOME.lon_deg)
        gcs.upload(1, fence)
        for name, value in (("FENCE_TYPE", 4), ("FENCE_ENABLE", 1)):
            gcs.set_param(name, value)
        gcs.pump(0.5)  # the fence check runs at 10 Hz
        assert_alive(ap, gcs)
        gcs.upload(0, mission)
        gcs.command(mav.MAV_CMD_MISSION_START)
        gcs.pump(1.0)  # AUTO flies to the jump
        assert_alive(ap, gcs)
        gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, GUIDED)
        attack(gcs, rng, HOSTILE_PER_STATE)
        assert_alive(ap, gcs)

        # --- every command answered exactly once ------------------------------------------------------
        gcs.state = "after the attack"
        gcs.pump(1.0)
        unanswered = {c: (n, gcs.acks[c]) for c, n in gcs.asked.items() if gcs.acks[c] != n}
        assert not unanswered, gcs.failure(f"commands (id: sent, acked) not answered exactly once: {unanswered}")
        extra = {c: n for c, n in gcs.acks.items() if c not in gcs.asked and c != mav.MAVLINK_MSG_ID_SET_MODE}
        assert not extra, gcs.failure(f"COMMAND_ACKs for commands never sent: {extra}")
    finally:
        if gcs is not None:
            gcs.conn.close()
        alive, said = ap.process.poll() is None, stderr_of(ap)
        ap.stop()  # SIGTERM: the process writes its exit report
    assert alive, f"the autopilot died: {said}"
    report = json.loads(stats.read_text())
    assert report["exception"] is None, f"the loop ended on an exception: {report['exception']}"
    (vehicle,) = report["vehicles"]
    assert vehicle["counters"].get("handler_errors", 0) == 0, f"handler errors, last: {vehicle['last_handler_error']}"
    assert vehicle.get("internal_errors", 0) == 0, \
        f"{vehicle['internal_errors']} internal errors, last: {vehicle.get('last_internal_error')}"

"""Helpers for pymavlink-driven tests: a GCS-like connection and condition waits."""
from __future__ import annotations

import math
import time

from pymavlink import mavutil

mav = mavutil.mavlink
GUIDED = 4


class Gcs:
    """A pymavlink client as a ground station would be: sysid 255, compid 190 (MAV_COMP_ID_MISSIONPLANNER)."""

    def __init__(self, url: str, timeout: float = 10.0):
        self.conn = mavutil.mavlink_connection(url, source_system=255, source_component=190,
                                               dialect="ardupilotmega")
        deadline = time.monotonic() + timeout
        while True:  # the autopilot's: not another component of its system (a thermal camera's)
            hb = self.conn.recv_match(type="HEARTBEAT", blocking=True, timeout=max(0.0, deadline - time.monotonic()))
            if hb is None:
                raise AssertionError("no HEARTBEAT from the autopilot")
            if hb.autopilot != mav.MAV_AUTOPILOT_INVALID:
                break
        self.heartbeat = hb
        self.conn.target_system = hb.get_srcSystem()
        self.conn.target_component = hb.get_srcComponent()
        self.mav = self.conn.mav

    def recv(self, types, timeout: float = 5.0, condition=None):
        """Next message of `types` satisfying `condition`, or None after `timeout` wall seconds."""
        deadline = time.monotonic() + timeout
        while True:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                return None
            msg = self.conn.recv_match(type=types, blocking=True, timeout=remaining)
            if msg is not None and (condition is None or condition(msg)):
                return msg

    def command(self, command: int, *params, timeout: float = 5.0):
        p = list(params) + [0.0] * (7 - len(params))
        self.mav.command_long_send(self.conn.target_system, self.conn.target_component, command, 0, *p)
        ack = self.recv("COMMAND_ACK", timeout, lambda m: m.command == command)
        if ack is None:
            raise AssertionError(f"no COMMAND_ACK for command {command}")
        return ack.result

    def command_with_reply(self, command: int, reply_type: str, *params, timeout: float = 5.0):
        """Send a command that answers with a message besides its ACK; return (result, message)."""
        p = list(params) + [0.0] * (7 - len(params))
        self.mav.command_long_send(self.conn.target_system, self.conn.target_component, command, 0, *p)
        ack = reply = None
        while ack is None or (reply is None and ack.result == 0):
            msg = self.recv(["COMMAND_ACK", reply_type], timeout,
                            lambda m: m.get_type() == reply_type or m.command == command)
            if msg is None:
                raise AssertionError(f"no COMMAND_ACK/{reply_type} for command {command}")
            if msg.get_type() == "COMMAND_ACK":
                ack = msg
            else:
                reply = msg
        return ack.result, reply

    def close(self) -> None:
        self.conn.close()


def set_param(gcs: Gcs, name: str, value: float) -> None:
    """PARAM_SET, and the echoed PARAM_VALUE that says it took."""
    gcs.mav.param_set_send(1, 1, name.encode(), value, mav.MAV_PARAM_TYPE_REAL32)
    echo = gcs.recv("PARAM_VALUE", 5, lambda m: m.param_id == name)
    assert echo is not None and math.isclose(echo.param_value, value, rel_tol=1e-6), f"{name} not set"


def take_off(gcs: Gcs, alt: float = 10.0) -> None:
    """GUIDED, arm, take off, and wait until the vehicle is near alt."""
    assert gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, GUIDED) == mav.MAV_RESULT_ACCEPTED
    assert gcs.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1) == mav.MAV_RESULT_ACCEPTED
    assert gcs.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, alt) == mav.MAV_RESULT_ACCEPTED
    assert gcs.recv("GLOBAL_POSITION_INT", 20, lambda m: m.relative_alt > (alt - 0.5) * 1000) is not None


def expect_failsafe(gcs: Gcs, words: str, mode: int, timeout: float = 30.0):
    """A STATUSTEXT containing `words`, then a HEARTBEAT in `mode` with system status CRITICAL."""
    text = gcs.recv("STATUSTEXT", timeout, lambda m: words in m.text)
    assert text is not None, f"no STATUSTEXT containing {words!r}"
    hb = gcs.recv("HEARTBEAT", 5, lambda m: m.custom_mode == mode)
    assert hb is not None, f"vehicle did not switch to mode {mode}"
    assert hb.system_status == mav.MAV_STATE_CRITICAL
    return text


def upload_mission(gcs: Gcs, items: list) -> None:
    """Upload a mission; items are (command, x, y, z) or (command, x, y, z, (p1, p2, p3, p4)) in
    MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, seq 0 (home) is added in front. Waits for an accepting
    MISSION_ACK."""
    full = [(mav.MAV_CMD_NAV_WAYPOINT, 0, 0, 0.0)] + list(items)
    gcs.mav.mission_count_send(gcs.conn.target_system, gcs.conn.target_component, len(full), 0)
    while True:
        msg = gcs.recv(["MISSION_REQUEST_INT", "MISSION_REQUEST", "MISSION_ACK"], 5)
        assert msg is not None, "upload stalled"
        if msg.get_type() == "MISSION_ACK":
            assert msg.type == mav.MAV_MISSION_ACCEPTED, msg
            return
        command, x, y, z, *params = full[msg.seq]
        p1, p2, p3, p4 = params[0] if params else (0, 0, 0, 0)
        gcs.mav.mission_item_int_send(gcs.conn.target_system, gcs.conn.target_component, msg.seq,
                                      mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, command, 0, 1, p1, p2, p3, p4,
                                      x, y, z, 0)

"""Every command Firefly handles, sent in each situation a vehicle can be in (disarmed in each
mode, armed on the ground, flying, landing, in a battery failsafe's RTL): the COMMAND_ACK result,
the mode and arming state a second later, and what the vehicle said about it."""
from __future__ import annotations

from ..client import Client, mav
from ..facts import Trace
from .states import (ALT_HOLD, AUTO, BRAKE, GUIDED, LAND, LOITER, RTL, STABILIZE, mode_name,
                     reach_armed_on_ground, reach_battery_failsafe, reach_disarmed_in, reach_flying,
                     reach_landing)
from .texts import said

AREA = "commands"
HOME_LAT, HOME_LON = -35.363261, 149.165230
NORTH_20M_LAT = HOME_LAT + 20 / 111_195.0
SAID_WITHIN_S = 1.0  # the replies to a command, and what the vehicle does in the second after it

# name -> how to send it: ("long", command, params) or ("int", command, frame, p1..p4, x, y, z)
STATEFUL = {
    "arm": ("long", mav.MAV_CMD_COMPONENT_ARM_DISARM, (1,)),
    "disarm": ("long", mav.MAV_CMD_COMPONENT_ARM_DISARM, (0,)),
    "takeoff": ("long", mav.MAV_CMD_NAV_TAKEOFF, (0, 0, 0, 0, 0, 0, 10)),
    "land": ("long", mav.MAV_CMD_NAV_LAND, ()),
    "rtl": ("long", mav.MAV_CMD_NAV_RETURN_TO_LAUNCH, ()),
    "mode_guided": ("long", mav.MAV_CMD_DO_SET_MODE, (1, GUIDED)),
    "mode_loiter": ("long", mav.MAV_CMD_DO_SET_MODE, (1, LOITER)),
    "mode_unknown": ("long", mav.MAV_CMD_DO_SET_MODE, (1, 99)),
    "change_speed": ("long", mav.MAV_CMD_DO_CHANGE_SPEED, (1, 3, -1)),
    "reposition": ("int", mav.MAV_CMD_DO_REPOSITION, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT,
                   (-1, 1, 0, float("nan")), (int(NORTH_20M_LAT * 1e7), int(HOME_LON * 1e7), 10.0)),
    "condition_yaw": ("long", mav.MAV_CMD_CONDITION_YAW, (90, 30, 1, 0)),
    "mission_start": ("long", mav.MAV_CMD_MISSION_START, (0, 0)),
}
QUERIES = {
    "get_home_position": ("long", mav.MAV_CMD_GET_HOME_POSITION, ()),
    "request_capabilities": ("long", mav.MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES, (1,)),
    "request_message_version": ("long", mav.MAV_CMD_REQUEST_MESSAGE, (148,)),
    "request_message_home": ("long", mav.MAV_CMD_REQUEST_MESSAGE, (242,)),
    "request_message_unknown": ("long", mav.MAV_CMD_REQUEST_MESSAGE, (60000,)),
    "set_message_interval": ("long", mav.MAV_CMD_SET_MESSAGE_INTERVAL, (30, 100000)),
    "get_message_interval": ("long", mav.MAV_CMD_GET_MESSAGE_INTERVAL, (30,)),
    "set_home_here": ("long", mav.MAV_CMD_DO_SET_HOME, (1,)),
    "unknown_command": ("long", 31010, ()),
    "reposition_as_long": ("long", mav.MAV_CMD_DO_REPOSITION, (-1, 1, 0, 0, NORTH_20M_LAT, HOME_LON, 10)),
}

STATES = {
    **{f"disarmed_{mode_name(m).lower()}": (lambda c, m=m: reach_disarmed_in(c, m))
       for m in (STABILIZE, ALT_HOLD, LOITER, GUIDED, AUTO, LAND, RTL, BRAKE)},
    "armed_ground_guided": lambda c: reach_armed_on_ground(c, GUIDED),
    "armed_ground_stabilize": lambda c: reach_armed_on_ground(c, STABILIZE),
    "flying_guided": reach_flying,
    "landing": reach_landing,
}


def send(client: Client, how) -> int | None:
    if how[0] == "long":
        return client.command(how[1], *how[2])
    _, command, frame, (p1, p2, p3, p4), (x, y, z) = how
    return client.command_int(command, frame, p1, p2, p3, p4, x, y, z)


def observe(client: Client, trace: Trace, name: str, how) -> None:
    t0 = client.now_ms
    result = send(client, how)
    client.idle(SAID_WITHIN_S)
    client.fresh_heartbeat()
    trace.fact(f"{name}.result", result)
    trace.fact(f"{name}.mode_after", mode_name(client.mode))
    trace.fact(f"{name}.armed_after", client.armed)
    trace.fact(f"{name}.said", said(client.texts_since(t0, SAID_WITHIN_S)))


def run(target) -> dict[str, Trace]:
    traces = {}
    client = target.boot()
    try:
        for state, reach in STATES.items():
            trace = traces[state] = Trace()
            for name, how in STATEFUL.items():
                reach(client)
                trace.fact(f"{name}.in_mode", mode_name(client.mode))
                observe(client, trace, name, how)
        trace = traces["battery_failsafe"] = Trace()
        for name, how in STATEFUL.items():  # a fresh vehicle each: a battery failsafe lasts until reboot
            client = target.boot()
            reach_battery_failsafe(client)
            trace.fact(f"{name}.in_mode", mode_name(client.mode))
            observe(client, trace, name, how)
        reach_disarmed_in(client, GUIDED)
        trace = traces["queries"] = Trace()
        for name, how in QUERIES.items():
            observe(client, trace, name, how)
    finally:
        target.close()
    return traces

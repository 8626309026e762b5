"""Bringing a vehicle into the situations probes start from, by client actions only, so the same
steps work on ArduCopter and Firefly. Each `reach_*` works from any state a probe may leave behind.
"""
from __future__ import annotations

from ..client import Client, mav

STABILIZE, ACRO, ALT_HOLD, AUTO, GUIDED, LOITER, RTL, LAND, BRAKE = 0, 1, 2, 3, 4, 5, 6, 9, 17
MODE_NAMES = {0: "STABILIZE", 1: "ACRO", 2: "ALT_HOLD", 3: "AUTO", 4: "GUIDED", 5: "LOITER", 6: "RTL",
              9: "LAND", 16: "POSHOLD", 17: "BRAKE"}
HOVER_ALT_M = 10.0


def mode_name(number) -> str:
    return MODE_NAMES.get(number, str(number))


def on_ground_disarmed(client: Client) -> None:
    """Disarmed on the ground; a flying vehicle lands first."""
    if not client.armed:
        return
    if client.rel_alt_m() < 0.5:
        client.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0)
        if client.try_wait(lambda: not client.armed, 2):
            return
    client.set_mode(LAND)  # flying, or not yet known to be landed
    client.wait(lambda: not client.armed, 120, what="landing and disarming")


def reach_disarmed_in(client: Client, mode: int) -> None:
    on_ground_disarmed(client)
    if client.mode != mode:
        client.set_mode(mode)
        client.try_wait(lambda: client.mode == mode, 2)


def reach_armed_on_ground(client: Client, mode: int = GUIDED) -> None:
    on_ground_disarmed(client)
    client.set_mode(mode)
    client.wait(lambda: client.mode == mode, 5, what=f"mode {mode_name(mode)}")
    client.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    client.wait(lambda: client.armed, 10, what="armed")


def reach_flying(client: Client, alt_m: float = HOVER_ALT_M) -> None:
    """Hovering in GUIDED near `alt_m` above home."""
    if not (client.armed and client.rel_alt_m() > 2.0):
        reach_armed_on_ground(client, GUIDED)
        client.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, alt_m)
        client.wait(lambda: client.rel_alt_m() > alt_m - 0.5, 60, what="takeoff altitude")
    else:
        client.set_mode(GUIDED)
        client.wait(lambda: client.mode == GUIDED, 5, what="GUIDED")
    client.idle(1.0)


def reach_landing(client: Client) -> None:
    """Descending in LAND from about HOVER_ALT_M."""
    reach_flying(client)
    client.set_mode(LAND)
    client.wait(lambda: client.mode == LAND, 5, what="LAND")
    client.idle(1.0)


def reach_battery_failsafe(client: Client) -> None:
    """Flying on a fresh vehicle whose low-battery failsafe has fired (BATT_LOW_VOLT above the
    pack's voltage) and sent it home in RTL: a failsafe, with time left before it lands."""
    client.set_param("BATT_FS_LOW_ACT", 2)  # RTL
    reach_flying(client, 20.0)
    client.set_param("BATT_LOW_VOLT", 30.0)
    client.wait(lambda: client.mode == RTL, 30, what="the battery failsafe's RTL")
    client.idle(1.0)

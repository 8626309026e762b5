"""A vehicle's reboot in place (MAV_CMD_PREFLIGHT_REBOOT_SHUTDOWN), as ArduCopter SITL reboots.

ArduCopter SITL, once it has sent the ACK, waits 200 ms, saves what is pending and starts its
process again: the simulation and the boot clock start from zero, at the start position, and the
vehicle comes back with what it had saved (parameters, missions, fence, rally, the signing key).
A ground station keeps its link: it sees the vehicle go silent and then speak again (measured with
pymavlink on ArduCopter 4.7.0-dev SITL, commit 90700977: the first HEARTBEAT 1.2 s of wall time
after the ACK at speedup 1, 0.12 s at speedup 10; boot time about 1.0 s then, the clock having
started some 0.2 s after the ACK; the boot texts and the EKF's again after it, and nothing
streamed until asked; what was sent to it meanwhile is lost).

Here the process, its ports and each Node's link and router stay (so TCP clients stay connected,
where ArduPilot's restarted process makes them reconnect; frame sequence numbers go on); the
vehicle, its MAVLink session and its dataflash recorder are built again from the state directory,
by the same code that built them at start (the Node's power_on, from cli/main.py), with
ArduCopter's start-up (startup.py); the dataflash log of the boot that ends is closed, as a reboot
ends ArduPilot's. Sim time goes on: the new vehicle's clock starts at zero REBOOT_GAP_S after the
ACK, and it hears and says nothing before FIRST_HEARTBEAT_S of its own time.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..mavlink.link import Link
    from ..mavlink.session import Session
    from ..vehicle import Vehicle
    from .runner import Node

REBOOT_GAP_S = 0.2  # from the ACK to the new boot clock's zero (ArduPilot's reboot delay)
FIRST_HEARTBEAT_S = 1.0  # the rebooted vehicle's boot time at its first HEARTBEAT
# The power-on time is a sum of floats: rounded to the nanosecond, the new vehicle's steps fall on
# the runner's ticks as a first boot's do (run_until compares within 1 ns).
POWER_ON_DECIMALS = 9


def bind_link(link: Link, vehicle: Vehicle, session: Session) -> None:
    """Point the Node's link at this vehicle's session: its codec packs and signs, its signing
    judges; a message that will not pack is this vehicle's internal error."""
    link.codec, link.signing = session.codec, session.signing
    if link.faults is not None:  # SIM_LINK_* are the new vehicle's parameters
        link.faults.rebind(vehicle.params)
    link.on_unpackable = lambda exc, what: vehicle.internal_error(exc, f"packing {what}", in_flight_code=False)


def save_before_reboot(vehicle: Vehicle, session: Session) -> None:
    """What ArduPilot flushes before it restarts: the pending parameter and mission writes, and the
    signing state (its timestamp must not go back across the reboot)."""
    vehicle.params.file.flush()
    vehicle.mission.file.flush()
    if session.signing.enabled:
        session.signing.save()


def reboot(node: Node) -> None:
    """Replace the node's vehicle, session and dataflash recorder by freshly booted ones (keeping
    its ports, link, router, tlog and state log); the old ones are dropped."""
    old_vehicle, old_session, power_on = node.vehicle, node.session, node.power_on
    assert power_on is not None  # Node.reboot calls this only for a node that can be built again
    save_before_reboot(old_vehicle, old_session)
    powered_on_at_s = round(old_vehicle.powered_on_at_s + old_vehicle.time_s + REBOOT_GAP_S, POWER_ON_DECIMALS)
    # The vehicle's UNIX time goes on from where it was (SYSTEM_TIME's time_unix_usec; GPS time).
    epoch_us = old_vehicle.unix_time_us() + int(REBOOT_GAP_S * 1e6)
    if node.log_files is not None:
        node.log_files.stop()
    vehicle, session, node.dataflash, node.log_files = power_on(epoch_us=epoch_us, powered_on_at_s=powered_on_at_s)
    session.silent_until_s = FIRST_HEARTBEAT_S
    bind_link(node.link, vehicle, session)
    node.vehicle, node.session = vehicle, session
    node.router.lists_traffic = vehicle.lists_traffic  # the new vehicle's ADS-B list decides forwarding
    node.reboots += 1

"""The preflight commands, answered as ArduCopter SITL answers them: reboot, parameter storage,
calibrations, the banner (measured with pymavlink on ArduCopter 4.7.0-dev SITL, commit 90700977;
the parity suite's surface_commands area records them too).

- PREFLIGHT_REBOOT_SHUTDOWN: FAILED while armed (unless param 6 is ArduPilot's force-reboot magic
  20190226), or when ESC_CALIBRATION asks for an ESC calibration at boot ("Reboot rejected, ESC
  cal on reboot"); param 1 other than 1 (reboot) or 3 (reboot to the bootloader, which SITL
  reboots as 1) UNSUPPORTED; else ACCEPTED, and the vehicle reboots once the ACK is out (the I/O
  edge does it: autopilot/io/reboot.py).
- PREFLIGHT_STORAGE: param 1 = 2 erases the saved parameters (the values in use stay until the
  reboot), "All parameters reset, reboot board", ACCEPTED also in flight; anything else DENIED.
- PREFLIGHT_CALIBRATION: FAILED with "Disarm to allow calibration" while armed. Then, first match:
  param 1 = 1 gyros (ACCEPTED); param 3 = 1 barometer (its two texts); param 5 = 1 the interactive
  accelerometer calibration ("Place vehicle level and press any key.", ACCEPTED: the positions
  that follow are not modelled); 2 level (trim) and 4 simple accelerometer calibration, each
  TEMPORARILY_REJECTED within 5 s of boot or of the last one; 76 in param 5 or param 2 accepts
  the existing accelerometer or compass calibration; anything else UNSUPPORTED (the radio
  calibration flag of param 4 alone too). ArduCopter's compass-motor calibration (param 6 = 1)
  blocks its main loop until the ground station acknowledges: not modelled, UNSUPPORTED here.
- DO_SEND_BANNER: the banner texts (autopilot/version.py), ACCEPTED.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

from .. import version
from ..results import Result, Severity
from .dialect import mavlink as mav

if TYPE_CHECKING:
    from .commands import Command

FORCE_REBOOT_MAGIC = 20190226  # ArduPilot's: param 6 (COMMAND_INT y) lets an armed vehicle reboot
REBOOT, REBOOT_TO_BOOTLOADER = 1, 3
ESC_CALIBRATION_AT_BOOT = 3  # ESC_CALIBRATION "auto": a reboot would start an ESC calibration
ERASE_PARAMETERS = 2
CALIBRATE = 1
ACCEL_INTERACTIVE, ACCEL_LEVEL, ACCEL_SIMPLE = 1, 2, 4
FORCE_SAVE = 76  # accept the existing calibration as valid
ACCEL_CAL_SPACING_S = 5.0  # ArduPilot refuses a level or simple accelerometer calibration this soon


def _as_int_field(c: Command, value: float) -> float:
    """A COMMAND_LONG's param 5/6 as the x/y integer ArduPilot converts it to (Command keeps a
    COMMAND_INT's x/y in degrees)."""
    return value * 1e7 if c.is_int else value


def preflight_reboot(s, c: Command) -> Result:
    v = s.vehicle
    if v.params.get("ESC_CALIBRATION") == ESC_CALIBRATION_AT_BOOT:
        v.notify("Reboot rejected, ESC cal on reboot", Severity.CRITICAL)
        return Result.FAILED
    if v.armed and _as_int_field(c, c.p6) != FORCE_REBOOT_MAGIC:
        return Result.FAILED
    if c.p1 not in (REBOOT, REBOOT_TO_BOOTLOADER):  # NaN too
        return Result.UNSUPPORTED
    v.reboot_requested = True
    return Result.ACCEPTED


def preflight_storage(s, c: Command) -> Result:
    if c.p1 != ERASE_PARAMETERS:
        return Result.DENIED
    s.vehicle.params.erase_saved()
    s.vehicle.notify("All parameters reset, reboot board", Severity.WARNING)
    return Result.ACCEPTED


def preflight_calibration(s, c: Command) -> Result:
    v = s.vehicle
    if v.armed:
        v.notify("Disarm to allow calibration", Severity.NOTICE)
        return Result.FAILED
    if _as_int_field(c, c.p6) == CALIBRATE:
        return Result.UNSUPPORTED  # compass-motor calibration (ArduCopter asks first): see the module docstring
    if c.p1 == CALIBRATE:
        return Result.ACCEPTED  # the gyros: the simulated ones need no offsets
    if c.p3 == CALIBRATE:
        v.notify("Updating barometer calibration", Severity.INFO)
        v.notify("Barometer calibration complete", Severity.INFO)
        return Result.ACCEPTED
    accel = _as_int_field(c, c.p5)
    if accel == ACCEL_INTERACTIVE:
        v.notify("Place vehicle level and press any key.", Severity.CRITICAL)
        return Result.ACCEPTED
    if accel in (ACCEL_LEVEL, ACCEL_SIMPLE):
        if v.time_s - s.accel_calibrated_s < ACCEL_CAL_SPACING_S:
            return Result.TEMPORARILY_REJECTED
        s.accel_calibrated_s = v.time_s
        if accel == ACCEL_LEVEL:
            roll, pitch, _ = v.attitude
            v.notify(f"Trim OK: roll={math.degrees(roll):.2f} pitch={math.degrees(pitch):.2f} yaw=0.00",
                     Severity.INFO)
        return Result.ACCEPTED
    if accel == FORCE_SAVE or c.p2 == FORCE_SAVE:
        return Result.ACCEPTED
    return Result.UNSUPPORTED


def send_banner(s, c: Command) -> Result:
    s.send_banner()
    return Result.ACCEPTED


HANDLERS = {
    mav.MAV_CMD_PREFLIGHT_REBOOT_SHUTDOWN: preflight_reboot,
    mav.MAV_CMD_PREFLIGHT_STORAGE: preflight_storage,
    mav.MAV_CMD_PREFLIGHT_CALIBRATION: preflight_calibration,
    mav.MAV_CMD_DO_SEND_BANNER: send_banner,
}

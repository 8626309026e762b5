"""Small commands a ground station sends about the link, the board and its calibrations, answered
as ArduCopter SITL answers them (measured: tests/parity/probes/misc_commands.py). Joined into the
command table (commands.HANDLERS) as **HANDLERS.

Most change nothing a client can see on ArduCopter SITL either, and Firefly does the same:
- START_RX_PAIR starts a receiver's bind, which SITL's RC input has none of: ACCEPTED.
- AIRFRAME_CONFIGURATION moves the landing gear (AP_LandingGear), which a quad without LGR_*
  outputs has none of: ACCEPTED for any gear and position, no output moves.
- SCRIPTING: no scripts run (SCR_ENABLE 0); stopping them (2, and 3 with a restart) is ACCEPTED,
  the REPL (0, 1) DENIED, anything else UNSUPPORTED.
- EXTERNAL_WIND_ESTIMATE: a speed below 0 or a direction outside 0-360 is DENIED, else
  ACCEPTED; without drag fusion ArduCopter's WIND stays zero after it, as Firefly's does.
- DO_ACCEPT_MAG_CAL / DO_CANCEL_MAG_CAL with no calibration running: ACCEPTED; ACCELCAL_VEHICLE_POS
  with no accelerometer calibration waiting for a position: FAILED.
- DO_START_MAG_CAL: refused while armed, as AP_Compass refuses it; else ACCEPTED with a
  MAG_CAL_PROGRESS at once (tests/parity/probes/surface_commands.py). Firefly's compass is exact,
  so no calibration runs: the one report says it is waiting to start, and none follows it.
- FIXED_MAG_CAL_YAW: ACCEPTED in every state, as on SITL (the offsets it would set are zero for
  Firefly's exact compass).
- STORAGE_FORMAT: only param 1 = 1 (the card) with param 2 = 1 (format) is taken, anything else
  UNSUPPORTED; SITL has no card to format: FAILED (tests/parity/probes/camera.py camera_v2).
"""
from __future__ import annotations

from ..results import Result, Severity
from .dialect import mavlink as mav

SCRIPTING_STOP, SCRIPTING_STOP_AND_RESTART = mav.SCRIPTING_CMD_STOP, mav.SCRIPTING_CMD_STOP_AND_RESTART
SCRIPTING_REPL = (mav.SCRIPTING_CMD_REPL_START, mav.SCRIPTING_CMD_REPL_STOP)
MAV_CMD_EXTERNAL_WIND_ESTIMATE = 43004  # in MAVLink's development set, not yet in ardupilotmega's


def control_high_latency(s, c) -> Result:
    """Param 1 exactly 0 or 1 turns the high-latency links off or on, said at NOTICE (Firefly has
    no HIGH_LATENCY2 link: the normal link streams on, as it does on SITL); else FAILED."""
    if c.p1 not in (0.0, 1.0):
        return Result.FAILED
    s.vehicle.notify(f"High Latency {'enabled' if c.p1 == 1.0 else 'disabled'}", Severity.NOTICE)
    return Result.ACCEPTED


def accepted(s, c) -> Result:
    return Result.ACCEPTED


def failed(s, c) -> Result:
    return Result.FAILED


def start_mag_cal(s, c) -> Result:
    """As Compass::handle_mag_cal_command: armed first ("Disarm to allow compass calibration"
    at NOTICE, FAILED), then param 1, the compass mask, outside 0-255 FAILED (NaN too)."""
    if s.vehicle.armed:
        s.vehicle.notify("Disarm to allow compass calibration", Severity.NOTICE)
        return Result.FAILED
    if not 0 <= c.p1 <= 255:
        return Result.FAILED
    s.queue(s.codec.mag_cal_progress_encode(0, 1, mav.MAG_CAL_WAITING_TO_START, 1, 0, [0] * 10,
                                            0.0, 0.0, 0.0))
    return Result.ACCEPTED


def storage_format(s, c) -> Result:
    return Result.FAILED if c.p1 == 1 and c.p2 == 1 else Result.UNSUPPORTED


def scripting(s, c) -> Result:
    if c.p1 in (SCRIPTING_STOP, SCRIPTING_STOP_AND_RESTART):
        return Result.ACCEPTED
    return Result.DENIED if c.p1 in SCRIPTING_REPL else Result.UNSUPPORTED


def external_wind_estimate(s, c) -> Result:
    """Param 1 the speed [m/s], param 3 the direction [deg] (NaN compares false: ACCEPTED)."""
    if c.p1 < 0 or c.p3 < 0 or c.p3 > 360:
        return Result.DENIED
    return Result.ACCEPTED


def set_safety_switch_state(s, c) -> Result:
    """Param 1 SAFE (0) turns the safety on, DANGEROUS (1) off; anything else DENIED."""
    if c.p1 not in (mav.SAFETY_SWITCH_STATE_SAFE, mav.SAFETY_SWITCH_STATE_DANGEROUS):
        return Result.DENIED
    s.vehicle.set_safety_switch(c.p1 == mav.SAFETY_SWITCH_STATE_SAFE)
    return Result.ACCEPTED


HANDLERS = {
    mav.MAV_CMD_CONTROL_HIGH_LATENCY: control_high_latency,
    mav.MAV_CMD_START_RX_PAIR: accepted,
    mav.MAV_CMD_AIRFRAME_CONFIGURATION: accepted,
    mav.MAV_CMD_SCRIPTING: scripting,
    mav.MAV_CMD_STORAGE_FORMAT: storage_format,
    MAV_CMD_EXTERNAL_WIND_ESTIMATE: external_wind_estimate,
    mav.MAV_CMD_DO_SET_SAFETY_SWITCH_STATE: set_safety_switch_state,
    mav.MAV_CMD_DO_START_MAG_CAL: start_mag_cal,
    mav.MAV_CMD_FIXED_MAG_CAL_YAW: accepted,
    mav.MAV_CMD_DO_ACCEPT_MAG_CAL: accepted,
    mav.MAV_CMD_DO_CANCEL_MAG_CAL: accepted,
    mav.MAV_CMD_ACCELCAL_VEHICLE_POS: failed,
}

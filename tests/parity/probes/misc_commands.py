"""Small commands a ground station sends, with their parameters varied (the surface area sends
each once): what ArduCopter answers and what changes on the ground.

high_latency    MAV_CMD_CONTROL_HIGH_LATENCY 0, 1, 0 and 2: answers, texts, ATTITUDE still streamed.
rx_pair         MAV_CMD_START_RX_PAIR (Spektrum DSM2, and 5, 5): answers, texts.
landing_gear    MAV_CMD_AIRFRAME_CONFIGURATION retract and deploy, then with a landing-gear servo on
                output 9 (SERVO9_FUNCTION 29): answers, texts, output 9.
scripting       MAV_CMD_SCRIPTING 0 to 3 and 9: answers, texts.
wind            MAV_CMD_EXTERNAL_WIND_ESTIMATE 3 m/s from 90 deg, a negative speed, a direction of
                400 deg: answers, and WIND's direction and speed 2 s after each.
safety          MAV_CMD_DO_SET_SAFETY_SWITCH_STATE safe, then ARM (answer, "Arm"/"PreArm" texts),
                dangerous, ARM again, and a state of 7: answers; outputs 1-4 and 9 (DO_SET_SERVO
                1500) before and after.
safety_flying   safe at 40 m (what is said, outputs, height 1.5 s on, arming), then dangerous
                (height 3 s on).
calibration     MAV_CMD_DO_ACCEPT_MAG_CAL and DO_CANCEL_MAG_CAL with no calibration running, and
                MAV_CMD_ACCELCAL_VEHICLE_POS level: answers, texts.
"""
from __future__ import annotations

import re

from ..client import Client, mav
from ..facts import Tol, Trace
from .booting import each_on_a_fresh_vehicle
from .states import reach_flying
from .texts import said

AREA = "misc_commands"
# A fall read off the stream a second after the safety goes on: at 20x a client 50 ms late reads
# it a metre lower; at 5x, a quarter of that
FIREFLY_SPEEDUP = "5"
SAFE, DANGEROUS = mav.SAFETY_SWITCH_STATE_SAFE, mav.SAFETY_SWITCH_STATE_DANGEROUS
GEAR = 9  # the landing gear's servo output


def _command(c: Client, trace: Trace, name: str, command: int, *params: float, settle_s: float = 1.0,
             texts: bool = True) -> int:
    """The answer and (with texts) what was said within `settle_s`; the vehicle time it was sent."""
    t0 = c.now_ms
    trace.fact(f"{name}.result", c.command(command, *params))
    c.idle(settle_s)
    if texts:
        trace.fact(f"{name}.said", said(c.texts_since(t0, within_s=settle_s + 0.5)))
    return t0


def high_latency(c: Client, trace: Trace) -> None:
    for name, value in (("off", 0), ("on", 1), ("off_again", 0), ("two", 2)):
        _command(c, trace, name, mav.MAV_CMD_CONTROL_HIGH_LATENCY, value)
        seen = c.received.get("ATTITUDE", 0)
        c.idle(1.0)
        trace.fact(f"{name}.attitude_streamed", c.received.get("ATTITUDE", 0) > seen)


def rx_pair(c: Client, trace: Trace) -> None:
    _command(c, trace, "dsm2", mav.MAV_CMD_START_RX_PAIR, 0, 0)
    _command(c, trace, "five", mav.MAV_CMD_START_RX_PAIR, 5, 5)


def _output(c: Client, n: int) -> int:
    c.fresh("SERVO_OUTPUT_RAW")
    return getattr(c.last["SERVO_OUTPUT_RAW"], f"servo{n}_raw")


def landing_gear(c: Client, trace: Trace) -> None:
    _command(c, trace, "retract", mav.MAV_CMD_AIRFRAME_CONFIGURATION, -1, 1)
    _command(c, trace, "deploy", mav.MAV_CMD_AIRFRAME_CONFIGURATION, -1, 0)
    trace.fact("servo.set", c.set_param(f"SERVO{GEAR}_FUNCTION", 29))
    c.idle(1.0)
    trace.fact("servo.output", _output(c, GEAR))
    for name, position in (("servo_retract", 1), ("servo_deploy", 0), ("servo_seven", 7)):
        _command(c, trace, name, mav.MAV_CMD_AIRFRAME_CONFIGURATION, -1, position)
        trace.fact(f"{name}.output", _output(c, GEAR))


def scripting(c: Client, trace: Trace) -> None:
    for value in (0, 1, 2, 3, 9):
        _command(c, trace, f"cmd{value}", mav.MAV_CMD_SCRIPTING, value)


def _wind(c: Client) -> list:
    c.fresh("WIND")
    m = c.last["WIND"]
    return [round(m.direction), round(m.speed, 1)]


def wind(c: Client, trace: Trace) -> None:
    c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_WIND, 200_000)
    c.idle(1.0)
    trace.fact("before.wind", _wind(c))
    near = Tol(abs=1.0, why="the estimate's direction [deg] and speed [m/s], read 2 s on")
    for name, params in (("east_3", (3, 1, 90, 10)), ("negative", (-1, 1, 90, 10)), ("dir_400", (3, 1, 400, 10))):
        _command(c, trace, name, mav.MAV_CMD_EXTERNAL_WIND_ESTIMATE, *params, settle_s=2.0)
        trace.fact(f"{name}.wind", _wind(c), near)


def _arm(c: Client, trace: Trace, name: str) -> None:
    t0 = c.now_ms
    trace.fact(f"{name}.result", c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1))
    c.idle(1.6)
    # (the periodic "PreArm:" report may come before or after the ARM's own "Arm:")
    trace.fact(f"{name}.texts", sorted({t for t in c.texts_since(t0) if t.startswith(("Arm", "PreArm"))}))
    c.fresh_heartbeat()
    trace.fact(f"{name}.armed", c.armed)
    if c.armed:
        c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0)
        c.wait(lambda: not c.armed, 5, what="disarmed")


def _outputs(c: Client) -> list[int]:
    c.fresh("SERVO_OUTPUT_RAW")
    m = c.last["SERVO_OUTPUT_RAW"]
    return [m.servo1_raw, m.servo2_raw, m.servo3_raw, m.servo4_raw, m.servo9_raw]


def safety(c: Client, trace: Trace) -> None:
    c.idle(5.0)  # past the 4 s a pre-arm report that begins failing waits for since the last one (from boot)
    trace.fact("servo9.result", c.command(mav.MAV_CMD_DO_SET_SERVO, 9, 1500))
    c.idle(0.5)
    trace.fact("before.outputs", _outputs(c))
    _command(c, trace, "safe", mav.MAV_CMD_DO_SET_SAFETY_SWITCH_STATE, SAFE)
    trace.fact("safe.outputs", _outputs(c))
    _arm(c, trace, "safe_arm")
    _command(c, trace, "dangerous", mav.MAV_CMD_DO_SET_SAFETY_SWITCH_STATE, DANGEROUS)
    trace.fact("dangerous.outputs", _outputs(c))
    _arm(c, trace, "dangerous_arm")
    _command(c, trace, "seven", mav.MAV_CMD_DO_SET_SAFETY_SWITCH_STATE, 7)


def safety_flying(c: Client, trace: Trace) -> None:
    reach_flying(c, 40.0)
    t0 = _command(c, trace, "safe", mav.MAV_CMD_DO_SET_SAFETY_SWITCH_STATE, SAFE, settle_s=1.5, texts=False)
    # which motor the thrust-loss text names is the one last asked for most: with every output
    # cut they are all at the top, and ArduCopter names 2 in one run and 3 in the next
    trace.fact("safe.said", [re.sub(r"Thrust Loss \(\d\)", "Thrust Loss (motor)", text)
                             for text in said(c.texts_since(t0, within_s=2.0))])
    trace.fact("safe.outputs", _outputs(c))
    trace.fact("safe.alt_m", round(c.rel_alt_m()), Tol(abs=2.5, why="a fall 1.5 s long read off a 10 Hz stream"))
    c.fresh_heartbeat()
    trace.fact("safe.armed", c.armed)
    _command(c, trace, "dangerous", mav.MAV_CMD_DO_SET_SAFETY_SWITCH_STATE, DANGEROUS, settle_s=3.0)
    trace.fact("dangerous.alt_m", round(c.rel_alt_m()), Tol(abs=3.0, why="each airframe's fall and recovery"))
    c.fresh_heartbeat()
    trace.fact("dangerous.armed", c.armed)


def calibration(c: Client, trace: Trace) -> None:
    _command(c, trace, "accept_mag", mav.MAV_CMD_DO_ACCEPT_MAG_CAL, 0)
    _command(c, trace, "cancel_mag", mav.MAV_CMD_DO_CANCEL_MAG_CAL, 0)
    _command(c, trace, "accel_level", mav.MAV_CMD_ACCELCAL_VEHICLE_POS, mav.ACCELCAL_VEHICLE_POS_LEVEL)


PROBES = {"high_latency": high_latency, "rx_pair": rx_pair, "landing_gear": landing_gear, "scripting": scripting,
          "wind": wind, "safety": safety, "safety_flying": safety_flying, "calibration": calibration}


def run(target) -> dict[str, Trace]:
    return each_on_a_fresh_vehicle(target, PROBES, {name: None for name in PROBES})

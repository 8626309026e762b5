"""ArduCopter's numbering of this airframe's motors, the order its outputs report them in.

The sim numbers the plus quad's motors as the paper's mixer does: 1 front, 2 left, 3 back, 4
right (sim/airframe.py). ArduCopter's QUAD PLUS (FRAME_CLASS 1, FRAME_TYPE 0) drives motor 1 on
output 1 (SERVO1_FUNCTION 33) and so on, and places them 1 right, 2 left, 3 front, 4 back, 1 and
2 turning the other way from 3 and 4 (measured on its SITL, tests/parity/probes/payload_outputs.py
motor_order: rolling right output 2 works harder than 1, pitching down 4 than 3, turning the nose
right 1 and 2 than 3 and 4). SERVO_OUTPUT_RAW, ESC telemetry, the log's RCOU and the texts that
name a motor use ArduCopter's numbers.
"""
from __future__ import annotations

import math
from typing import TypeVar

T = TypeVar("T")

OUTPUT_OF_MOTOR = (3, 2, 4, 1)  # the sim's motor 1, 2, 3, 4 -> ArduCopter's motor (output) number
MOTOR_ON_OUTPUT = tuple(OUTPUT_OF_MOTOR.index(n) for n in (1, 2, 3, 4))  # output 1-4 -> the sim's motor (0-based)


def in_output_order(per_motor: tuple[T, T, T, T]) -> list[T]:
    """Four per-motor values (the sim's order) in ArduCopter's output order."""
    return [per_motor[i] for i in MOTOR_ON_OUTPUT]


def omega_of_pwm(pwm: int, low: int, high: int, spin_min: float, spin_max: float, expo: float,
                 omega_idle: float, omega_max: float) -> float:
    """The rotor speed a PWM written straight to a motor gives (a motor test): the inverse of the
    output mapping SERVO_OUTPUT_RAW reports (sensor_messages.motor_pwm), so the test's PWM flies
    as the same PWM would in flight. Below MOT_SPIN_MIN a motor turns without lifting, up to
    ground idle's speed there; at or below MOT_PWM_MIN it stands."""
    share = (pwm - low) / (high - low) if high > low else 0.0
    if share <= 0.0:
        return 0.0
    if share <= spin_min or spin_max <= spin_min:
        return omega_idle * min(share / spin_min, 1.0) if spin_min > 0.0 else omega_idle
    throttle = min((share - spin_min) / (spin_max - spin_min), 1.0)
    thrust = (1.0 - expo) * throttle + expo * throttle * throttle  # MOT_THST_EXPO's curve
    return max(omega_max * math.sqrt(max(thrust, 0.0)), omega_idle)

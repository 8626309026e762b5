"""The whole vehicle's physics step: motors -> rotor forces -> mixer -> rigid body -> ground.

`step` is pure: it takes plain state and returns new plain state.
"""
from __future__ import annotations

from typing import NamedTuple

from .airframe import Airframe
from .rigid_body import BodyState, apply_ground, step_body
from .rotors import mix_forces, rotor_forces, step_motors


class PhysicsState(NamedTuple):
    body: BodyState
    omega_rad_s: tuple  # four motor speeds
    on_ground: bool


def initial_state(yaw_rad: float = 0.0, n_m: float = 0.0, e_m: float = 0.0) -> PhysicsState:
    from .rigid_body import quaternion_from_euler
    qw, qx, qy, qz = quaternion_from_euler(0.0, 0.0, yaw_rad)
    return PhysicsState(BodyState(n_m=n_m, e_m=e_m, qw=qw, qx=qx, qy=qy, qz=qz),
                        (0.0, 0.0, 0.0, 0.0), True)


def step(state: PhysicsState, omega_cmd: tuple, airframe: Airframe, wind_ned: tuple,
         dt: float, motor_lag: float) -> PhysicsState:
    """Advance by dt. `motor_lag` is rotors.motor_lag_factor(airframe, dt), computed once."""
    omega = step_motors(state.omega_rad_s, omega_cmd, motor_lag, airframe.omega_max_rad_s)
    forces = rotor_forces(omega, airframe.thrust_coeff_b)
    u = mix_forces(forces, airframe.arm_length_m, airframe.torque_ratio_c)
    body, on_ground = apply_ground(step_body(state.body, u, airframe, wind_ned, dt))
    return PhysicsState(body, omega, on_ground)

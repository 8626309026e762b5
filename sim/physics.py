"""The whole vehicle's physics step: motors -> rotor forces -> mixer -> rigid body -> ground.

`step` is pure: it takes plain state and returns new plain state.
"""
from __future__ import annotations

from typing import NamedTuple

from .airframe import GRAVITY_M_S2, Airframe
from .rigid_body import BodyState, apply_ground, ned_to_body, step_body
from .rotors import HEALTHY, mix_forces, rotor_forces, step_motors


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
         dt: float, motor_lag: float, speed_scale: tuple = HEALTHY) -> PhysicsState:
    """Advance by dt. `motor_lag` is rotors.motor_lag_factor(airframe, dt), computed once;
    `speed_scale` is each motor's health (rotors.step_motors)."""
    omega = step_motors(state.omega_rad_s, omega_cmd, motor_lag, airframe.omega_max_rad_s, speed_scale)
    forces = rotor_forces(omega, airframe.thrust_coeff_b)
    u = mix_forces(forces, airframe.arm_length_m, airframe.torque_ratio_c)
    body, on_ground = apply_ground(step_body(state.body, u, airframe, wind_ned, dt))
    return PhysicsState(body, omega, on_ground)


def fast_step_constants(airframe: Airframe, dt: float) -> dict:
    """The numbers the hot path binds, by the names make_fast_step gives them. The compiled twin
    reads the same dict by the same names (physics.h's PhysicsConstants, autopilot/control/by_name.h),
    so a number added or renamed on one side only is a KeyError, not a silent mix-up."""
    from .rotors import motor_lag_factor
    return {"m": airframe.mass_kg, "ixx": airframe.ixx_kg_m2, "iyy": airframe.iyy_kg_m2,
            "izz": airframe.izz_kg_m2, "b": airframe.thrust_coeff_b, "arm": airframe.arm_length_m,
            "c": airframe.torque_ratio_c, "k": airframe.linear_drag_n_per_m_s,
            "kr": airframe.angular_drag_nm_per_rad_s, "lag": motor_lag_factor(airframe, dt),
            "w_max": airframe.omega_max_rad_s, "g": GRAVITY_M_S2, "half": 0.5 * dt, "dt": dt}


def make_fast_step(airframe: Airframe, dt: float):
    """The same step as `step`, specialised for one airframe and dt: constants bound once, the
    motor, mixer and rigid-body arithmetic inlined over plain floats. Returns
    fast_step(state, omega_cmd, wind_ned, speed_scale) -> PhysicsState; a test checks it agrees
    with `step`.
    This is the hot path: at 400 Hz it runs 400 times per simulated second for every vehicle.
    Its C twin is physics.h (used by the compiled cascade).
    """
    bound = fast_step_constants(airframe, dt)
    m, ixx, iyy, izz = bound["m"], bound["ixx"], bound["iyy"], bound["izz"]
    b, arm, c, k, kr = bound["b"], bound["arm"], bound["c"], bound["k"], bound["kr"]
    lag, w_max, g, half, dt = bound["lag"], bound["w_max"], bound["g"], bound["half"], bound["dt"]
    sqrt, new_body, new_state = __import__("math").sqrt, BodyState._make, PhysicsState

    def fast_step(state: PhysicsState, omega_cmd: tuple, wind_ned: tuple,
                  speed_scale: tuple = HEALTHY) -> PhysicsState:
        n, e, d, vn, ve, vd, qw, qx, qy, qz, p, q, r = state.body
        o1, o2, o3, o4 = state.omega_rad_s
        c1, c2, c3, c4 = omega_cmd
        s1, s2, s3, s4 = speed_scale
        o1 += ((0.0 if c1 < 0.0 else w_max if c1 > w_max else c1) * s1 - o1) * lag
        o2 += ((0.0 if c2 < 0.0 else w_max if c2 > w_max else c2) * s2 - o2) * lag
        o3 += ((0.0 if c3 < 0.0 else w_max if c3 > w_max else c3) * s3 - o3) * lag
        o4 += ((0.0 if c4 < 0.0 else w_max if c4 > w_max else c4) * s4 - o4) * lag
        f1, f2, f3, f4 = b * o1 * o1, b * o2 * o2, b * o3 * o3, b * o4 * o4
        u1 = f1 + f2 + f3 + f4
        r02 = 2.0 * (qx * qz + qw * qy)
        r12 = 2.0 * (qy * qz - qw * qx)
        r22 = 1.0 - 2.0 * (qx * qx + qy * qy)
        vn += (-u1 * r02 - k * (vn - wind_ned[0])) / m * dt
        ve += (-u1 * r12 - k * (ve - wind_ned[1])) / m * dt
        vd += ((-u1 * r22 - k * (vd - wind_ned[2])) / m + g) * dt
        p, q, r = (p + (arm * (f2 - f4) - (izz - iyy) * q * r - kr * p) / ixx * dt,
                   q + (arm * (f1 - f3) - (ixx - izz) * r * p - kr * q) / iyy * dt,
                   r + (c * (f1 - f2 + f3 - f4) - (iyy - ixx) * p * q - kr * r) / izz * dt)
        nw = qw + half * (-qx * p - qy * q - qz * r)
        nx = qx + half * (qw * p + qy * r - qz * q)
        ny = qy + half * (qw * q - qx * r + qz * p)
        nz = qz + half * (qw * r + qx * q - qy * p)
        inv = 1.0 / sqrt(nw * nw + nx * nx + ny * ny + nz * nz)
        body = new_body((n + vn * dt, e + ve * dt, d + vd * dt, vn, ve, vd,
                         nw * inv, nx * inv, ny * inv, nz * inv, p, q, r))
        if body[2] >= 0.0:  # at or below the ground: the contact rules decide
            body, on_ground = apply_ground(body)
            return new_state(body, (o1, o2, o3, o4), on_ground)
        return new_state(body, (o1, o2, o3, o4), False)

    return fast_step


def specific_force_body(state: PhysicsState, airframe: Airframe, wind_ned: tuple) -> tuple:
    """What an accelerometer at the centre of mass reads (FRD body frame, m/s^2): every force
    but gravity, per unit mass. Resting on the ground the ground's push reads as 1 g up; in the
    air, the rotors' thrust along body -z and the drag of the air moving past."""
    s = state.body
    if state.on_ground:
        return ned_to_body(s, (0.0, 0.0, -GRAVITY_M_S2))
    thrust = sum(rotor_forces(state.omega_rad_s, airframe.thrust_coeff_b))
    k, m = airframe.linear_drag_n_per_m_s, airframe.mass_kg
    drag = ned_to_body(s, (-k * (s.vn_m_s - wind_ned[0]) / m, -k * (s.ve_m_s - wind_ned[1]) / m,
                           -k * (s.vd_m_s - wind_ned[2]) / m))
    return (drag[0], drag[1], drag[2] - thrust / m)

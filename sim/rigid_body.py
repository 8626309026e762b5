"""Rigid-body quadrotor dynamics: a pure step over plain state.

Translational (NED): m a = R_body_to_ned (0, 0, -U1) + m g e_z - k_drag (v - wind)
Rotational (FRD):    I w_dot = (U2, U3, U4) - w x (I w) - k_rot w
The paper writes the rotational part in its small-angle form; this is the full equation.
Integrated with semi-implicit Euler (velocities first, then positions with the new velocities),
which is stable at the 400 Hz+ physics rates used here and costs a fraction of RK4.
"""
from __future__ import annotations

import math
from typing import NamedTuple

from .airframe import GRAVITY_M_S2, Airframe


class BodyState(NamedTuple):
    n_m: float = 0.0
    e_m: float = 0.0
    d_m: float = 0.0
    vn_m_s: float = 0.0
    ve_m_s: float = 0.0
    vd_m_s: float = 0.0
    qw: float = 1.0
    qx: float = 0.0
    qy: float = 0.0
    qz: float = 0.0
    p_rad_s: float = 0.0
    q_rad_s: float = 0.0
    r_rad_s: float = 0.0


def quaternion_from_euler(roll: float, pitch: float, yaw: float) -> tuple:
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return (cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy,
            cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy)


def euler_from_quaternion(qw: float, qx: float, qy: float, qz: float) -> tuple:
    """(roll, pitch, yaw) in radians, ZYX convention (aerospace)."""
    roll = math.atan2(2 * (qw * qx + qy * qz), 1 - 2 * (qx * qx + qy * qy))
    sinp = 2 * (qw * qy - qz * qx)
    pitch = math.asin(max(-1.0, min(1.0, sinp)))
    yaw = math.atan2(2 * (qw * qz + qx * qy), 1 - 2 * (qy * qy + qz * qz))
    return roll, pitch, yaw


def step_body(s: BodyState, u: tuple, airframe: Airframe, wind_ned: tuple, dt: float) -> BodyState:
    """One semi-implicit Euler step of the free rigid body (no ground)."""
    u1, u2, u3, u4 = u
    m = airframe.mass_kg
    ixx, iyy, izz = airframe.ixx_kg_m2, airframe.iyy_kg_m2, airframe.izz_kg_m2
    qw, qx, qy, qz = s.qw, s.qx, s.qy, s.qz
    # Third column of R_body_to_ned: where body -z thrust points in NED.
    r02 = 2.0 * (qx * qz + qw * qy)
    r12 = 2.0 * (qy * qz - qw * qx)
    r22 = 1.0 - 2.0 * (qx * qx + qy * qy)
    k = airframe.linear_drag_n_per_m_s
    an = (-u1 * r02 - k * (s.vn_m_s - wind_ned[0])) / m
    ae = (-u1 * r12 - k * (s.ve_m_s - wind_ned[1])) / m
    ad = (-u1 * r22 - k * (s.vd_m_s - wind_ned[2])) / m + GRAVITY_M_S2
    p, q, r = s.p_rad_s, s.q_rad_s, s.r_rad_s
    kr = airframe.angular_drag_nm_per_rad_s
    p_dot = (u2 - (izz - iyy) * q * r - kr * p) / ixx
    q_dot = (u3 - (ixx - izz) * r * p - kr * q) / iyy
    r_dot = (u4 - (iyy - ixx) * p * q - kr * r) / izz
    vn, ve, vd = s.vn_m_s + an * dt, s.ve_m_s + ae * dt, s.vd_m_s + ad * dt
    p, q, r = p + p_dot * dt, q + q_dot * dt, r + r_dot * dt
    h = 0.5 * dt
    nw = qw + h * (-qx * p - qy * q - qz * r)
    nx = qx + h * (qw * p + qy * r - qz * q)
    ny = qy + h * (qw * q - qx * r + qz * p)
    nz = qz + h * (qw * r + qx * q - qy * p)
    norm = 1.0 / math.sqrt(nw * nw + nx * nx + ny * ny + nz * nz)
    return BodyState(s.n_m + vn * dt, s.e_m + ve * dt, s.d_m + vd * dt, vn, ve, vd,
                     nw * norm, nx * norm, ny * norm, nz * norm, p, q, r)


def apply_ground(s: BodyState, ground_d_m: float = 0.0) -> tuple[BodyState, bool]:
    """Ground contact: a body at or below the ground rests on it.

    Returns the corrected state and whether it is in contact. A body that reaches the ground
    moving down is stopped there (no sinking, no bounce); while resting, friction holds it and
    the ground levels it, keeping its heading. Upward motion leaves the ground untouched.
    """
    if s.d_m < ground_d_m:
        return s, False
    if s.vd_m_s < 0.0:  # climbing away: lift-off
        return s._replace(d_m=ground_d_m), False
    _, _, yaw = euler_from_quaternion(s.qw, s.qx, s.qy, s.qz)
    qw, qx, qy, qz = quaternion_from_euler(0.0, 0.0, yaw)
    return BodyState(s.n_m, s.e_m, ground_d_m, 0.0, 0.0, 0.0, qw, qx, qy, qz, 0.0, 0.0, 0.0), True


def ned_to_body(s: BodyState, v_ned: tuple) -> tuple:
    """A vector in NED expressed in the body's FRD frame (R_body_to_ned transposed)."""
    qw, qx, qy, qz = s.qw, s.qx, s.qy, s.qz
    x, y, z = v_ned
    return ((1.0 - 2.0 * (qy * qy + qz * qz)) * x + 2.0 * (qx * qy + qw * qz) * y + 2.0 * (qx * qz - qw * qy) * z,
            2.0 * (qx * qy - qw * qz) * x + (1.0 - 2.0 * (qx * qx + qz * qz)) * y + 2.0 * (qy * qz + qw * qx) * z,
            2.0 * (qx * qz + qw * qy) * x + 2.0 * (qy * qz - qw * qx) * y + (1.0 - 2.0 * (qx * qx + qy * qy)) * z)

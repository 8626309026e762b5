"""Outer loops of the paper's cascade: position -> velocity -> acceleration -> lean angles, and
altitude -> climb rate -> vertical acceleration -> total thrust U1 with m*g feed-forward.

Velocity targets from position errors use a square-root controller (linear near the target,
constant deceleration further out) and are slewed at the acceleration limit, so a step in the
target never asks for more than the configured acceleration.

Vector lengths are sqrt(x*x + y*y) rather than math.hypot: the compiled twin (cascade.h) can then
compute the very same bits, and these magnitudes are far from overflow.
"""
from __future__ import annotations

import math

from firefly.sim.airframe import GRAVITY_M_S2, Airframe

from .pid import Pid


def sqrt_controller(error: float, p: float, accel_max: float) -> float:
    """ArduPilot's shaping: v = p*e near zero, sqrt(2 a |e|) beyond, continuous at the join."""
    if accel_max <= 0.0 or p <= 0.0:
        return error * p
    linear = accel_max / (p * p)
    if abs(error) <= linear:
        return error * p
    return math.copysign(math.sqrt(2.0 * accel_max * (abs(error) - linear / 2.0)), error)


def stopping_distance(speed: float, p: float, accel_max: float) -> float:
    """How far the square-root controller takes to bring `speed` to rest (its inverse): speed/p
    up to the speed accel/p, then accel/(2p^2) + speed^2/(2 accel)."""
    if p <= 0.0:
        return speed * speed / (2.0 * accel_max) if accel_max > 0.0 else 0.0
    if accel_max <= 0.0 or abs(speed) < accel_max / p:
        return speed / p
    return math.copysign(accel_max / (2.0 * p * p) + speed * speed / (2.0 * accel_max), speed)


def stopping_point_ne(n: float, e: float, vn: float, ve: float, p: float, accel_max: float,
                      speed_max: float = math.inf) -> tuple:
    """Where the position controller brings a vehicle at (n, e) moving at (vn, ve) to rest: the
    stopping distance of its speed (at most speed_max) along its velocity, as ArduCopter's
    AC_PosControl::get_stopping_point_NE."""
    speed = math.sqrt(vn * vn + ve * ve)
    if speed < 1e-6:
        return n, e
    k = stopping_distance(min(speed, speed_max), p, accel_max) / speed
    return n + vn * k, e + ve * k


MEASURED_D_HZ = 20.0  # the filter of D on the measured velocity (Pid's default)


class PositionController:
    def __init__(self, airframe: Airframe, params):
        self.mass = airframe.mass_kg
        self.weight = airframe.weight_n
        self.thrust_max = 4.0 * airframe.max_rotor_thrust_n
        self.vel_pid_n = Pid(0)
        self.vel_pid_e = Pid(0)
        self.vel_pid_d = Pid(0)
        self.vel_target_ne = [0.0, 0.0]
        self.vel_target_d = 0.0
        self.configure(params)

    def configure(self, params) -> None:
        self.pos_xy_p = params["PSC_POSXY_P"]
        self.pos_z_p = params["PSC_POSZ_P"]
        for pid in (self.vel_pid_n, self.vel_pid_e):
            pid.kp, pid.ki, pid.kd = params["PSC_VELXY_P"], params["PSC_VELXY_I"], params["PSC_VELXY_D"]
            pid.imax = params["PSC_VELXY_IMAX"] / 100.0
        fltd = params["PSC_VELXY_FLTD"]
        self.vel_fltd_hz = fltd if fltd > 0.0 else math.inf  # 0: unfiltered (an alpha of 1)
        self.vel_pid_d.kp, self.vel_pid_d.ki = params["PSC_VELZ_P"], params["PSC_VELZ_I"]
        self.vel_pid_d.imax = params["PSC_VELZ_IMAX"] / 100.0
        self.accel_xy_max = params["WPNAV_ACCEL"] / 100.0
        self.lean_max = math.radians(params["ANGLE_MAX"] / 100.0)
        self.speed_up = params["WPNAV_SPEED_UP"] / 100.0
        self.speed_dn = params["WPNAV_SPEED_DN"] / 100.0
        self.accel_z_max = 2.5

    def reset(self, vel_ne: tuple, vel_d: float) -> None:
        """Bumpless hand-over: start the velocity targets from the current velocity."""
        self.vel_target_ne = [vel_ne[0], vel_ne[1]]
        self.vel_target_d = vel_d
        for pid in (self.vel_pid_n, self.vel_pid_e, self.vel_pid_d):
            pid.reset()

    def _slew(self, current: float, desired: float, limit: float, dt: float) -> float:
        step = limit * dt
        return current + max(-step, min(step, desired - current))

    def horizontal(self, pos_t, vel_ff: tuple, speed_max: float, pos: tuple, vel: tuple,
                   yaw: float, dt: float, accel_ff=None) -> tuple:
        """Returns (roll, pitch) targets. pos_t None = velocity control on vel_ff. accel_ff, when
        given, is the acceleration of a trajectory already shaped within the limits (waypoint
        navigation): its velocity is followed without slewing, its acceleration fed forward."""
        vn_d, ve_d = vel_ff
        if pos_t is not None:
            en, ee = pos_t[0] - pos[0], pos_t[1] - pos[1]
            dist = math.sqrt(en * en + ee * ee)
            if dist > 1e-6:
                v = sqrt_controller(dist, self.pos_xy_p, self.accel_xy_max)
                vn_d += v * en / dist
                ve_d += v * ee / dist
        speed = math.sqrt(vn_d * vn_d + ve_d * ve_d)
        if speed > speed_max > 0.0:
            vn_d, ve_d = vn_d * speed_max / speed, ve_d * speed_max / speed
        # A shaped trajectory's velocity (LOITER's point, a leg) is followed as AC_PosControl's
        # velocity PID does, with D on the error (filtered at FLTD): a vehicle keeping up with
        # its target's own acceleration is not held back. On the measurement, D resisted every
        # change of speed and P and I had to make up for it: braking into a proximity margin
        # with the stick held, the vehicle ran 1.5 m past its point and wound the integrator up
        # enough to be thrown back 3 m, then on through the wall. A slewed target (below) has
        # corners where its acceleration steps, which D on the error would kick: there D stays
        # on the measurement, filtered as before.
        self._d_on_error(accel_ff is not None)
        if accel_ff is not None:
            self.vel_target_ne[0], self.vel_target_ne[1] = vn_d, ve_d
            an = accel_ff[0] + self.vel_pid_n.update(vn_d, vel[0], dt)
            ae = accel_ff[1] + self.vel_pid_e.update(ve_d, vel[1], dt)
            return self.lean_from_accel(an, ae, yaw)
        # Slew the velocity target as a vector so a diagonal move keeps its heading.
        dn, de = vn_d - self.vel_target_ne[0], ve_d - self.vel_target_ne[1]
        change = math.sqrt(dn * dn + de * de)
        step = self.accel_xy_max * dt
        if change > step:
            dn, de = dn * step / change, de * step / change
        self.vel_target_ne[0] += dn
        self.vel_target_ne[1] += de
        # The slew's own acceleration is fed forward, so the PID only corrects tracking error.
        an = dn / dt + self.vel_pid_n.update(self.vel_target_ne[0], vel[0], dt)
        ae = de / dt + self.vel_pid_e.update(self.vel_target_ne[1], vel[1], dt)
        return self.lean_from_accel(an, ae, yaw)

    def _d_on_error(self, shaped: bool) -> None:
        on_error, hz = (1.0, self.vel_fltd_hz) if shaped else (0.0, MEASURED_D_HZ)
        self.vel_pid_n.set_d_on_error(on_error, hz)
        self.vel_pid_e.set_d_on_error(on_error, hz)

    def lean_from_accel(self, an: float, ae: float, yaw: float) -> tuple:
        a_max = GRAVITY_M_S2 * math.tan(self.lean_max)
        a = math.sqrt(an * an + ae * ae)
        if a > a_max:
            an, ae = an * a_max / a, ae * a_max / a
        # Rotate into the heading frame: forward and right accelerations.
        cy, sy = math.cos(yaw), math.sin(yaw)
        a_fwd = an * cy + ae * sy
        a_right = -an * sy + ae * cy
        pitch = math.atan2(-a_fwd, GRAVITY_M_S2)
        roll = math.atan2(a_right * math.cos(pitch), GRAVITY_M_S2)
        return roll, pitch

    def vertical(self, pos_d_t, vel_d_ff: float, pos_d: float, vel_d: float, roll: float,
                 pitch: float, dt: float, speed_up: float | None = None,
                 speed_dn: float | None = None) -> float:
        """Returns the total thrust U1 [N]. pos_d_t None = climb-rate control on vel_d_ff."""
        up = self.speed_up if speed_up is None else speed_up
        dn = self.speed_dn if speed_dn is None else speed_dn
        vd_t = vel_d_ff
        if pos_d_t is not None:
            vd_t += sqrt_controller(pos_d_t - pos_d, self.pos_z_p, self.accel_z_max)
        vd_t = max(-up, min(dn, vd_t))
        self.vel_target_d = self._slew(self.vel_target_d, vd_t, self.accel_z_max * 2.0, dt)
        accel_d = self.vel_pid_d.update(self.vel_target_d, vel_d, dt)
        return self.thrust_for(accel_d, roll, pitch)

    def thrust_for(self, accel_d: float, roll: float, pitch: float) -> float:
        tilt = max(math.cos(roll) * math.cos(pitch), 0.5)
        u1 = self.mass * (GRAVITY_M_S2 - accel_d) / tilt
        return max(0.0, min(self.thrust_max, u1))

    def thrust_from_stick(self, stick: float) -> float:
        """STABILIZE throttle curve: mid stick = hover thrust, full stick = full thrust
        (stick_for_thrust_share is its inverse)."""
        hover = self.weight
        if stick <= 0.5:
            return 2.0 * stick * hover
        return hover + (stick - 0.5) * 2.0 * (self.thrust_max - hover)


def stick_for_thrust_share(share: float, hover_share: float) -> float:
    """The manual-throttle stick that asks for `share` of full thrust: the inverse of
    PositionController.thrust_from_stick's curve, which puts the hover at mid stick."""
    if share <= hover_share:
        return 0.5 * share / hover_share
    return 0.5 + 0.5 * (share - hover_share) / (1.0 - hover_share)

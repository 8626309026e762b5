"""Inner loop of the paper's cascade: attitude angles -> body rates -> torques U2..U4.

Angle errors go through a P gain to Euler-rate targets, which are turned into body-rate targets;
a PID per axis turns the rate error into a normalised output (-1..1, as ArduPilot's rate
controller), scaled by the largest torque the rotors can give about that axis.
"""
from __future__ import annotations

import math

from firefly.sim.airframe import Airframe

from .pid import Pid


def wrap_pi(angle: float) -> float:
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


class AttitudeController:
    def __init__(self, airframe: Airframe, params):
        f_max = airframe.max_rotor_thrust_n
        self.roll_torque_max = airframe.arm_length_m * f_max
        self.pitch_torque_max = airframe.arm_length_m * f_max
        self.yaw_torque_max = 2.0 * airframe.torque_ratio_c * f_max
        self.rate_pids = [Pid(0, 0, 0, out_limit=1.0) for _ in range(3)]
        self.configure(params)

    def configure(self, params) -> None:
        self.angle_p = (params["ATC_ANG_RLL_P"], params["ATC_ANG_PIT_P"], params["ATC_ANG_YAW_P"])
        for pid, axis in zip(self.rate_pids, ("RLL", "PIT", "YAW")):
            pid.kp = params[f"ATC_RAT_{axis}_P"]
            pid.ki = params[f"ATC_RAT_{axis}_I"]
            pid.kd = params[f"ATC_RAT_{axis}_D"]
            pid.imax = params[f"ATC_RAT_{axis}_IMAX"]
            # ArduCopter's D acts on the error of a target filtered at FLTT; that is close to D on
            # the measurement, except with FLTT 0 (AUTOTUNE's twitches), where a step kicks it.
            pid.d_on_error = 1.0 if params[f"ATC_RAT_{axis}_FLTT"] == 0 else 0.0
        self.rp_rate_max = math.radians(params["ATC_RATE_R_MAX"] or 360.0)
        self.yaw_rate_max = math.radians(params["ATC_RATE_Y_MAX"] or 90.0)

    def reset(self) -> None:
        for pid in self.rate_pids:
            pid.reset()

    def update(self, roll_t: float, pitch_t: float, yaw_t: float | None, yaw_rate_t: float,
               roll: float, pitch: float, yaw: float, rates: tuple, dt: float) -> tuple:
        """Targets in radians (yaw_t None = follow yaw_rate_t); returns torques (U2, U3, U4)."""
        rl = self.rp_rate_max
        roll_dot = max(-rl, min(rl, self.angle_p[0] * (roll_t - roll)))
        pitch_dot = max(-rl, min(rl, self.angle_p[1] * (pitch_t - pitch)))
        yaw_dot = yaw_rate_t
        if yaw_t is not None:
            yaw_dot += self.angle_p[2] * wrap_pi(yaw_t - yaw)
        yl = self.yaw_rate_max
        yaw_dot = max(-yl, min(yl, yaw_dot))
        # Euler-angle rates to body rates (full kinematics, not the small-angle shortcut).
        sr, cr = math.sin(roll), math.cos(roll)
        sp, cp = math.sin(pitch), math.cos(pitch)
        p_t = roll_dot - sp * yaw_dot
        q_t = cr * pitch_dot + sr * cp * yaw_dot
        r_t = -sr * pitch_dot + cr * cp * yaw_dot
        return self.rate_update((p_t, q_t, r_t), rates, dt)

    def rate_update(self, targets: tuple, rates: tuple, dt: float) -> tuple:
        """Body-rate targets (p, q, r) [rad/s] -> torques (U2, U3, U4): the rate loop alone."""
        p_t, q_t, r_t = targets
        p, q, r = rates
        out_r = self.rate_pids[0].update(p_t, p, dt)
        out_p = self.rate_pids[1].update(q_t, q, dt)
        out_y = self.rate_pids[2].update(r_t, r, dt)
        return (out_r * self.roll_torque_max, out_p * self.pitch_torque_max,
                out_y * self.yaw_torque_max)

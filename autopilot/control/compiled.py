"""The compiled cascade: the loop of cascade.Cascade run in C, many physics steps per call.

Python enters once per chunk (normally the four physics steps between two flight-mode updates)
instead of several times per physics step. The physics and controller state live in a C struct
(_cascade.c over cascade.h and sim/physics.h); after every run the sim's PhysicsState is replaced
by a snapshot of it, so everything outside the cascade reads the same plain state as before.
Gains and constants are read from the Python controllers, so parameters have one source; the
sim's wind and motor health are handed over again whenever the sim says they changed.
If the extension was not built, vehicles fly the Python reference (after one warning line).
"""
from __future__ import annotations

import sys

from sim.physics import PhysicsState, fast_step_constants
from sim.rigid_body import BodyState

from .cascade import Cascade

_why_missing = ""
try:
    from . import _cascade
except ImportError as exc:  # a failed build: fly the reference, slower but the same trajectory
    _cascade = None
    _why_missing = str(exc)


def available() -> bool:
    return _cascade is not None


def make_cascade(sim, params, rates, compiled: bool = True) -> Cascade:
    global _why_missing
    if compiled and _cascade is not None:
        return CompiledCascade(sim, params, rates)
    if compiled and _why_missing:
        print(f"firefly: compiled cascade not built ({_why_missing}); flying the Python reference",
              file=sys.stderr)
        _why_missing = ""
    return Cascade(sim, params, rates)


class CompiledCascade(Cascade):
    def _start(self) -> None:
        sim = self.sim
        a, p, al = self.attitude_ctl, self.position_ctl, self.allocator
        constants = (*fast_step_constants(sim.airframe, sim.dt, sim.wind_ned),
                     a.roll_torque_max, a.pitch_torque_max, a.yaw_torque_max, p.mass, p.weight,
                     p.thrust_max, al.l, al.c, al.b, al.f_max, al.f_min, self.omega_idle,
                     self.dt_pos, self.dt_att)
        self.loop = _cascade.Loop(constants, self.ratio_pos, self.ratio_att, BodyState, PhysicsState)
        self.loop.configure(self._gains())
        self.loop.load(sim.state)
        self._loaded = sim.state
        self._conditions = None  # the sim's conditions_version last handed to the loop
        self.loop.reset()  # holds the heading the vehicle starts with, as the reference does

    def _gains(self) -> tuple:
        """Every parameter-derived number of the Python controllers, in _cascade.c's order."""
        a, p = self.attitude_ctl, self.position_ctl
        pids = (*a.rate_pids, p.vel_pid_n, p.vel_pid_e, p.vel_pid_d)
        return (*a.angle_p, a.rp_rate_max, a.yaw_rate_max, p.pos_xy_p, p.pos_z_p, p.accel_xy_max,
                p.lean_max, p.speed_up, p.speed_dn, p.accel_z_max,
                *(x for pid in pids for x in (pid.kp, pid.ki, pid.kd, pid.imax, pid.out_limit, pid.d_filter_hz)))

    def _sync(self) -> None:
        """If something outside the cascade replaced the sim's state, step on from that one."""
        if self.sim.state is not self._loaded:
            self.loop.load(self.sim.state)
            self._loaded = self.sim.state

    def configure(self, params) -> None:
        super().configure(params)
        self.loop.configure(self._gains())

    def command(self, sp, armed: bool, landed: bool, speed_xy: float) -> None:
        self.loop.command(sp, armed, landed, speed_xy)

    def reset_position(self) -> None:
        self._sync()
        self.loop.reset_position()

    def reset(self) -> None:
        self._sync()
        self.loop.reset()

    def run(self, n: int) -> None:
        sim = self.sim
        self._sync()
        if sim.conditions_version != self._conditions:
            self.loop.set_conditions(sim.wind_ned, sim.motor_speed_scale)
            self._conditions = sim.conditions_version
        self.loop.run(sim.steps, n)
        self._loaded = self.loop.state()
        sim.take(self._loaded, n)

    @property
    def lean_t(self) -> tuple:
        return self.loop.lean_t

    @property
    def thrust_t(self) -> float:
        return self.loop.thrust_t

    @property
    def yaw_t(self) -> float:
        return self.loop.yaw_t

    @property
    def omega_cmd(self) -> tuple:
        return self.loop.omega_cmd

"""The compiled cascade: the loop of cascade.Cascade run in C, many physics steps per call.

Python enters once per chunk (normally the four physics steps between two flight-mode updates)
instead of several times per physics step. The physics and controller state live in a C struct
(_cascade.c over cascade.h and sim/physics.h); after every run the sim's PhysicsState is replaced
by a snapshot of it, so everything outside the cascade reads the same plain state as before.
Gains and constants are read from the Python controllers and handed over by name (by_name.h),
so parameters have one source; the sim's wind and motor health are handed over again whenever
the sim says they changed.
If the extension was not built, vehicles fly the Python reference (after one warning line) —
except in CI (CI=true), where setup.py refuses to install without it and the tests stop at once.
"""
from __future__ import annotations

import os
import sys
from typing import TYPE_CHECKING, Protocol

from firefly.sim.physics import PhysicsState, fast_step_constants
from firefly.sim.rigid_body import BodyState

from .cascade import Cascade, CascadeSetup

if TYPE_CHECKING:
    from ._cascade import Loop


class Extension(Protocol):
    """What is used of the extension module (its stub: _cascade.pyi)."""

    @property
    def Loop(self) -> type[Loop]: ...


def _import_extension() -> tuple[Extension | None, str]:
    """The extension, or None and why it could not be imported."""
    try:
        from . import _cascade
    except ImportError as exc:  # a failed build: fly the reference, slower but the same trajectory
        return None, str(exc)
    return _cascade, ""


_cascade, _why_missing = _import_extension()
_warned = False


def available() -> bool:
    return _cascade is not None


def why_missing() -> str:
    """Why the extension could not be imported ("" when it was)."""
    return _why_missing


def required() -> bool:
    """Whether the extension must be there: in CI, where a failed build would otherwise only turn
    the compiled twin's checks into skips (setup.py reads the same variable)."""
    return os.environ.get("CI", "").lower() == "true"


def make_cascade(sim, params, rates, compiled: bool = True) -> Cascade | CompiledCascade:
    global _warned
    if compiled and _cascade is not None:
        return CompiledCascade(sim, params, rates)
    if compiled and not _warned:
        print(f"firefly: compiled cascade not built ({_why_missing}); flying the Python reference",
              file=sys.stderr)
        _warned = True
    return Cascade(sim, params, rates)


PID_GAINS = ("kp", "ki", "kd", "imax", "out_limit", "d_filter_hz", "d_on_error")


def numbers(obj, names: tuple) -> dict:
    """{name: obj.name}: the attribute names of the Python controllers are the keys _cascade.c
    reads (by_name.h), as they are the field names of its structs."""
    return {name: getattr(obj, name) for name in names}


class CompiledCascade(CascadeSetup):
    def _start(self) -> None:
        sim = self.sim
        if _cascade is None:  # make_cascade makes one only when the extension is there
            raise ImportError(f"compiled cascade not built ({_why_missing})")
        self.loop = _cascade.Loop(self.constants(), self.ratio_pos, self.ratio_att, BodyState, PhysicsState)
        self.loop.configure(self.gains())
        self.loop.set_conditions(sim.wind_ned, sim.motor_speed_scale)
        self._conditions = sim.conditions_version  # the sim's conditions last handed to the loop
        self.loop.load(sim.state)
        self._loaded = sim.state
        self.loop.reset()  # holds the heading the vehicle starts with, as the reference does
        # The loop's own method, not one that calls it: the vehicle commands it at every tick.
        self.command = self.loop.command

    def constants(self) -> dict:
        """What the loop takes once, by name: the physics step's constants and the airframe's
        limits as the controllers hold them."""
        return {"physics": fast_step_constants(self.sim.airframe, self.sim.dt),
                "attitude": numbers(self.attitude_ctl, ("roll_torque_max", "pitch_torque_max", "yaw_torque_max")),
                "position": numbers(self.position_ctl, ("mass", "weight", "thrust_max")),
                "allocator": numbers(self.allocator, ("l", "c", "b", "f_max", "f_min")),
                "cascade": numbers(self, ("omega_idle", "dt_pos", "dt_att"))}

    def gains(self) -> dict:
        """Every parameter-derived number of the Python controllers, by name."""
        a, p = self.attitude_ctl, self.position_ctl
        roll, pitch, yaw = a.angle_p
        rate_roll, rate_pitch, rate_yaw = a.rate_pids
        return {"attitude": {"angle_p_roll": roll, "angle_p_pitch": pitch, "angle_p_yaw": yaw,
                             **numbers(a, ("rp_rate_max", "yaw_rate_max"))},
                "position": numbers(p, ("pos_xy_p", "pos_z_p", "accel_xy_max", "lean_max", "speed_up",
                                        "speed_dn", "accel_z_max", "vel_fltd_hz")),
                "rate_roll": numbers(rate_roll, PID_GAINS), "rate_pitch": numbers(rate_pitch, PID_GAINS),
                "rate_yaw": numbers(rate_yaw, PID_GAINS), "vel_n": numbers(p.vel_pid_n, PID_GAINS),
                "vel_e": numbers(p.vel_pid_e, PID_GAINS), "vel_d": numbers(p.vel_pid_d, PID_GAINS)}

    def _sync(self) -> None:
        """If something outside the cascade replaced the sim's state, step on from that one."""
        if self.sim.state is not self._loaded:
            self.loop.load(self.sim.state)
            self._loaded = self.sim.state

    def configure(self, params) -> None:
        super().configure(params)
        self.loop.configure(self.gains())

    def reset_position(self) -> None:
        self._sync()
        self.loop.reset_position()

    def reset(self) -> None:
        self._sync()
        self.loop.reset()

    def run(self, n: int) -> None:
        self._ready()
        self.loop.run(self.sim.steps, n)
        self._took(n)

    def run_fixed(self, n: int, omega: tuple[float, float, float, float]) -> None:
        """n physics steps with the motors held at `omega`, no control (a motor test)."""
        self._ready()
        self.loop.run_physics(n, omega)
        self._took(n)

    def _ready(self) -> None:
        """The loop stepping from the sim's state, in its wind and motor conditions."""
        sim = self.sim
        self._sync()
        if sim.conditions_version != self._conditions:
            self.loop.set_conditions(sim.wind_ned, sim.motor_speed_scale)
            self._conditions = sim.conditions_version

    def _took(self, n: int) -> None:
        self._loaded = self.loop.state()
        self.sim.take(self._loaded, n)

    @property
    def lean_t(self) -> tuple[float, float]:
        return self.loop.lean_t

    @property
    def thrust_t(self) -> float:
        return self.loop.thrust_t

    @property
    def yaw_t(self) -> float:
        return self.loop.yaw_t

    @property
    def omega_cmd(self) -> tuple[float, float, float, float]:
        return self.loop.omega_cmd

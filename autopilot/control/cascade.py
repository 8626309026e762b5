"""The control cascade between two flight-mode updates, as the paper draws it: position and
altitude -> lean angles and U1 -> body rates -> U2..U4 -> motor speeds -> the sim's physics step.

This is the readable reference. `compiled.CompiledCascade` runs the same arithmetic in the same
order in C (cascade.h, sim/physics.h) and a test checks the two fly bit-identical trajectories.

The vehicle's flight mode fills a Setpoint at its own (slower) rate and hands it over with
`command()` before every run; `run(n)` then advances the sim n physics steps, running the
position loop every `ratio_pos` steps and the attitude and rate loops every `ratio_att` steps.
"""
from __future__ import annotations

from typing import Protocol

from firefly.sim.rigid_body import euler_from_quaternion

from .allocation import Allocator
from .attitude import AttitudeController, wrap_pi
from .position import PositionController


class Command(Protocol):
    """What the cascade reads of the flight mode's setpoint (modes/base.py Setpoint)."""

    @property
    def lean(self) -> tuple[float, float] | None: ...
    @property
    def pos_ne(self) -> tuple[float, float] | None: ...
    @property
    def vel_ne(self) -> tuple[float, float]: ...
    @property
    def accel_ne(self) -> tuple[float, float] | None: ...
    @property
    def throttle(self) -> float | None: ...
    @property
    def pos_d(self) -> float | None: ...
    @property
    def vel_d(self) -> float: ...
    @property
    def speed_dn(self) -> float | None: ...
    @property
    def yaw(self) -> float | None: ...
    @property
    def yaw_rate(self) -> float: ...
    @property
    def rates(self) -> tuple[float, float, float] | None: ...

    def wants_climb(self, d_m: float) -> bool: ...


class CascadeSetup:
    """What the two cascades share: the controllers, configured from the parameters, and the
    loop rates. The Python reference (Cascade, below) and its compiled twin
    (compiled.CompiledCascade) each run the loop, and hold its targets, their own way."""

    def __init__(self, sim, params, rates):
        airframe = sim.airframe
        self.sim = sim
        self.position_ctl = PositionController(airframe, params)
        self.attitude_ctl = AttitudeController(airframe, params)
        self.allocator = Allocator(airframe)
        self.omega_idle = airframe.omega_idle_rad_s
        self.ratio_pos = rates.ratio(rates.position_hz)
        self.ratio_att = rates.ratio(rates.attitude_hz)
        self.dt_pos = 1.0 / rates.position_hz
        self.dt_att = 1.0 / rates.attitude_hz
        self._start()

    def _start(self) -> None:
        raise NotImplementedError

    def configure(self, params) -> None:
        self.position_ctl.configure(params)
        self.attitude_ctl.configure(params)


class Cascade(CascadeSetup):
    """The readable reference: the loop in Python."""
    lean_t: tuple[float, float]
    thrust_t: float
    yaw_t: float
    omega_cmd: tuple[float, float, float, float]

    def __init__(self, sim, params, rates):
        self._sp: Command | None = None  # none until the vehicle's first command()
        self._armed = self._landed = False
        self._speed_xy = 0.0
        super().__init__(sim, params, rates)

    def _start(self) -> None:
        """Targets and commands before the first loop: nothing asked, heading held."""
        self.lean_t = (0.0, 0.0)
        self.thrust_t = 0.0
        body = self.sim.state.body
        self.yaw_t = euler_from_quaternion(body.qw, body.qx, body.qy, body.qz)[2]
        self.omega_cmd = (0.0, 0.0, 0.0, 0.0)

    def command(self, sp: Command, armed: bool, landed: bool, speed_xy: float) -> None:
        """What the flight mode asks for until the next command (speed_xy: horizontal limit)."""
        self._sp, self._armed, self._landed, self._speed_xy = sp, armed, landed, speed_xy

    # ----- resets from the vehicle (arming, mode changes) -------------------------------------
    def reset_position(self) -> None:
        """Bumpless hand-over of the position loop: velocity targets start from the velocity."""
        b = self.sim.state.body
        self.position_ctl.reset((b.vn_m_s, b.ve_m_s), b.vd_m_s)

    def reset(self) -> None:
        """Forget all controller history and hold the current heading (on arming)."""
        self.attitude_ctl.reset()
        self.reset_position()
        b = self.sim.state.body
        self.yaw_t = euler_from_quaternion(b.qw, b.qx, b.qy, b.qz)[2]

    # ----- the loop ----------------------------------------------------------------------------
    def run(self, n: int) -> None:
        sim = self.sim
        for _ in range(n):
            steps = sim.steps
            pos_due, att_due = steps % self.ratio_pos == 0, steps % self.ratio_att == 0
            if pos_due or att_due:
                b = sim.state.body
                attitude = euler_from_quaternion(b.qw, b.qx, b.qy, b.qz)
                if pos_due:
                    self._position_step(b, attitude)
                if att_due:
                    self._attitude_step(b, attitude)
            sim.step(self.omega_cmd)

    def run_fixed(self, n: int, omega: tuple[float, float, float, float]) -> None:
        """n physics steps with the motors held at `omega`, no control (a motor test)."""
        sim = self.sim
        self.omega_cmd = omega
        for _ in range(n):
            sim.step(omega)

    def ground_idle(self, d_m: float) -> bool:
        """Whether the motors should just idle (disarmed, or armed on the ground not taking off)."""
        sp = self._sp
        if not self._armed or sp is None:  # nothing commanded yet: nothing to fly
            return True
        if self._landed:
            return not sp.wants_climb(d_m)
        return False

    def _position_step(self, b, attitude: tuple) -> None:
        roll, pitch, yaw = attitude
        if self.ground_idle(b.d_m):
            self.attitude_ctl.reset()
            self.position_ctl.reset((b.vn_m_s, b.ve_m_s), b.vd_m_s)
            self.lean_t = (0.0, 0.0)
            self.thrust_t = 0.0
            self.yaw_t = yaw
            return
        sp, pc, dt = self._sp, self.position_ctl, self.dt_pos
        if sp is None:  # never: ground_idle() is True until the first command
            return
        if sp.lean is not None:
            self.lean_t = sp.lean
        else:
            self.lean_t = pc.horizontal(sp.pos_ne, sp.vel_ne, self._speed_xy, (b.n_m, b.e_m),
                                        (b.vn_m_s, b.ve_m_s), yaw, dt, sp.accel_ne)
        if sp.throttle is not None:
            self.thrust_t = pc.thrust_from_stick(sp.throttle)
        else:
            self.thrust_t = pc.vertical(sp.pos_d, sp.vel_d, b.d_m, b.vd_m_s, roll, pitch, dt,
                                        speed_dn=sp.speed_dn)
        if sp.rates is not None:  # body rates fly it: an angle mode taking over holds this heading
            self.yaw_t = yaw
        elif sp.yaw is not None:
            self.yaw_t = sp.yaw
        else:
            self.yaw_t = wrap_pi(self.yaw_t + sp.yaw_rate * dt)

    def _attitude_step(self, b, attitude: tuple) -> None:
        if self.ground_idle(b.d_m):
            idle = self.omega_idle if self._armed else 0.0
            self.omega_cmd = (idle, idle, idle, idle)
            return
        roll, pitch, yaw = attitude
        body_rates = (b.p_rad_s, b.q_rad_s, b.r_rad_s)
        sp = self._sp
        if sp is not None and sp.rates is not None:
            u2, u3, u4 = self.attitude_ctl.rate_update(sp.rates, body_rates, self.dt_att)
        else:
            u2, u3, u4 = self.attitude_ctl.update(self.lean_t[0], self.lean_t[1], self.yaw_t, 0.0,
                                                  roll, pitch, yaw, body_rates, self.dt_att)
        self.omega_cmd = self.allocator.omega_commands(self.thrust_t, u2, u3, u4)

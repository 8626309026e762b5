"""The vehicle: sensors -> estimate -> flight mode -> cascaded PID -> allocation -> sim step.

It knows nothing of MAVLink or sockets. Ground stations reach it through the command methods,
which return a Result (MAV_RESULT numbers) and queue what ArduCopter would announce in `events`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

from sim.airframe import GRAVITY_M_S2
from sim.rigid_body import euler_from_quaternion
from sim.vehicle import BATTERY_EVERY, SimConfig, SimVehicle

from .control.attitude import wrap_pi
from .control.compiled import make_cascade
from .safety.failsafe import Failsafes
from .faults.world import Faults, world_values
from sim.geo import GeoPoint, global_from_ned, ned_from_global
from .mission import MissionStore
from .modes import MODE_BY_NUMBER, Auto, Guided, Setpoint, Stabilize
from .params import ParamStore
from .pilot import CENTRED, CENTRED_MANUAL, PilotInput
from .rates import LoopRates
from .results import Result, Severity
from .safety.thrust_loss import ThrustLossCheck

FORCE_ARM_MAGIC = 2989
FORCE_DISARM_MAGIC = 21196
LAND_DETECT_S = 1.0
GPS_RATE_HZ = 10
TEMPERATURE_RATE_HZ = 10


@dataclass
class VehicleConfig:
    home: GeoPoint = field(default_factory=lambda: GeoPoint(43.5615, 1.4838, 150.0))
    home_yaw_deg: float = 0.0
    offset_ne_m: tuple = (0.0, 0.0)  # start position relative to the shared origin
    sim: SimConfig = field(default_factory=SimConfig)
    rates: LoopRates = field(default_factory=LoopRates)
    system_id: int = 1
    epoch_unix_us: int = 1_790_000_000_000_000  # UNIX time at sim time 0 (SYSTEM_TIME only)
    compiled: bool = True  # fly the compiled cascade when it is built (False: the Python reference)
    faults: dict = field(default_factory=dict)  # SIM_* parameter values to start with (a scenario's [faults])


class Vehicle:
    def __init__(self, config: VehicleConfig, params: ParamStore | None = None,
                 mission: MissionStore | None = None):
        config.rates.check()
        if config.rates.physics_hz != config.sim.physics_rate_hz:
            raise ValueError("sim physics rate and loop-rate table disagree")
        self.config = config
        self.system_id = config.system_id
        self.params = params or ParamStore()
        self.mission = mission or MissionStore()
        self._mission_index = 0
        self.mission_state = "NOT_STARTED"
        self.auto_armed = False  # ArduCopter's flag: AUTO may start its mission from the ground
        self.reached: list[int] = []  # mission seqs reached, for MISSION_ITEM_REACHED
        self.failsafes = Failsafes()
        self.script = None  # a scenario's scripted commands (autopilot.cli.script.Script), if any
        n0, e0 = config.offset_ne_m
        self.origin = config.home
        self.sim = SimVehicle(config.sim, math.radians(config.home_yaw_deg), n0, e0)
        for name, value in {**world_values(config.sim), **config.faults}.items():
            self.params.set(name, value)
        self.faults = Faults(self.sim, self.params, self.origin)
        self.thrust_loss = ThrustLossCheck()
        self._alt_error_m = 0.0  # how far the barometer, and so the height estimate, reads high
        airframe = config.sim.airframe
        self.weight_n = airframe.weight_n
        self.thrust_max_n = 4.0 * airframe.max_rotor_thrust_n
        self.omega_idle = airframe.omega_idle_rad_s
        self.cascade = make_cascade(self.sim, self.params, config.rates, config.compiled)
        self.params.on_change(self._param_changed)
        self.modes = {number: cls() for number, cls in MODE_BY_NUMBER.items()}
        self.mode = self.modes[Stabilize.number]
        self.setpoint = Setpoint()
        self.armed = False
        self.landed = True
        self.home_ned: tuple | None = None
        self.pilot_input = PilotInput()
        self.events: list[tuple[int, str]] = []
        self.nav_speed_m_s = self.params["WPNAV_SPEED"] / 100.0
        self._loiter_speed_max = self.params["LOIT_SPEED"] / 100.0 * 2.0
        self._ratio_mode = config.rates.ratio(config.rates.mode_hz)
        self._ratio_gps = max(1, config.rates.physics_hz // GPS_RATE_HZ)
        self._ratio_temp = max(1, config.rates.physics_hz // TEMPERATURE_RATE_HZ)
        # The cascade runs in chunks that end wherever Python has work: a mode tick, a sensor
        # sample or a battery update (the sim integrates the battery every BATTERY_EVERY steps).
        self._chunk = math.gcd(self._ratio_mode, self._ratio_gps, self._ratio_temp, BATTERY_EVERY)
        self.temperature = (0.0, float("nan"))  # (sim time of the sample, degrees C)
        self._dt_mode = 1.0 / config.rates.mode_hz
        self._landed_since: float | None = None
        self._disarm_timer_start: float | None = None
        self.gps = self.sim.gps.read(self.sim.state.body)
        self.baro_alt_m = 0.0  # the barometer's last sample (altitude above the origin), at the GPS rate
        self.armed_time_s = 0.0
        if self.has_position():  # the simulated GPS has a fix at once: armable from the first heartbeat
            self._set_home_here()

    # ----- state seen by modes and telemetry ---------------------------------------------------
    @property
    def time_s(self) -> float:
        return self.sim.time_s

    @property
    def body(self):
        """The state estimate: the sim's own state (an ideal EKF), except that its height is the
        barometer's, as ArduCopter's EKF takes it, so a drifting barometer moves it."""
        b = self.sim.state.body
        return b._replace(d_m=b.d_m - self._alt_error_m) if self._alt_error_m else b

    @property
    def attitude(self) -> tuple:
        b = self.sim.state.body
        return euler_from_quaternion(b.qw, b.qx, b.qy, b.qz)

    @property
    def pilot(self) -> PilotInput:
        if self.pilot_input.present(self.time_s):
            return self.pilot_input
        return CENTRED_MANUAL if self.mode.manual_throttle else CENTRED

    @property
    def home(self) -> GeoPoint | None:
        if self.home_ned is None:
            return None
        return global_from_ned(self.origin, *self.home_ned)

    @property
    def thrust_demand_n(self) -> float:
        return self.cascade.thrust_t

    def unix_time_us(self) -> int:
        return self.config.epoch_unix_us + int(self.time_s * 1e6)

    def ned_to_global(self, n: float, e: float, d: float) -> GeoPoint:
        return global_from_ned(self.origin, n, e, d)

    def drain_reached(self) -> list:
        reached, self.reached = self.reached, []
        return reached

    def drain_events(self) -> list:
        events, self.events = self.events, []
        return events

    def position_global(self) -> GeoPoint:
        b = self.body
        return global_from_ned(self.origin, b.n_m, b.e_m, b.d_m)

    def has_position(self) -> bool:
        return self.gps.fix_type >= 3

    def landed_state(self) -> str:
        """ON_GROUND, TAKEOFF, IN_AIR or LANDING (MAV_LANDED_STATE names)."""
        if self.landed:
            return "ON_GROUND"
        return self.mode.landed_state_hint(self) or "IN_AIR"

    # ----- mission progress ----------------------------------------------------------------------
    def mission_index(self) -> int:
        """Index into the stored items of the current mission item (seq = index + 1)."""
        return min(self._mission_index, max(len(self.mission.items(0)) - 1, 0))

    def set_mission_index(self, index: int) -> None:
        self._mission_index = index

    def mission_current_seq(self) -> int:
        return self.mission_index() + 1 if self.mission.items(0) else 0

    def set_mission_current(self, seq: int) -> bool:
        """MISSION_SET_CURRENT: in AUTO the mission continues from that item at once."""
        if not 1 <= seq <= len(self.mission.items(0)):
            return False
        self._mission_index = seq - 1
        if isinstance(self.mode, Auto) and self.mission_state == "ACTIVE":
            self.mode.restart_at(self, seq - 1)
        return True

    def mission_item_reached(self, index: int) -> None:
        self.reached.append(index + 1)

    def mission_start(self) -> Result:
        """MISSION_START: switch to AUTO and let the mission begin even from the ground."""
        result = self.set_mode(Auto.number)
        if result == Result.ACCEPTED:
            self.auto_armed = self.armed
            if self.mission_state == "COMPLETE":
                self._mission_index = 0
            if self.mission_state != "ACTIVE":
                self.mission_state = "NOT_STARTED"
        return result

    def notify(self, text: str, severity: int = Severity.INFO) -> None:
        self.events.append((int(severity), text))

    def _param_changed(self, name: str, value: float) -> None:
        self.cascade.configure(self.params)
        self._loiter_speed_max = self.params["LOIT_SPEED"] / 100.0 * 2.0
        if name == "WPNAV_SPEED":
            self.nav_speed_m_s = value / 100.0

    # ----- arming ------------------------------------------------------------------------------
    def prearm_failure(self) -> str | None:
        """The first failing pre-arm check, worded as ArduCopter's 'PreArm: ...', or None."""
        if self.params["ARMING_CHECK"] == 0:
            return None
        if not self.has_position():
            return "Need 3D Fix"
        if self.failsafes.ekf.gps_glitching:
            return "GPS glitching"
        if self.home_ned is None:
            return "Waiting for home"
        roll, pitch, _ = self.attitude
        if max(abs(roll), abs(pitch)) > math.radians(self.params["ANGLE_MAX"] / 100.0):
            return "Leaning"
        low = self.params["BATT_LOW_VOLT"]
        if low > 0 and self.sim.battery.voltage_v < low:
            return "Battery below minimum arming voltage"
        return None

    def is_armable(self) -> bool:
        return self.prearm_failure() is None

    def arm(self, force: bool = False) -> Result:
        if self.armed:
            return Result.ACCEPTED
        if not self.mode.allows_arming:
            self.notify("Arm: Mode not armable", Severity.CRITICAL)
            return Result.FAILED
        if not force:
            reason = self.prearm_failure()
            if reason:
                self.notify(f"PreArm: {reason}", Severity.CRITICAL)
                return Result.FAILED
            if self.mode.manual_throttle and self.pilot.throttle > 0.1:
                self.notify("Arm: Throttle too high", Severity.CRITICAL)
                return Result.FAILED
        if self.home_ned is None:
            self._set_home_here()
        self.armed = True
        self.armed_time_s = self.time_s
        self.landed = True
        self._disarm_timer_start = self.time_s
        self.cascade.reset()
        self.notify("Arming motors")
        return Result.ACCEPTED

    def disarm(self, reason: str = "", force: bool = False) -> Result:
        if not self.armed:
            return Result.ACCEPTED
        if not force and not self.landed:
            self.notify("Disarm: not landed", Severity.CRITICAL)
            return Result.FAILED
        self.armed = False
        self.auto_armed = False
        self.notify("Disarming motors")
        return Result.ACCEPTED

    def _set_home_here(self) -> None:
        b = self.body
        self.home_ned = (b.n_m, b.e_m, b.d_m)
        self.notify("Home set")

    # ----- modes and navigation commands -------------------------------------------------------
    def set_mode(self, number: int) -> Result:
        cls_mode = self.modes.get(number)
        if cls_mode is None:
            return Result.FAILED
        if cls_mode is self.mode:
            return Result.ACCEPTED
        reason = None
        if cls_mode.requires_position and not self.has_position():
            reason = "requires position"
        if reason is None:
            reason = cls_mode.enter(self)
        if reason is not None:
            self.notify(f"Mode change to {cls_mode.name} failed: {reason}", Severity.WARNING)
            return Result.FAILED
        self.mode.exit(self)
        self.mode = cls_mode
        self.cascade.reset_position()
        return Result.ACCEPTED

    def takeoff(self, alt_m: float) -> Result:
        """User takeoff to alt_m above home: only armed, landed, in a mode with user takeoff."""
        if not (self.armed and self.landed and self.mode.has_user_takeoff):
            return Result.FAILED
        if not math.isfinite(alt_m):
            return Result.FAILED
        alt_m = max(alt_m, self.params["PILOT_TKOFF_ALT"] / 100.0)
        home_d = self.home_ned[2]
        if alt_m <= home_d - self.body.d_m:
            return Result.FAILED
        if isinstance(self.mode, Guided):
            self.mode.set_takeoff(self, alt_m)
        else:
            return Result.FAILED
        self.auto_armed = True
        self._disarm_timer_start = None
        return Result.ACCEPTED

    def guided_goto(self, n: float, e: float, d: float | None, yaw: float | None = None,
                    vel_ff: tuple = (0.0, 0.0, 0.0)) -> Result:
        if not isinstance(self.mode, Guided):
            return Result.DENIED
        self.mode.set_position(self, n, e, d, yaw, vel_ff)
        return Result.ACCEPTED

    def set_yaw(self, angle_deg: float, relative: bool, direction: int) -> Result:
        """CONDITION_YAW in GUIDED: absolute heading, or relative (direction -1 ccw, 1 cw)."""
        if not isinstance(self.mode, Guided) or not -360.0 <= angle_deg <= 360.0:
            return Result.FAILED
        target = math.radians(angle_deg)
        if relative:
            target = self.attitude[2] + (-target if direction < 0 else target)
        self.mode.target_yaw = wrap_pi(target)
        return Result.ACCEPTED

    def set_home(self, ned: tuple | None) -> Result:
        """DO_SET_HOME: here (None) or at a local NED point within 50 km."""
        if ned is None:
            self._set_home_here()
            return Result.ACCEPTED
        if math.hypot(ned[0], ned[1]) > 50_000:
            return Result.DENIED
        self.home_ned = tuple(ned)
        return Result.ACCEPTED

    def guided_velocity(self, vn: float, ve: float, vd: float, yaw: float | None = None) -> Result:
        if not isinstance(self.mode, Guided):
            return Result.DENIED
        self.mode.set_velocity(self, vn, ve, vd, yaw)
        return Result.ACCEPTED

    def set_speed(self, speed_m_s: float) -> Result:
        if not (math.isfinite(speed_m_s) and speed_m_s > 0):
            return Result.FAILED
        self.nav_speed_m_s = min(speed_m_s, self.params.get("WPNAV_SPEED") / 100.0 * 5.0)
        return Result.ACCEPTED

    def ned_of(self, lat: float, lon: float, alt_amsl: float) -> tuple:
        return ned_from_global(self.origin, lat, lon, alt_amsl)

    # ----- the loop ----------------------------------------------------------------------------
    def step(self) -> None:
        """One physics tick: the work due at this tick (sensors, flight mode), then the cascade."""
        self._advance(1)

    def run_until(self, t_s: float) -> None:
        """Step until sim time reaches t_s (to within 1 ns), in as few cascade runs as it takes."""
        dt, steps = self.sim.dt, self.sim.steps
        target = max(steps, math.floor((t_s - 1e-9) / dt) - 1)
        while target * dt < t_s - 1e-9:  # the same test as time_s < t_s - 1e-9, step by step
            target += 1
        while self.sim.steps < target:
            self._advance(target - self.sim.steps)

    def _advance(self, most: int) -> None:
        """The Python work due at this physics step, then up to `most` steps of the cascade,
        stopping before the next step that has Python work."""
        sim = self.sim
        steps = sim.steps
        if steps % self._ratio_gps == 0:
            self.gps = sim.gps.read(sim.state.body)
            # Sampled here at a fixed sim rate, never by telemetry: its noise stream stays the same
            # whatever a client asks for.
            self.baro_alt_m = sim.baro.altitude_m(sim.state.body, sim.time_s)
            if self.home_ned is None and self.gps.fix_type >= 3:
                self._set_home_here()
        if steps % self._ratio_temp == 0:
            self.temperature = (sim.time_s, sim.read_temperature((self.home_ned or (0, 0, 0))[2]))
        if steps % self._ratio_mode == 0:
            self._mode_tick()
        sp = self.setpoint
        if self._alt_error_m and sp.pos_d is not None:
            sp = in_true_height(sp, self._alt_error_m)
        self.cascade.command(sp, self.armed, self.landed, min(sp.speed_xy, self._loiter_speed_max))
        self.cascade.run(min(most, self._chunk - steps % self._chunk))

    def _mode_tick(self) -> None:
        dt = self._dt_mode
        baro = self.sim.baro
        self._alt_error_m = baro.error_m(self.time_s) if baro.drift_m_s else 0.0
        if self.script is not None:
            self.script.run_due(self)
        self.mode.update(self, self.setpoint, dt)
        self._update_land_detector(dt)
        self._update_auto_disarm()
        if self.sim.steps % (self._ratio_mode * 10) == 0:  # failsafe checks at 10 Hz
            self.failsafes.check(self)
            self.thrust_loss.check(self, 10 * dt)

    def _update_land_detector(self, dt: float) -> None:
        b = self.body
        if self.landed:
            if self.armed and (b.d_m < (self.home_ned or (0, 0, 0))[2] - 0.2 or b.vd_m_s < -0.3):
                self.landed = False
                self._landed_since = None
            return
        if not self.armed:
            self.landed = True
            return
        low_thrust = self.cascade.thrust_t < 0.85 * self.weight_n
        still = abs(b.vd_m_s) < 0.3 and math.hypot(b.vn_m_s, b.ve_m_s) < 0.5
        if low_thrust and still:
            if self._landed_since is None:
                self._landed_since = self.time_s
            elif self.time_s - self._landed_since >= LAND_DETECT_S:
                self.landed = True
                self._disarm_timer_start = self.time_s
        else:
            self._landed_since = None

    def _update_auto_disarm(self) -> None:
        """ArduCopter disarms after DISARM_DELAY seconds landed with nothing asking to climb."""
        delay = self.params["DISARM_DELAY"]
        if not self.armed or delay <= 0:
            return
        if not self.landed or self.setpoint.wants_climb(self.body.d_m):
            self._disarm_timer_start = None
            return
        if self._disarm_timer_start is None:
            self._disarm_timer_start = self.time_s
        elif self.time_s - self._disarm_timer_start >= delay:
            self.disarm("auto")


def in_true_height(sp: Setpoint, alt_error_m: float) -> Setpoint:
    """The setpoint as the cascade, which flies the true state, must see it when the height
    estimate reads alt_error_m high: holding an estimated height means being that much lower."""
    true_sp = Setpoint()
    for name in Setpoint.__slots__:
        setattr(true_sp, name, getattr(sp, name))
    true_sp.pos_d = sp.pos_d + alt_error_m
    return true_sp

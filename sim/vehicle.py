"""One simulated vehicle: physics state, battery, wind and sensors, advanced in fixed steps of
sim time. Injected faults reach it as plain settings: motor health (set_motor_thrust_scale), the
wind (self.wind), the sensors' fault attributes, the battery's resting voltage. Payloads act at the
battery steps: a recovery parachute's canopy, once deployed (deploy_canopy), drags it through the
air; a load on a string (hang_load) makes it heavier while it hangs."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

from .airframe import GRAVITY_M_S2, Airframe
from .fire import FireWorld, TemperatureSensor
from .battery import (STEP_AT, BatteryState, open_circuit_volts_per_cell, remaining_fraction,
                      soc_at_open_circuit_volts)
from .parachute import Canopy, slowed
from .slung_load import SlungLoad, carried
from .physics import PhysicsState, initial_state, make_fast_step
from .rotors import HEALTHY, shaft_power_per_thrust_1p5
from .precland import Beacon
from .optical_flow import FlowCamera, FlowSample
from .rangefinder import SonarBeam
from .rigid_body import apply_ground
from .terrain import FLAT, Terrain
from .traffic import Aircraft, Track, TrafficSim
from .sensors import Barometer, Gps, Gyro, NoiseConfig, RcReceiver
from .wind import SteadyWind, Wind


BATTERY_EVERY = 4  # physics steps per battery step; the wind changes at the same steps
# A wind that weakens near the ground is worked out again when the height has moved this much: a
# finer step changes it by millimetres a second, and each change costs the compiled loop a reload.
WIND_HEIGHT_STEP_M = 0.1


@dataclass
class SimConfig:
    airframe: Airframe = field(default_factory=Airframe)
    wind: SteadyWind = field(default_factory=SteadyWind)
    noise: NoiseConfig = field(default_factory=NoiseConfig)
    physics_rate_hz: int = 400
    seed: int = 0
    world: FireWorld = field(default_factory=FireWorld)
    traffic: tuple[Track, ...] = ()  # the scenario's own aircraft ([[traffic]])
    canopy: Canopy = field(default_factory=Canopy)  # the recovery parachute's ([parachute])
    terrain: Terrain = FLAT  # the ground's hills ([[terrain]]); the field is flat without them


class SimVehicle:
    def __init__(self, config: SimConfig, yaw_rad: float = 0.0, n_m: float = 0.0, e_m: float = 0.0):
        self.config = config
        self.airframe = config.airframe
        self.dt = 1.0 / config.physics_rate_hz
        self._step = make_fast_step(self.airframe, self.dt)
        self.wind = Wind(config.wind, config.seed)
        self._wind_ned = self.wind.velocity_ned
        self._wind_height_m = -math.inf  # the height the wind was last worked out at
        self._start_ground_d = config.terrain.ground_d_m(n_m, e_m) if config.terrain.hills else 0.0
        self._speed_scale: tuple[float, ...] = HEALTHY
        self._thrust_scale: tuple[float, ...] = HEALTHY
        self._outputs_cut = False
        self.conditions_version = 0  # bumped whenever the wind or the motors' health changes
        self.state: PhysicsState = initial_state(yaw_rad, n_m, e_m)
        self.battery = BatteryState(0.0, 0.0, self.airframe.battery_cells * 4.2)
        self.gps = Gps(config.seed, config.noise)
        self.baro = Barometer(config.seed, config.noise)
        self.rc = RcReceiver()
        self.gyro = Gyro(config.seed, config.noise)
        self.sonar = SonarBeam(config.seed)
        self.flow_camera = FlowCamera(config.seed)  # SITL's optical flow (SIM_FLOW_*), off until enabled
        self.beacon: Beacon | None = None  # SITL's precision-landing beacon (SIM_PLD_*), when on
        # Switched off after it was on, SITL's beacon stops reporting but keeps its last health:
        # the autopilot hears nothing new and still calls the sensor healthy.
        self.beacon_on = False
        self.traffic = TrafficSim(config.seed, config.traffic)  # other aircraft (SIM_ADSB_*, [[traffic]])
        self.thermometer = TemperatureSensor(config.world, config.seed)
        self.time_s = 0.0
        self.steps = 0
        # An outside push (a hand's throw; ArduPilot SITL's SIM_SHOVE_*): a body-frame (FRD)
        # acceleration [m/s^2] until _shove_until_s, or None.
        self.shove_accel_frd: tuple[float, float, float] | None = None
        self._shove_until_s = 0.0
        # The parachute's canopy: sim time it was deployed (None: packed); a load on a string
        # (None: none); the acceleration [m/s^2, NED] they gave at the last battery step, which
        # the accelerometer feels (None: none), and the velocity then.
        self.canopy_deployed_at_s: float | None = None
        self.load: SlungLoad | None = None
        self.payload_accel_ned: tuple[float, float, float] | None = None
        self._payload_v: tuple[float, float, float] | None = None
        af = self.airframe
        power_per_omega_cubed = shaft_power_per_thrust_1p5(af) * af.thrust_coeff_b ** 1.5 / af.motor_efficiency
        self._battery_constants = (power_per_omega_cubed, af.battery_cells, af.battery_capacity_mah,
                                   af.battery_internal_resistance_ohm, af.avionics_current_a, self.dt * BATTERY_EVERY)

    def step(self, omega_cmd: tuple) -> None:
        self.state = self._step(self.state, omega_cmd, self._wind_ned, self._speed_scale)
        self._count(1)

    def take(self, state: PhysicsState, n: int) -> None:
        """The state after n physics steps taken elsewhere (the compiled cascade steps the same
        physics in C). n must not carry the step count past a multiple of BATTERY_EVERY."""
        if n < 1 or (self.steps % BATTERY_EVERY) + n > BATTERY_EVERY:
            # The battery and wind steps between would be skipped: the caller's chunking is wrong.
            raise ValueError(f"take({n}) at step {self.steps} skips a battery step (every {BATTERY_EVERY})")
        self.state = state
        self._count(n)

    def _count(self, n: int) -> None:
        if self.config.terrain.hills:
            self._rest_on_hills()
        self.steps += n
        self.time_s = self.steps * self.dt
        if self.steps % BATTERY_EVERY == 0:  # the pack changes slowly: integrate it at a quarter rate
            self.battery = STEP_AT(self.battery, self.state.omega_rad_s, self._battery_constants)
            if self.wind.live:
                self._blow(self.wind)
            if self.shove_accel_frd is not None:
                self._push(self.dt * BATTERY_EVERY)
            if self.canopy_deployed_at_s is not None or self.load is not None:
                self._act_payloads(self.dt * BATTERY_EVERY)

    def _blow(self, wind: Wind) -> None:
        """The wind at this battery step, as it changes in time or with the height it weakens
        with (SIM_WIND_T), the height in steps of WIND_HEIGHT_STEP_M."""
        height = self._height_above_start()
        if not wind.changing and abs(height - self._wind_height_m) < WIND_HEIGHT_STEP_M:
            return
        self._wind_height_m = height
        blowing = wind.advance(self.dt * BATTERY_EVERY, height)
        if blowing != self._wind_ned:
            self._wind_ned = blowing
            self.conditions_version += 1

    def _height_above_start(self) -> float:
        """The body's height above the ground it started on [m]: SITL's wind profile reads the
        barometer's altitude, zeroed at boot, not the height over the ground under it (hills)."""
        return self._start_ground_d - self.state.body.d_m

    def _rest_on_hills(self) -> None:
        """Ground contact with a hill. The physics step (and its compiled twin) knows only the flat
        field at d = 0; a body that has sunk into a hill since the last step is set on its surface
        by the same contact rules, so a vehicle lands on and rests on the hill."""
        b = self.state.body
        ground_d = self.config.terrain.ground_d_m(b.n_m, b.e_m)
        if ground_d < 0.0 and b.d_m >= ground_d:
            body, on_ground = apply_ground(b, ground_d)
            self.state = self.state._replace(body=body, on_ground=on_ground)

    def shove(self, accel_frd: tuple[float, float, float], seconds: float) -> None:
        """Push the body with a body-frame acceleration [m/s^2] for `seconds` (0: stop pushing),
        as a hand throwing it would: the velocity changes at every battery step, and the
        accelerometer feels the push while it lasts."""
        self.shove_accel_frd = tuple(accel_frd) if seconds > 0 else None  # type: ignore[assignment]
        self._shove_until_s = self.time_s + seconds

    def _push(self, dt: float) -> None:
        if self.time_s >= self._shove_until_s:
            self.shove_accel_frd = None
            return
        ax, ay, az = self.shove_accel_frd  # type: ignore[misc]
        b = self.state.body
        qw, qx, qy, qz = b.qw, b.qx, b.qy, b.qz
        # body (FRD) to NED: the transpose of rigid_body.ned_to_body's rotation
        dvn = ((1.0 - 2.0 * (qy * qy + qz * qz)) * ax + 2.0 * (qx * qy - qw * qz) * ay + 2.0 * (qx * qz + qw * qy) * az) * dt
        dve = (2.0 * (qx * qy + qw * qz) * ax + (1.0 - 2.0 * (qx * qx + qz * qz)) * ay + 2.0 * (qy * qz - qw * qx) * az) * dt
        dvd = (2.0 * (qx * qz - qw * qy) * ax + 2.0 * (qy * qz + qw * qx) * ay + (1.0 - 2.0 * (qx * qx + qy * qy)) * az) * dt
        body = b._replace(vn_m_s=b.vn_m_s + dvn, ve_m_s=b.ve_m_s + dve, vd_m_s=b.vd_m_s + dvd)
        self.state = self.state._replace(body=body)

    def deploy_canopy(self) -> None:
        """Open the parachute (once: a canopy cannot be packed again in flight)."""
        if self.canopy_deployed_at_s is None:
            self.canopy_deployed_at_s = self.time_s

    def hang_load(self, mass_kg: float) -> None:
        """A load on a string below the vehicle (a gripper closing on it on the ground)."""
        self.load = SlungLoad(mass_kg)

    def drop_load(self) -> None:
        self.load = None
        self._payload_v = None

    def _act_payloads(self, dt: float) -> None:
        """The load's weight and inertia, then the canopy's drag, over the last battery interval."""
        state, b = self.state, self.state.body
        v0 = v = (b.vn_m_s, b.ve_m_s, b.vd_m_s)
        if state.on_ground:  # resting: the canopy lies beside it, the load beneath
            self.payload_accel_ned = self._payload_v = None
            return
        mass, load, before = self.airframe.mass_kg, self.load, self._payload_v
        hanging_kg = load.mass_kg if load is not None and load.hangs(-b.d_m) else 0.0
        if hanging_kg:
            if before is not None:  # (else it has just begun to hang: from the next interval on)
                v = carried(before, v, GRAVITY_M_S2 * dt, mass, hanging_kg)
            mass += hanging_kg
        if self.canopy_deployed_at_s is not None:
            area = self.config.canopy.drag_area_at(self.time_s - self.canopy_deployed_at_s)
            v = slowed(v, self._wind_ned, area, mass, dt)
        self.payload_accel_ned = ((v[0] - v0[0]) / dt, (v[1] - v0[1]) / dt, (v[2] - v0[2]) / dt)
        self._payload_v = v if hanging_kg else None
        self.state = state._replace(body=b._replace(vn_m_s=v[0], ve_m_s=v[1], vd_m_s=v[2]))

    def set_motor_thrust_scale(self, thrust_scale: tuple) -> None:
        """Each motor's share of the thrust it is asked for (1 healthy, 0.7 weak, 0 failed): its
        speed reaches sqrt of that share of the command, thrust going with speed squared."""
        self._thrust_scale = tuple(thrust_scale)
        self._rescale()

    def cut_outputs(self, cut: bool) -> None:
        """Every motor's signal cut (an autopilot's safety switch on): no motor turns while cut,
        each is as its thrust scale says again after."""
        self._outputs_cut = cut
        self._rescale()

    def _rescale(self) -> None:
        shares = (0.0,) * len(self._thrust_scale) if self._outputs_cut else self._thrust_scale
        self._speed_scale = tuple(math.sqrt(min(max(x, 0.0), 1.0)) for x in shares)
        self.conditions_version += 1

    @property
    def motor_speed_scale(self) -> tuple:
        return self._speed_scale

    def set_battery_resting_voltage(self, volts: float) -> None:
        """Re-initialise the pack's charge to where it rests at `volts` (at most full): a battery
        fault, or a partly charged pack, as ArduPilot's SIM_BATT_VOLTAGE."""
        cells, capacity = self.airframe.battery_cells, self.airframe.battery_capacity_mah
        soc = soc_at_open_circuit_volts(volts / cells)
        current = self.battery.current_a
        ocv = cells * open_circuit_volts_per_cell(soc)
        r = self.airframe.battery_internal_resistance_ohm
        self.battery = BatteryState((1.0 - soc) * capacity, current, max(ocv - current * r, 0.0))

    def read_temperature(self, home_d_m: float) -> float:
        """The downward radiometric sensor: reads the ground below at the vehicle's height above
        it (above home's ground less the hill under it, if any)."""
        b = self.state.body
        return self.thermometer.read(b.n_m, b.e_m, home_d_m + self.config.terrain.ground_d_m(b.n_m, b.e_m) - b.d_m,
                                     self.time_s)

    def fly_traffic(self, dt_s: float, count: int, radius_m: float, alt_m: float) -> list[Aircraft]:
        """Move the other aircraft dt_s on around this vehicle; those flying."""
        b = self.state.body
        self.traffic.step(dt_s, self.time_s, count, (b.n_m, b.e_m), radius_m, alt_m)
        return self.traffic.flying()

    def read_beacon(self) -> tuple[float, float, float] | None:
        """Where the beacon sees this vehicle (north, east, down of it), or None."""
        b = self.state.body
        return None if self.beacon is None else self.beacon.sees(b.n_m, b.e_m, b.d_m)

    def ground_d_m(self) -> float:
        """The ground's down coordinate under the vehicle: 0 on the flat field, above it on a hill.
        (The beams meet the ground straight below: over a smooth hill and a modest tilt the
        difference from where a tilted beam lands is small.)"""
        b = self.state.body
        return self.config.terrain.ground_d_m(b.n_m, b.e_m)

    def read_sonar(self) -> float:
        """The downward rangefinder's beam to the ground below [m] (inf: it misses the ground)."""
        return self.sonar.range_m(self.state.body, self.ground_d_m())

    def read_flow(self) -> FlowSample | None:
        """The optical flow camera's new sample over the ground below, when one is due (SIM_FLOW_RATE)."""
        return self.flow_camera.read(self.time_s, self.state.body, self.ground_d_m())

    @property
    def battery_remaining(self) -> float:
        return remaining_fraction(self.battery, self.airframe.battery_capacity_mah)

    @property
    def wind_ned(self) -> tuple:
        return self._wind_ned

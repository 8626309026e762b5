"""The vehicle: sensors -> estimate -> flight mode -> cascaded PID -> allocation -> sim step.

This module is the loop and the command facade. The parts it runs each own one idea: the state
estimate (estimate.py), arming and the pre-arm checks (safety/arming.py), the land detector and
auto-disarm (safety/land_detector.py), the failsafes (safety/), mission progress
(mission/progress.py), the flight modes (modes/, which see the vehicle only through a
ModeContext) and the control cascade (control/). It knows nothing of MAVLink or sockets: ground
stations reach it through the command methods, which return a Result (MAV_RESULT numbers) and
queue what ArduCopter would announce in `events`.
"""
from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from functools import partial
from operator import attrgetter
from typing import TYPE_CHECKING

from firefly.sim.geo import GeoPoint, global_from_ned, ned_from_global
from firefly.sim.sensors import GpsReading
from firefly.sim.vehicle import BATTERY_EVERY, SimConfig, SimVehicle

from .adsb.escape import CopterEscape
from .location import ZERO as NOWHERE
from .location import Loc, loc_of
from .adsb.sitl_transceiver import SitlTransceiver
from .adsb.sitl_transceiver import report_of as sitl_report
from .adsb.threats import Avoidance, Collision
from .adsb.traffic_list import AdsbReport, TrafficList
from .control.attitude import wrap_pi
from .startup import Startup, StartupTimeline
from .tuning.gains import GainOverlay, Params
from .version import board_id_for
from .control.compiled import make_cascade
from .estimate import StateEstimate
from .external_nav import ExternalNav
from .faults.world import Faults, world_values
from .follow_target import FollowTarget
from .mission import FENCE, MISSION, MissionStore
from .mission.progress import MissionProgress
from .mission.terrain import TerrainItems
from .surface_distance import SurfaceDistance
from .terrain import FROM_DATABASE, FROM_RANGEFINDER, VehicleTerrain
from .modes import MODE_BY_NUMBER, Mode, ModeNumber, Setpoint
from .modes.auto_rtl import EITHER, AutoRtl
from .modes.context import ModeContext
from .modes.manual import pilot_climb_rate
from .modes.return_path import ReturnPath
from .params import ParamStore
from .pilot import PilotInput
from .rc import RadioInput
from .rc.aux import announcement, run_aux_function
from .rates import LoopRates
from .motor_outputs import OUTPUT_OF_MOTOR, omega_of_pwm
from .motor_test import COMPASS_CAL, DELAY_TEXT_EVERY_S, MotorTest
from .results import Result, Severity
from .safety.arming import REPORTED_CHECKS, Arming, arm_refusals, prearm_failure, prearm_failures
from .safety.failsafe import Failsafes
from .safety.fence_breach import destination_within_fence
from .safety.fence_shapes import FenceShapes, Shape
from .safety.simple_avoid import USE_PROXIMITY, FenceGeometry, SimpleAvoid
from .proximity import Proximity
from .safety.fence_switch import FenceSwitch
from .safety.internal_error import CONSTRAINING_NAN, FLOW_OF_CONTROL, InternalErrors
from .safety.land_detector import AutoDisarm, LandDetector
from .safety.prearm_display import NO_ARMING_CHANGE_TEXT, PrearmDisplay
from .safety.thrust_loss import ThrustLossCheck
from .path_planning.planner import PathPlanner
from .payload.camera import Camera
from .payload.gripper import Gripper
from .payload.mount import Mount, read_rc, take_roi
from .payload.parachute import Parachute
from .payload.sitl_gripper import SitlGripper
from .payload.sitl_parachute import SitlParachute
from .payload.sprayer import Sprayer
from .payload.winch import Winch
from .precland import BODY_FRD, LOCAL_FRD, PrecLand, Steer, line_of_sight
from .precland import MAVLINK as PRECLAND_MAVLINK
from .precland import SITL as PRECLAND_SITL
from .rangefinder import UPDATE_S as RANGEFINDER_UPDATE_S
from .rangefinder import RangeStatus
from .rangefinder import TERRAIN_HEIGHT_VALID_S
from .rangefinder import Rangefinder
from .optical_flow import OpticalFlow
from .servo_relay import ServoRelayEvents
from .views import ReadThrough, Vector3

if TYPE_CHECKING:
    from firefly.sim.battery import BatteryState
    from firefly.sim.rigid_body import BodyState
    from firefly.sim.sensors import GpsReading, RcReceiver

    from .cli.script import Script

FAILSAFE_EVERY = 10  # flight-mode ticks between failsafe checks (10 Hz at the default 100 Hz)
RETURN_PATH_EVERY = 3  # failsafe checks between SmartRTL path updates (ArduCopter: 3 Hz)
PREARM_DISPLAY_PERIOD_S = 1.0  # AP_Arming::update's rate
LAND_DETECTOR_ERROR_LINE = 66  # ArduCopter's land_detector.cpp line of its "climbed while landed" error
MAX_PENDING_TEXTS = 64  # STATUSTEXTs waiting for the next poll; a loop of texts cannot grow memory
EKF_LANES = ("IMU0", "IMU1")  # ArduCopter SITL's two EKF3 cores, each says what it does
TERRAIN_UPDATE_S = 0.1  # AP_Terrain::update runs at 10 Hz (Copter.cpp terrain_update)
HOME_RANGE_M = 50_000  # DO_SET_HOME farther than this from the origin is refused
LOCATION_ALT_MAX_M = 83_000  # the largest altitude ArduPilot's Location holds: home and commands' positions
SPEED_MAX_WPNAV = 5.0  # DO_CHANGE_SPEED is capped at this multiple of WPNAV_SPEED


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
    startup: StartupTimeline | None = None  # None: armable at once; else ArduCopter's start-up (startup.py)
    board_id: str = ""  # SITL's system id (version.py), read at the I/O edge; "" = SITL's fallback
    powered_on_at_s: float = 0.0  # the runner's sim time at power-on: a rebooted vehicle's clock starts again


class Vehicle:
    def __init__(self, config: VehicleConfig, params: ParamStore | None = None,
                 mission: MissionStore | None = None):
        config.rates.check()
        if config.rates.physics_hz != config.sim.physics_rate_hz:
            raise ValueError("sim physics rate and loop-rate table disagree")
        self.config = config
        self.system_id = config.system_id
        self.board_id = config.board_id or board_id_for(None, config.system_id - 1)
        self.powered_on_at_s = config.powered_on_at_s
        self.reboot_requested = False  # a PREFLIGHT_REBOOT_SHUTDOWN accepted: the I/O edge reboots it (io/reboot.py)
        self.params = params or ParamStore()
        self.mission = mission or MissionStore()
        self.mission_progress = MissionProgress(self.mission, self.notify)
        self.return_path = ReturnPath(self.params, self.notify)  # SMART_RTL's way back
        self.follow_target = FollowTarget(self.params, self.notify)  # FOLLOW's lead, as others report it
        self._return_path_due = 0  # failsafe checks until the next path update
        self.prearm_display = PrearmDisplay()  # the "PreArm: " texts said unasked
        self._prearm_display_at_s = PREARM_DISPLAY_PERIOD_S  # sim time of the next update
        # AP_Notify's pre_arm_check: the pre-arm checks' last verdict, SYS_STATUS's PREARM health.
        # ArduCopter runs them once a second (AP_Arming::update), at an ARM and at RUN_PREARM_CHECKS,
        # not at each SYS_STATUS: a change shows up to a second late, and nothing is checked per send.
        self.prearm_passed = False
        self.script: Script | None = None  # a scenario's scripted commands (autopilot.cli.script.Script), if any
        n0, e0 = config.offset_ne_m
        # Where this vehicle's EKF origin lies in the sim's frame (its start, where ArduCopter sets
        # the origin at its first fix): MAVLink's local frame (LOCAL_POSITION_NED, HOME_POSITION's
        # x/y/z, SET_POSITION_TARGET_LOCAL_NED) is relative to it, so each of several vehicles of
        # a process has its own, as each ArduCopter has.
        self.ekf_origin_ne = (n0, e0)
        self.origin = config.home
        self.sim = SimVehicle(config.sim, math.radians(config.home_yaw_deg), n0, e0)
        for name, value in {**world_values(config.sim), **config.faults}.items():
            self.params.set(name, value)
        self.faults = Faults(self.sim, self.params, self.origin)
        self.startup = Startup(config.startup)
        self.estimate = StateEstimate(self.sim, config.rates.physics_hz, self.startup, self.params)
        airframe = config.sim.airframe
        self.thrust_max_n = 4.0 * airframe.max_rotor_thrust_n
        self.omega_max_rad_s = airframe.omega_max_rad_s
        self.omega_idle_rad_s = airframe.omega_idle_rad_s
        self.arming = Arming()
        self.internal_errors = InternalErrors()
        self.land_detector = LandDetector(airframe.weight_n)
        self.auto_disarm = AutoDisarm()
        self.failsafes = Failsafes()
        self.fence = FenceSwitch(self.params)
        self._fence_shapes = FenceShapes()
        # OA_TYPE's path planner round the fence (made at boot), which modes' waypoint legs ask
        self.path_planner = PathPlanner(self.params, self.fence_shapes, self.fence, self.notify)
        self.path_planner_prearm_failure = self.path_planner.prearm_failure
        self.simple_avoid = SimpleAvoid(self.params)
        self.thrust_loss = ThrustLossCheck()
        self.cascade = make_cascade(self.sim, self.params, config.rates, config.compiled)
        self._gains: Params = self.params  # what the controllers are configured from
        self.params.on_change(self._param_changed)
        self._hear_positions()
        # The parameter and mission files with a write waiting for its interval (persist.JsonFile):
        # the session polls them while this is not empty.
        self.stores_waiting: set = set()
        self.params.file.waiting = self.mission.file.waiting = self.stores_waiting
        self.servo_relay = ServoRelayEvents(self.params, self.notify)  # DO_SET_SERVO / _RELAY and repeats
        # CAM1 (AP_Camera): pictures on command, by interval and by distance; drives those outputs
        self.camera = Camera(self, self.params, self.servo_relay.pwm, self.servo_relay.relays,
                             self.constraining_nan)
        self.camera_status = self.camera.status
        # MNT1 (AP_Mount): a servo gimbal, made at boot from MNT1_TYPE, on the pan / tilt / roll outputs
        self.mount = Mount(self.params, self.servo_relay.pwm, self.constraining_nan)
        # The parachute (CHUTE_*), the sprayer (SPRAY_*) and the gripper (GRIP_*), driving those
        # outputs too; SITL's simulated parachute (SIM_PARA_*) fires on its output and opens the
        # sim's canopy, its simulated gripper (SIM_GRPS_*) takes up a load and lets it go
        self.parachute = Parachute(self.params, self.servo_relay.pwm, self.servo_relay.relays, self.notify,
                                   partial(self.disarm, "parachute", force=True))
        self.parachute_prearm_failure = self.parachute.prearm_failure
        self.sprayer = Sprayer(self.params, self.servo_relay.pwm)
        self.sitl_parachute = SitlParachute(self.params, self.servo_relay.pwm, self.notify, self.sim.deploy_canopy)
        self.gripper = Gripper(self.params, self.servo_relay.pwm, self.notify)
        # The winch (WINCH_*): made at boot from WINCH_TYPE, its line reckoned from the rate it asks
        self.winch = Winch(self.params, self.servo_relay.pwm, self.notify, self.constraining_nan, self._winch_stick)
        self.winch_prearm_failure = self.winch.prearm_failure
        self.motor_test = MotorTest()
        self._motor_test_omega = (0.0, 0.0, 0.0, 0.0)
        self.safety_on = False  # the safety switch (SITL boots with it off: BRD_SAFETY_DEFLT 0)
        self._arming_stuck = False  # a test ended on an armed vehicle: ARM answers ACCEPTED, arms nothing
        self._delay_text_at_s = -math.inf  # when ArduPilot's blocking-delay callback last spoke
        self.sitl_gripper = SitlGripper(self.params, self.servo_relay.pwm, self.sim.hang_load, self.sim.drop_load)
        # RNGFND1 (AP_RangeFinder): SITL's beam or a companion's DISTANCE_SENSOR, read at 20 Hz
        self.rangefinder = Rangefinder(self.params)
        self.rangefinder_reading = self.rangefinder.reading
        self.rangefinder_prearm_failure = self.rangefinder.prearm_failure
        # The optical flow sensor (AP_OpticalFlow): SITL's camera when FLOW_TYPE is 10 at boot
        self.optical_flow = OpticalFlow(self.params)
        # Precision landing (AC_PrecLand): PLND_TYPE's sensor made at boot, steering LAND to a target
        self.precland = PrecLand(self.params)
        self.proximity = Proximity(self.params)
        # ADS-B (adsb/): the receiver's traffic list (ADSB_TYPE), avoidance (AVD_ENABLE) and what the
        # copter does about a threat; both run at 10 Hz with the failsafe checks once either is on
        self.mode_changes = 0  # modes entered so far: whether the mode avoidance chose still stands
        self.traffic = TrafficList(self.params)
        self.avoidance = Avoidance(self.params, CopterEscape(self, self.failsafes))
        self.collisions_due: list[Collision] = []  # COLLISION reports for every link
        # SITL's transceiver for the simulated traffic (SIM_ADSB_*, [[traffic]]), there if SIM_ADSB_COUNT >= 0
        # at boot or the scenario flies aircraft;
        # what it reports goes to the list, or (ADSB_TYPE 0) out to every link as it is
        self.sitl_transceiver = SitlTransceiver(self.params["SIM_ADSB_COUNT"] >= 0 or bool(config.sim.traffic))
        self.adsb_forwards_due: list[AdsbReport] = []
        self._adsb_wanted = False  # ADSB_TYPE, AVD_ENABLE or SITL's traffic: the 10 Hz ADS-B update runs
        self._want_adsb()
        self.adsb_next_to_send = self.traffic.next_to_send  # (now_ms): the ADSB stream's next message
        self.ctx = ModeContext(self)
        # The parts' own methods that readers call through their views (views.py), bound once:
        # no call in between (telemetry and the failsafes call them for every vehicle, often).
        self.attitude_known = self.estimate.attitude_known
        self.origin_known = self.estimate.origin_known
        self.local_position_known = self.estimate.local_position_known
        self.startup_initialising = self.startup.initialising  # (t_s)
        self.startup_arm_blockers = self.startup.arm_blockers  # (t_s)
        self.internal_error_prearm_text = self.internal_errors.prearm_text
        self.internal_error_fields = self.internal_errors.sys_status_fields
        self.mission_status = self.mission_progress.status
        self.fence_items = partial(self.mission.items, FENCE)
        self.mission_items = partial(self.mission.items, MISSION)
        self.mission_uses_terrain = TerrainItems(self.mission)
        self.terrain = VehicleTerrain()  # the terrain database a ground station fills (AP_Terrain)
        self.surface = SurfaceDistance()  # the downward rangefinder's terrain offset
        self._terrain_updated_s = -math.inf
        self.modes: dict[int, Mode] = {number: cls() for number, cls in MODE_BY_NUMBER.items()}
        self.mode = self.modes[ModeNumber.STABILIZE]
        # A mode entered before what it needs is there (disarmed before home, as ArduCopter
        # allows) is entered for real, its enter() run, once it is: until then it flies nothing.
        self._mode_entered = True
        self.setpoint = Setpoint()
        self.home_ned: Vector3 | None = None
        # Where heights are measured from until home is set: the ground the vehicle boots on (its
        # barometer's zero, as ArduCopter's altitude without a GPS origin)
        self.boot_ground_d = self.sim.state.body.d_m
        self.home_sets = 0  # times home was set: a cleared mission lists home again after the next
        # The pilot's radio: SITL's receiver and the ground station's overrides (rc/); the
        # flight-mode and aux switches taken where they are at power-on, before anyone listens.
        self.rc = RadioInput(self.sim.rc, self.params)
        self.rc.read(0.0)
        self._power_on_mode_switch = self.rc.settle_switches()
        self.motors_emergency_stopped = False  # aux MOTOR_ESTOP / ARM_EMERGENCY_STOP
        self.events: list[tuple[int, str]] = []
        # Who else hears each status text as it is made (the dataflash log's MSG records): set by
        # the I/O edge, None when nothing logs.
        self.text_listener: Callable[[int, str], None] | None = None
        self.nav_speed_m_s = self.params["WPNAV_SPEED"] / 100.0
        self._loiter_speed_max = self.params["LOIT_SPEED"] / 100.0 * 2.0
        self._mode_every = config.rates.ratio(config.rates.mode_hz)
        # physics steps between the rangefinder's reads; 0 without one (the type is read at boot)
        self._rangefinder_every = self._mode_every * max(1, round(RANGEFINDER_UPDATE_S * config.rates.mode_hz)) \
            if self.rangefinder.kind else 0
        self._dt_mode = 1.0 / config.rates.mode_hz
        # The cascade runs in chunks that end wherever Python has work: a mode tick, a sensor
        # sample or a battery update (the sim integrates the battery every BATTERY_EVERY steps).
        est = self.estimate
        self._chunk = math.gcd(self._mode_every, est.gps_every, est.temperature_every, BATTERY_EVERY)
        if est.origin_known():  # by default the GPS has a fix at once: armable from the first heartbeat
            self._set_home_here()
        if self._power_on_mode_switch is not None:  # the switch's mode, as ArduCopter's first reading
            self._mode_switch_to(self._power_on_mode_switch)

    # ----- state, as modes, safety checks and telemetry read it -------------------------------
    # The state most read, as C-level attribute getters (failsafes and telemetry read them often).
    # Each reader family reads through a typed view of these (views.py), never into the parts.
    time_s: ReadThrough[float] = property(attrgetter("sim.time_s"), doc="Sim time [s].")
    body: ReadThrough[BodyState] = property(attrgetter("estimate.body"), doc="The state estimate (estimate.py).")
    attitude: ReadThrough[Vector3] = property(attrgetter("estimate.attitude"), doc="(roll, pitch, yaw) [rad].")
    gps: ReadThrough[GpsReading] = property(attrgetter("estimate.gps"), doc="The last GPS sample.")
    gps_fitted: ReadThrough[bool] = property(attrgetter("estimate.gps_fitted"), doc="GPS1_TYPE is not 0.")
    gps_detected: ReadThrough[bool] = property(attrgetter("estimate.gps_detected"),
                                               doc="A receiver is there (a companion's once it has sent GPS_INPUT).")
    external_nav: ReadThrough[ExternalNav] = property(attrgetter("estimate.external_nav"),
                                                      doc="VISO_TYPE's sensor (external_nav.py).")
    armed: ReadThrough[bool] = property(attrgetter("arming.armed"))
    auto_armed: ReadThrough[bool] = property(attrgetter("arming.auto_armed"), doc="AUTO may start from the ground.")
    adsb_threat: ReadThrough[bool] = property(attrgetter("failsafes.adsb"), doc="ADS-B avoidance is acting.")
    interlock_at_s: ReadThrough[float] = property(attrgetter("arming.interlock_at_s"),
                                                  doc="Sim time the arming delay ends [s].")
    arm_changes: ReadThrough[int] = property(attrgetter("arming.changes"), doc="Arms and disarms so far.")
    landed: ReadThrough[bool] = property(attrgetter("land_detector.landed"))
    # ... the rest of the estimate and the sensors, as telemetry reports them
    true_body: ReadThrough[BodyState] = property(attrgetter("estimate.true_body"), doc="The sim's own state.")
    battery: ReadThrough[BatteryState] = property(attrgetter("estimate.battery"), doc="The pack, as its monitor reads it.")
    battery_remaining: ReadThrough[float] = property(attrgetter("estimate.battery_remaining"), doc="0..1.")
    rc_receiver: ReadThrough[RcReceiver] = property(attrgetter("sim.rc"), doc="The simulated RC receiver.")
    temperature: ReadThrough[tuple[float, float]] = property(attrgetter("estimate.temperature"),
                                                             doc="(sim time of the sample, ground degrees C).")
    baro_alt_m: ReadThrough[float] = property(attrgetter("estimate.baro_alt_m"), doc="The barometer's last sample.")
    accel_body: ReadThrough[Vector3] = property(attrgetter("estimate.accel_body"), doc="The accelerometer (FRD).")
    mag_body_mgauss: ReadThrough[Vector3] = property(attrgetter("estimate.mag_body_mgauss"))
    wind_ned: ReadThrough[Vector3] = property(attrgetter("estimate.wind_ned"))
    motor_speeds_rad_s: ReadThrough[tuple[float, float, float, float]] = property(
        attrgetter("estimate.motor_speeds_rad_s"))
    # ... the cascade's targets and commands
    thrust_demand_n: ReadThrough[float] = property(attrgetter("cascade.thrust_t"), doc="U1 demand [N].")
    lean_target: ReadThrough[tuple[float, float]] = property(
        attrgetter("cascade.lean_t"), doc="(roll, pitch) the position loop asks of the attitude loop [rad].")
    yaw_target: ReadThrough[float] = property(attrgetter("cascade.yaw_t"), doc="The heading target [rad].")
    motor_commands: ReadThrough[tuple[float, float, float, float]] = property(
        attrgetter("cascade.omega_cmd"), doc="The four motor speed commands [rad/s].")
    servo_pwm: ReadThrough[list[int]] = property(
        attrgetter("servo_relay.pwm"), doc="Outputs 1-16 as DO_SET_SERVO / DO_REPEAT_SERVO set them [us], 0 = never.")
    # ... the current mode's declarations
    mode_number: ReadThrough[int] = property(attrgetter("mode.number"))
    mode_name: ReadThrough[str] = property(attrgetter("mode.name"))
    mode_requires_position: ReadThrough[bool] = property(attrgetter("mode.requires_position"))
    mode_requires_terrain_failsafe: ReadThrough[bool] = property(attrgetter("mode.requires_terrain_failsafe"))
    mode_named_float: ReadThrough[tuple[bytes, float] | None] = property(
        attrgetter("mode.named_float"), doc="A value the mode reports by name (FLOWHOLD's HEST).")
    mode_allows_arming: ReadThrough[bool] = property(attrgetter("mode.allows_arming"))
    mode_manual_throttle: ReadThrough[bool] = property(attrgetter("mode.manual_throttle"))
    # ... the failsafes, the internal errors and the mission store
    failsafe_active: ReadThrough[bool] = property(attrgetter("failsafes.active"), doc="Any failsafe on.")
    battery_failsafe_level: ReadThrough[int] = property(attrgetter("failsafes.battery_level"),
                                                        doc="0 ok, 1 low, 2 critical.")
    fence_breaches: ReadThrough[int] = property(attrgetter("failsafes.fence.breaches"))  # AC_FENCE_TYPE_* bits
    fence_breach_count: ReadThrough[int] = property(attrgetter("failsafes.fence.count"))
    fence_breach_time_ms: ReadThrough[int] = property(attrgetter("failsafes.fence.time_ms"))
    gps_glitching: ReadThrough[bool] = property(attrgetter("failsafes.ekf.gps_glitching"))
    ekf_test_ratios: ReadThrough[tuple[float, float]] = property(
        attrgetter("failsafes.ekf.test_ratios"), doc="EKF3's GPS velocity and position variances, as modelled.")
    internal_error_bits: ReadThrough[int] = property(attrgetter("internal_errors.bits"))
    mission_version: ReadThrough[int] = property(attrgetter("mission.version"), doc="Bumped on every change.")
    precland_kind: ReadThrough[int] = property(attrgetter("precland.kind"), doc="PLND_TYPE's sensor, 0 none.")
    precland_healthy: ReadThrough[bool] = property(attrgetter("precland.healthy"))
    rangefinder_kind: ReadThrough[int] = property(attrgetter("rangefinder.kind"),
                                                  doc="RNGFND1_TYPE's driver made at boot, 0 none.")
    rangefinder_down: ReadThrough[bool] = property(attrgetter("rangefinder.down"),
                                                   doc="A rangefinder faces down (RANGEFINDER, SYS_STATUS).")
    rangefinder_enabled: ReadThrough[bool] = property(attrgetter("rangefinder.enabled"),
                                                      doc="ArduCopter's rangefinder_state.enabled.")

    def has_position(self) -> bool:
        return self.estimate.has_position()

    def ekf_has_origin(self) -> bool:
        return self.estimate.has_origin()

    def ekf_aiding(self) -> bool:
        """The EKF still aids its position (15 s after the last it fused), else holds a constant one."""
        return self.estimate.aiding()

    def navigating_externally(self) -> bool:
        """The horizontal position is external navigation's (the source set's POSXY 6, a pose fused)."""
        return self.estimate.nav_offset_ne is not None

    @property
    def height_ref_d(self) -> float:
        """The down coordinate heights are measured from: home's, or before home the ground the
        vehicle booted on."""
        home = self.home_ned
        return self.boot_ground_d if home is None else home[2]

    pilot: ReadThrough[PilotInput] = property(attrgetter("rc.pilot"), doc="The sticks as the radio reads them (rc/radio.py).")

    @property
    def radio_input_valid(self) -> bool:
        """ArduCopter's has_valid_input (Failsafes.radio_input_valid)."""
        return self.failsafes.radio_input_valid

    def pilot_climb_rate(self) -> float:
        """The climb rate the throttle stick asks of ALT_HOLD and alike [m/s]; 0 while the
        radio is not to be trusted."""
        return pilot_climb_rate(self.ctx) if self.failsafes.radio_input_valid else 0.0

    def rc_channels_us(self) -> list[int]:
        """Every channel [us] as the radio last read it (RC_CHANNELS)."""
        return self.rc.radio_in

    def _winch_stick(self) -> tuple[list[int], bool]:
        """The channels as the radio last read them, and whether it is to be trusted (the winch's stick)."""
        return self.rc.radio_in, self.failsafes.radio_input_valid

    def rc_throttle_us(self) -> int | None:
        """The throttle channel [us] if a frame or an override came within the last failsafe
        check, else None (the radio is silent)."""
        if self.time_s - self.rc.updated_at_s > FAILSAFE_EVERY * self._dt_mode + 1e-9:
            return None
        return self.rc.throttle_us()

    # ----- the pilot's switches ----------------------------------------------------------------
    def _read_mode_switch(self, now: float) -> None:
        """The flight-mode switch, after the channels moved (not while the radio is in failsafe
        or its throttle reads low)."""
        rc = self.rc
        if self.failsafes.radio_input_valid:
            position = rc.mode_switch_moved(now)
            rc.switches_dirty = rc.mode_switch.settling
            if position is not None:
                self._mode_switch_to(position)

    def _mode_switch_to(self, position: int) -> None:
        self.set_mode(int(self.params[f"FLTMODE{position + 1}"]))

    def reset_mode_switch(self) -> None:
        """A mode's aux switch moved off: the flight-mode switch's mode is taken back once read."""
        self.rc.mode_switch.forget()
        self.rc.switches_dirty = True

    def _read_aux_switches(self, now: float) -> None:
        """ArduCopter's read_aux_all (10 Hz): each aux switch that has moved runs its function."""
        if not self.failsafes.radio_input_valid:
            return
        for channel, option, position in self.rc.aux_switches_moved(now):
            text = announcement(channel, option, position)
            if text is not None:
                self.notify(text)
            run_aux_function(self, option, position)

    def set_servo(self, channel: int, pwm: int) -> Result:
        """DO_SET_SERVO (servo_relay.py): FAILED for an output that is missing or in use."""
        return Result.ACCEPTED if self.servo_relay.set_servo(channel, pwm) else Result.FAILED

    def repeat_servo(self, channel: int, pwm: int, count: int, cycle_s: float) -> Result:
        """DO_REPEAT_SERVO (servo_relay.py), from now: FAILED as set_servo."""
        done = self.servo_relay.repeat_servo(channel, pwm, count, cycle_s, self.time_s)
        return Result.ACCEPTED if done else Result.FAILED

    def set_relay(self, relay: int, state: int) -> Result:
        """DO_SET_RELAY (servo_relay.py): FAILED for a relay that is not one."""
        return Result.ACCEPTED if self.servo_relay.set_relay(relay, state) else Result.FAILED

    def repeat_relay(self, relay: int, count: int, cycle_s: float) -> Result:
        """DO_REPEAT_RELAY (servo_relay.py), from now: FAILED as set_relay."""
        done = self.servo_relay.repeat_relay(relay, count, cycle_s, self.time_s)
        return Result.ACCEPTED if done else Result.FAILED

    def relay_masks(self) -> tuple[int, int]:
        """RELAY_STATUS's present and on masks (servo_relay.py)."""
        return self.servo_relay.relay_masks()

    def parachute_action(self, action: int) -> Result:
        """DO_PARACHUTE: 0 disables it, 1 enables it, 2 releases it as the pilot would (refused on
        the ground and below CHUTE_ALT_MIN: payload/parachute.py); anything else FAILED."""
        chute = self.parachute
        if action == 0:
            chute.enable(False)
        elif action == 1:
            chute.enable(True)
        elif action == 2:
            chute.manual_release(self.time_s, self.land_detector.landed, self.height_above_home_m())
        else:
            return Result.FAILED
        return Result.ACCEPTED

    def gripper_action(self, action: int) -> Result:
        """DO_GRIPPER: FAILED while GRIP_ENABLE is 0; 0 releases, 1 grabs (payload/gripper.py),
        anything else FAILED."""
        if not self.gripper.enabled or action not in (0, 1):
            return Result.FAILED
        if action == 0:
            self.gripper.release(self.time_s)
        else:
            self.gripper.grab(self.time_s)
        return Result.ACCEPTED

    def winch_action(self, action: int, length_m: float, rate_m_s: float) -> Result:
        """DO_WINCH: FAILED without a winch made at boot (and WINCH_TYPE still set); 0 relaxes it,
        1 lets out a length (negative: winds it in), 2 runs it at a rate; anything else FAILED."""
        winch = self.winch
        if not winch.fitted:
            return Result.FAILED
        if action == 0:
            winch.relax()
        elif action == 1:
            winch.release_length(length_m)
        elif action == 2:
            winch.set_rate(rate_m_s)
        else:
            return Result.FAILED
        return Result.ACCEPTED

    def start_motor_test(self, seq: int, kind: int, value: float, timeout_s: float, count: int) -> Result:
        """DO_MOTOR_TEST (motor_test.py): refused in words unless landed and not emergency-stopped;
        a test that runs already takes the new settings."""
        test = self.motor_test
        if not test.running:
            refusal = ("vehicle not landed" if not self.land_detector.landed else
                       "Safety switch" if self.safety_on else
                       "Motor Emergency Stopped" if self.motors_emergency_stopped else None)
            if refusal is not None:
                self.notify(f"Motor Test: {refusal}", Severity.CRITICAL)
                return Result.FAILED
        starting = test.start(seq, kind, value, timeout_s, count, self.time_s)
        if starting:
            self.notify("starting motor test")
        if kind == COMPASS_CAL and self.time_s - self._delay_text_at_s > DELAY_TEXT_EVERY_S:
            # the per-motor compass calibration starts with 200 ms of blocking compass reads, and
            # ArduPilot's delay callback says this when it has not for 5 s
            self._delay_text_at_s = self.time_s
            self.notify("Initialising ArduPilot")
        return Result.ACCEPTED

    @property
    def motors_armed(self) -> bool:
        """HEARTBEAT's armed flag: ArduCopter's motors, which a motor test arms too."""
        return self.arming.armed or self.motor_test.running

    def set_safety_switch(self, on: bool) -> None:
        """DO_SET_SAFETY_SWITCH_STATE: on, no motor output reaches its motor (SITL writes 0 us),
        in flight too, and arming is refused; off, they flow again (measured)."""
        self.safety_on = on
        self.sim.cut_outputs(on)

    @property
    def motor_test_pwm(self) -> list[int] | None:
        """Outputs 1-4 while a motor test runs, else None."""
        return self.motor_test.outputs(self.pwm_range[0]) if self.motor_test.running else None

    @property
    def pwm_range(self) -> tuple[int, int]:
        """MOT_PWM_MIN..MOT_PWM_MAX as the motor library takes them (integers; 0 is 1000..2000)."""
        p = self.params
        return int(p["MOT_PWM_MIN"] or 1000), int(p["MOT_PWM_MAX"] or 2000)

    def _motor_test_tick(self, now: float) -> None:
        """The test's outputs, spun by the sim's motors; its end said, and the motors disarmed."""
        test = self.motor_test
        if self.arming.armed and now < self.arming.interlock_at_s:  # no motor interlock in the arming delay
            self.notify("Motor Test: cancelled")
            test.stop()
        elif test.update(now, self.pwm_range, self.rc.radio_in[2]):
            low, high = self.pwm_range
            p = self.params
            outputs = test.outputs(low)
            self._motor_test_omega = tuple(  # type: ignore[assignment]
                omega_of_pwm(outputs[output - 1], low, high, p["MOT_SPIN_MIN"], p["MOT_SPIN_MAX"], p["MOT_THST_EXPO"],
                             self.omega_idle_rad_s, self.omega_max_rad_s)
                for output in OUTPUT_OF_MOTOR)
            return
        self.notify("finished motor test")
        if self.arming.armed:  # the motors disarmed, in silence, and ArduCopter's arming left set:
            self._disarm_now(None)  # ARM and DISARM are ACCEPTED from then on and change nothing
            self._arming_stuck = True

    def run_sprayer(self, on: bool) -> None:
        """DO_SPRAYER (payload/sprayer.py)."""
        self.sprayer.run(on, self.time_s)

    def _rangefinder_height(self) -> float | None:
        """ArduCopter's rangefinder_alt_ok height [m]: a downward rangefinder's good reading, else None."""
        if not self.rangefinder_kind or not self.rangefinder.down or not self.rangefinder.enabled:
            return None
        r = self.rangefinder.reading()
        return r.distance_m if r.status == RangeStatus.GOOD else None

    def _precland_tick(self, now: float) -> None:
        """SITL's beacon read (when it is the sensor), then AC_PrecLand's update."""
        pl = self.precland
        if not self.params["PLND_ENABLED"]:
            return
        if pl.kind == PRECLAND_SITL and self.sim.beacon is not None and self.sim.beacon_on:
            seen = self.sim.read_beacon()
            pl.healthy = seen is not None
            if seen is not None:
                length = math.sqrt(seen[0] ** 2 + seen[1] ** 2 + seen[2] ** 2)
                distance = length if int(self.params["SIM_PLD_OPTIONS"]) & 1 else 0.0
                pl.heard((-seen[0] / length, -seen[1] / length, -seen[2] / length), distance, now)
        b = self.body
        pl.update(now, self.notify, (b.n_m, b.e_m, b.d_m), self._rangefinder_height())

    def precland_landing(self, land_speed_m_s: float) -> Steer | None:
        """What precision landing makes of LAND now (precland.py's Steer), None without it."""
        pl = self.precland
        if not pl.kind or not self.params["PLND_ENABLED"]:
            return None
        b = self.body
        return pl.landing(self.time_s, self.notify, self._rangefinder_height(), (b.n_m, b.e_m, b.d_m), land_speed_m_s)

    def fence_shapes(self) -> tuple[Shape, ...]:
        """The stored fence's polygons and circles in the local frame."""
        return self._fence_shapes.shapes(self.mission.version, self.fence_items, self.ned_of)

    def destination_within_fence(self, n: float, e: float, d: float) -> bool:
        """A GUIDED destination (local NED) within every enabled fence (fence_breach.py)."""
        enabled = self.fence.enabled_fences
        if not enabled or self.home_ned is None:
            return True
        return destination_within_fence(enabled, self.params, self.fence_shapes(), self.home_ned, (n, e, d))

    def _fence_geometry(self) -> FenceGeometry:
        b, home = self.estimate.body, self.home_ned or (0.0, 0.0, 0.0)
        prox = self.proximity
        near = prox.good and int(self.params["AVOID_ENABLE"]) & USE_PROXIMITY != 0
        return FenceGeometry((b.n_m, b.e_m), (home[0], home[1]), home[2] - b.d_m, self.fence.enabled_fences,
                             self.fence_shapes(), self.params, prox.obstacles() if near else (),
                             self.estimate.attitude[2], prox.upward_m if near else None)

    def _proximity_update(self, now: float) -> None:
        """10 Hz: the proximity sensor (proximity.py); SITL's lidar reads the inclusion fence."""
        shapes = self.fence_shapes()
        b = self.estimate.body
        here = (b.n_m, b.e_m)

        def outside(dn: float, de: float) -> bool:
            point = (here[0] + dn, here[1] + de)
            return any(shape.contains(point) != shape.inclusion for shape in shapes)

        home = self.home_ned or (0.0, 0.0, 0.0)
        fenced = any(shape.inclusion and shape.kind == "poly" for shape in shapes)
        self.proximity.update(now, self.estimate.attitude[2], outside, fenced, home[2] - b.d_m)

    def obstacle_distance(self, distances, increment_deg: float, angle_offset_deg: float, min_cm: int,
                          max_cm: int) -> None:
        """A companion's OBSTACLE_DISTANCE: PRX1_TYPE 2's reading (proximity.py), each reading
        an obstacle for the path planner's database (path_planning/obstacle_database.py)."""
        readings = self.proximity.obstacle_distance(distances, increment_deg, angle_offset_deg, min_cm, max_cm,
                                                    self.time_s)
        database = self.path_planner.database
        if readings and database is not None:
            b, home = self.estimate.body, self.home_ned or (0.0, 0.0, 0.0)
            here, attitude = (b.n_m, b.e_m, -b.d_m), self.estimate.attitude
            for bearing_deg, metres in readings:
                database.push(self.time_s, here, attitude, bearing_deg, metres, (home[0], home[1], -home[2]))

    def obstacle_distance_3d(self, stamp_ms: int, frame: int, xyz: tuple[float, float, float], min_m: float,
                             max_m: float) -> None:
        """A companion's OBSTACLE_DISTANCE_3D: a point for PRX1_TYPE 2 (proximity.py)."""
        self.proximity.obstacle_3d(stamp_ms, frame, xyz, min_m, max_m, self.time_s)

    def avoid_velocity(self, vel_neu: Vector3, accel_m_s2: float, dt: float) -> Vector3:
        """A velocity (north, east, up) as simple avoidance lets it be flown (safety/simple_avoid.py),
        with the position controller's gains and the mode's horizontal acceleration."""
        avoid = self.simple_avoid
        if not avoid.wanted(self.fence.enabled_fences, self.proximity.good) or not self.has_position():
            return vel_neu
        p = self.params
        return avoid.adjust_velocity(self._fence_geometry(), vel_neu, p["PSC_POSXY_P"], accel_m_s2, p["PSC_POSZ_P"],
                                     p["PILOT_ACCEL_Z"] / 100.0, self.time_s, dt)

    def avoid_lean(self, lean: tuple[float, float]) -> tuple[float, float]:
        """ALT_HOLD's lean with the proximity sensor's push (safety/simple_avoid.py)."""
        prox = self.proximity
        if not prox.good or not int(self.params["AVOID_ENABLE"]) & USE_PROXIMITY:
            return lean
        return self.simple_avoid.adjust_lean(prox.objects(), lean, math.radians(self.params["ANGLE_MAX"] / 100.0))

    def terrain_here(self) -> Loc | None:
        """Where the terrain database looks from: the vehicle's location, once it has one."""
        return loc_of(self.position_global()) if self.has_position() else None

    def terrain_update(self) -> None:
        """AP_Terrain::update, at its 10 Hz, run when someone asks (reports, requests, pre-arm)."""
        if self.time_s - self._terrain_updated_s < TERRAIN_UPDATE_S:
            return
        self._terrain_updated_s = self.time_s
        home = self.home
        self.terrain.update(self.params, self.terrain_here(), None if home is None else loc_of(home), self.mission)

    def _track_surface(self, now: float) -> None:
        """The downward rangefinder's reading as a terrain offset (surface_distance.py)."""
        r, b = self.rangefinder.reading(), self.body
        self.surface.update(now, r.status == RangeStatus.GOOD, r.valid_count, r.distance_m,
                            1.0 - 2.0 * (b.qx * b.qx + b.qy * b.qy), -b.d_m, RANGEFINDER_UPDATE_S,
                            float(self.params["SURFTRAK_TC"]))

    def terrain_from_rangefinder(self) -> bool:
        """AC_WPNav's terrain source is the rangefinder (WPNAV_RFND_USE and one enabled facing down),
        else the terrain database."""
        return bool(self.params["WPNAV_RFND_USE"]) and self.rangefinder.enabled

    def terrain_source(self) -> str | None:
        """AC_WPNav::get_terrain_source: the rangefinder, else the terrain database while
        TERRAIN_ENABLE is on, else none."""
        if self.terrain_from_rangefinder():
            return FROM_RANGEFINDER
        return FROM_DATABASE if self.params["TERRAIN_ENABLE"] else None

    def terrain_offset_m(self) -> float | None:
        """The terrain's height above the local origin under the vehicle [m] (AC_WPNav's terrain
        offset): the rangefinder's while it is healthy when it is the source; else the database's,
        the last known while there is none here, and before any was known 0 m AMSL, as
        AP_Terrain::height_above_terrain extrapolates from its last height, which starts at 0
        (measured: DO_REPOSITION in the terrain frame ACCEPTED with no tile served); None with
        no source or no position."""
        source = self.terrain_source()
        if source is None:
            return None
        if source == FROM_RANGEFINDER:
            surface = self.surface
            return surface.offset_m if surface.healthy else None
        self.terrain_update()
        here = self.terrain_here()
        if here is None:
            return None
        height = self.terrain.height_amsl(self.params, here)
        if height is None:
            last = self.terrain.last_current_height_m
            height = 0.0 if last is None else last
        return height - self.origin.alt_m

    def terrain_offset_at(self, n_m: float, e_m: float) -> float | None:
        """The terrain database's height above the local origin at a local point [m], None where
        it holds none (or is off): Location::change_alt_frame to above terrain."""
        height = self.terrain.height_amsl(self.params, loc_of(global_from_ned(self.origin, n_m, e_m, 0.0)))
        return None if height is None else height - self.origin.alt_m

    def terrain_failsafe(self) -> None:
        """A mode that needs the terrain has none (failsafe_terrain_on_event): said; landed it
        disarms, RTL starts again above home, any other mode goes to RTL (else LAND)."""
        self.failsafes.terrain = True
        self.notify("Failsafe: Terrain data missing", Severity.CRITICAL)
        if self.land_detector.landed:
            self.disarm("terrain failsafe")
        elif self.mode.number == ModeNumber.RTL:
            self.mode.restart_without_terrain(self.ctx)
        elif self.set_mode(ModeNumber.RTL) != Result.ACCEPTED:
            self.set_mode(ModeNumber.LAND)

    def terrain_status(self, found: bool) -> None:
        self.failsafes.terrain_status(found, self.time_s)

    @property
    def terrain_failsafe_on(self) -> bool:
        return self.failsafes.terrain

    def terrain_height_known(self) -> bool:
        """ArduCopter's EKF3 terrain height estimate (EKF_STATUS_REPORT's EKF_POS_VERT_AGL): valid
        for 5 s after a good downward range, none without a rangefinder (measured: area ekf_flags)."""
        return self.time_s - self.rangefinder.last_good_s < TERRAIN_HEIGHT_VALID_S

    def avoid_limits_active(self) -> bool:
        """Whether simple avoidance changed a wanted velocity within the last half second."""
        return self.simple_avoid.limits_active(self.time_s)

    def avoid_climb(self, climb_m_s: float, dt: float) -> float:
        """The pilot's climb rate as the altitude fences let it be flown (safety/simple_avoid.py)."""
        avoid = self.simple_avoid
        if not climb_m_s or not avoid.wanted(self.fence.enabled_fences, self.proximity.good):
            return climb_m_s
        p = self.params
        return avoid.adjust_climb_rate(self._fence_geometry(), climb_m_s, p["PSC_POSZ_P"], p["PILOT_ACCEL_Z"] / 100.0, dt)

    def landing_target(self, frame: int, angle_x: float, angle_y: float, distance: float,
                       xyz: tuple[float, float, float], position_valid: bool) -> None:
        """A companion's LANDING_TARGET (PLND_TYPE 1), as AC_PrecLand_MAVLink takes it: only in the
        body or the heading-turned local frame ("Plnd: Frame not supported", once, otherwise)."""
        pl = self.precland
        if pl.kind != PRECLAND_MAVLINK or not self.params["PLND_ENABLED"]:
            return
        if frame not in (BODY_FRD, LOCAL_FRD):
            if not pl.said_frame:
                pl.said_frame = True
                self.notify("Plnd: Frame not supported", Severity.INFO)
            return
        seen = line_of_sight(frame, angle_x, angle_y, distance, xyz, position_valid, self.attitude)
        if seen is not None:
            pl.heard(seen[0], seen[1], self.time_s)

    def vision_pose(self, xyz: tuple[float, float, float], quality: int = 0, reset_counter: int = 0) -> None:
        """A companion's pose (VISION_POSITION_ESTIMATE and its kin): metres north, east and down
        in its frame, which starts where MAVLink's local frame does (external_nav.py)."""
        on, oe = self.ekf_origin_ne
        est = self.estimate
        was = est.nav_offset_ne is not None
        est.external_pose((on, oe, self.boot_ground_d), xyz, quality, reset_counter)
        ext = est.external_nav
        if not was and est.nav_offset_ne is not None and not ext.announced:
            ext.announced = True  # as EKF3 says it once, when it starts using the pose (IMU1's core first)
            b = self.body
            for lane in reversed(EKF_LANES):
                self.notify(f"EKF3 {lane} is using external nav data")
                self.notify(f"EKF3 {lane} initial pos NED = {b.n_m - on:.1f},{b.e_m - oe:.1f},"
                            f"{b.d_m - self.boot_ground_d:.1f} (m)")
                if ext.speeds:  # only with a velocity from the companion too
                    self.notify(f"EKF3 {lane} initial vel NED = {b.vn_m_s:.1f},{b.ve_m_s:.1f},{b.vd_m_s:.1f} (m/s)")

    def gps_input(self, gps_id: int, fix_type: int, lat_deg: float, lon_deg: float, alt_m: float,
                  vel_ned: tuple[float, float, float], satellites: int) -> None:
        """A companion's GPS_INPUT: the receiver's fix when GPS1_TYPE is 14 (AP_GPS_MAV), its
        first one announced as AP_GPS detects a receiver. Only the first receiver's (gps_id 0)."""
        est = self.estimate
        if not est.gps_from_mavlink or gps_id != 0:
            return
        if not all(math.isfinite(x) for x in (lat_deg, lon_deg, alt_m, *vel_ned)):
            return
        if abs(lat_deg) > 90 or abs(lon_deg) > 180 or abs(alt_m) > LOCATION_ALT_MAX_M:
            return  # no place on earth: dropped
        n, e, d = self.ned_of(lat_deg, lon_deg, alt_m)
        if est.take_gps_input(GpsReading(n, e, d, *vel_ned, satellites, fix_type)):
            self.notify("GPS 1: detected MAV")

    def vision_speed(self) -> None:
        """A companion's VISION_SPEED_ESTIMATE: it keeps the sensor healthy."""
        self.estimate.external_nav.speed(self.time_s)

    def use_source_set(self, n: int) -> None:
        """EK3_SRCn_* become the estimate's sources (MAV_CMD_SET_EKF_SOURCE_SET, RC function 90).
        Where the estimate jumps, the point the mode holds jumps with it."""
        self._estimate_jumps(lambda: self.estimate.use_source_set(n))

    def _estimate_jumps(self, change: Callable[[], None]) -> None:
        """change() may make the horizontal estimate jump: the point the mode holds jumps with it."""
        est = self.estimate
        before = est.position_offset_ne or (0.0, 0.0)
        change()
        after = est.position_offset_ne or (0.0, 0.0)
        if after != before:
            self._position_reset(after[0] - before[0], after[1] - before[1])

    def _position_reset(self, dn: float, de: float) -> None:
        if self._mode_entered:
            self.mode.position_reset(dn, de)

    def take_position_estimate(self, lat_deg: float, lon_deg: float, age_s: float, accuracy_m: float) -> Result:
        """MAV_CMD_EXTERNAL_POSITION_ESTIMATE's position, as it was age_s ago: FAILED unless the
        estimate takes one now (StateEstimate.takes_told_position). Taken, the estimate jumps there
        and the point held with it, and nothing is said. A point off the globe (ArduCopter takes
        it, and its estimate goes thousands of kilometres astray) is answered but not taken."""
        est = self.estimate
        if not est.takes_told_position():
            return Result.FAILED
        if abs(lat_deg) <= 90 and abs(lon_deg) <= 180:
            n, e, _ = self.ned_of(lat_deg, lon_deg, self.origin.alt_m)
            self._estimate_jumps(lambda: est.take_told_position(n, e, age_s, accuracy_m))
        return Result.ACCEPTED

    def source_set_switch(self, position: int) -> None:
        """RC function 90: low, middle and high choose source sets 1, 2 and 3, and say so."""
        self.use_source_set(position + 1)
        self.notify(f"Using EKF Source Set {position + 1}")

    def set_gps_global_origin(self, lat_deg: float, lon_deg: float, alt_m: float) -> bool:
        """SET_GPS_GLOBAL_ORIGIN: the EKF's origin, taken only while it has none (from a GPS fix or
        an earlier message). The sim's frame keeps its place; what moves is where it lies on the
        earth, so that MAVLink's local frame starts at the given point. Whether it was taken."""
        est = self.estimate
        if est.origin_known() or not all(math.isfinite(x) for x in (lat_deg, lon_deg, alt_m)):
            return False
        if abs(lat_deg) > 90 or abs(lon_deg) > 180:
            return False
        on, oe = self.ekf_origin_ne
        given = GeoPoint(lat_deg, lon_deg, alt_m)
        self.origin = global_from_ned(given, -on, -oe, -self.boot_ground_d)
        est.origin_set_by_message = True
        for lane in EKF_LANES:
            self.notify(f"EKF3 {lane} origin set")
        if self.home_ned is None and self.has_position():  # as ArduCopter: home where it is, at once
            self._set_home_here(in_flight=not self.land_detector.landed)
        self.notify(f"Field Elevation Set: {alt_m:.0f}m")
        return True

    def adsb_vehicle(self, report: AdsbReport) -> None:
        """An ADSB_VEHICLE from any link: traffic for the receiver's list (adsb/traffic_list.py)."""
        self.traffic.receive(report, int(self.time_s * 1000))

    def _hear_positions(self) -> None:
        p = self.params
        self._follows_or_avoids = bool(p["FOLL_ENABLE"]) or bool(int(p["DEV_OPTIONS"]) & 1)

    def hears_positions(self) -> bool:
        """Whether another system's GLOBAL_POSITION_INT can matter here: FOLLOW (FOLL_ENABLE),
        avoidance of MAVLink positions (DEV_OPTIONS bit 0), a gimbal pointed at a system. The
        vehicles of one process hear each other (io/shared_air.py): asked first, a swarm of N
        costs N² of these instead of N² message reads."""
        return self._follows_or_avoids or self.mount.target_sysid != 0

    def position_heard(self, system_id: int, lat_e7: int, lon_e7: int, alt_mm: int, vx_cms: int, vy_cms: int,
                       vz_cms: int) -> None:
        """Another system's GLOBAL_POSITION_INT: with DEV_OPTIONS bit 0 (ADSBMavlinkProcessing) an
        obstacle for avoidance, as ArduCopter takes it; where the gimbal's system is (mode 5)."""
        mount = self.mount
        if mount.fitted and system_id == mount.target_sysid and self.origin_known() \
                and -900_000_000 <= lat_e7 <= 900_000_000 and -1_800_000_000 <= lon_e7 <= 1_800_000_000:
            _, _, d = self.ned_of(lat_e7 * 1e-7, lon_e7 * 1e-7, alt_mm / 1000.0)
            n, e, _ = self.ned_of(lat_e7 * 1e-7, lon_e7 * 1e-7, self.origin.alt_m)
            mount.sysid_point = (n, e, self.height_ref_d - d)
        if system_id != self.system_id and int(self.params["DEV_OPTIONS"]) & 1:
            self.avoidance.position_heard(int(self.time_s * 1000), system_id, Loc(lat_e7, lon_e7, int(alt_mm * 0.1)),
                                          (vx_cms * 0.01, vy_cms * 0.01, vz_cms * 0.01))

    def _want_adsb(self) -> None:
        p = self.params
        self._adsb_wanted = bool(p["ADSB_TYPE"] or p["AVD_ENABLE"]) or self.sitl_transceiver.attached

    def lists_traffic(self) -> bool:
        """Whether the ADS-B list runs (AP_ADSB's enabled()): ADSB_VEHICLE is then not forwarded."""
        return self.traffic.started and self.traffic.enabled

    def adsb_location(self) -> Loc | None:
        """Where the vehicle is, as ADS-B compares it with traffic; None without a position."""
        if not self.has_position():
            return None
        return loc_of(self.position_global())

    def height_above_home_m(self) -> float:
        return self.height_ref_d - self.body.d_m

    def _adsb_update(self, now: float) -> None:
        """ArduCopter's avoidance_adsb_update, at 10 Hz: the list, then the threats."""
        now_ms = int(now * 1000)
        traffic = self.traffic
        p = self.params
        if self.sitl_transceiver.attached:
            flying = self.sim.fly_traffic(self._dt_mode * FAILSAFE_EVERY, int(p["SIM_ADSB_COUNT"]),
                                          p["SIM_ADSB_RADIUS"], p["SIM_ADSB_ALT"])
            if int(p["SIM_ADSB_TYPES"]) & 1 and self.sitl_transceiver.due(now):
                origin = loc_of(self.origin)
                for a in flying:
                    if traffic.enabled:
                        traffic.receive(sitl_report(a, origin), now_ms)
                    else:
                        self.adsb_forwards_due.append(sitl_report(a, origin))
        own = self.adsb_location()
        traffic.update(now_ms, own or NOWHERE)
        b = self.body
        collision = self.avoidance.update(now_ms, traffic.take_samples if traffic.started else list, own,
                                          (b.vn_m_s, b.ve_m_s, b.vd_m_s) if own is not None else None)
        if collision is not None:
            self.collisions_due.append(collision)

    def distance_sensor(self, orientation: int, distance_cm: int, min_cm: int, max_cm: int, sensor_type: int,
                        signal_quality: int) -> None:
        """A companion's DISTANCE_SENSOR: RNGFND1_TYPE 10's reading (rangefinder.py), and PRX1_TYPE
        2's when it faces one of the eight ways or up (proximity.py)."""
        self.rangefinder.heard(self.time_s, orientation, distance_cm, min_cm, max_cm, sensor_type, signal_quality)
        if self.proximity.kind:
            self.proximity.distance_sensor(orientation, distance_cm, min_cm, max_cm, self.time_s)

    def aux_function(self, number: int, position: int) -> Result:
        """MAV_CMD_DO_AUX_FUNCTION: DENIED for a position past HIGH, FAILED for a function
        ArduCopter does not know."""
        if position not in (0, 1, 2):
            return Result.DENIED
        return Result.ACCEPTED if run_aux_function(self, number, position) else Result.FAILED

    def rangefinder_switch(self, position: int) -> None:
        """The RANGEFINDER aux function (rangefinder.py)."""
        self.rangefinder.switched(position == 2)

    def avoid_adsb_switch(self, position: int) -> None:
        """The AVOID_ADSB aux function (38): avoidance on (HIGH, with the ADS-B list running) or off,
        until AVD_ENABLE is next set (ArduPilot sets the value in RAM and does not save it)."""
        if position == 2:
            if not self.traffic.available():
                self.notify("ADSB not available", Severity.CRITICAL)
                return
            self.avoidance.switched = True
            self.notify("ADSB Avoidance Enabled", Severity.CRITICAL)
        else:
            self.avoidance.switched = False
            self.notify("ADSB Avoidance Disabled", Severity.CRITICAL)

    def zigzag_switch(self, which: str, position: int) -> None:
        """ZIGZAG's aux switches (SaveWP, Auto), in ZIGZAG only."""
        mode = self.mode
        if which == "save_wp":
            mode.switch_save_wp(position)  # type: ignore[attr-defined]
        else:
            mode.switch_auto(position)  # type: ignore[attr-defined]

    @property
    def home(self) -> GeoPoint | None:
        if self.home_ned is None:
            return None
        return global_from_ned(self.origin, *self.home_ned)

    def controls_position(self) -> bool:
        """The horizontal position controller flies the current mode (Mode.controls_position)."""
        return self.mode.controls_position(self.ctx)

    def destination(self) -> tuple[float, float, float | None] | None:
        """Where the current mode flies to, if anywhere (Mode.destination)."""
        return self.mode.destination()

    def nav_distance_bearing(self) -> tuple[float, float] | None:
        """NAV_CONTROLLER_OUTPUT's distance and bearing as the current mode reports them, when
        not from its destination (Mode.nav_distance_bearing)."""
        return self.mode.nav_distance_bearing()

    def unix_time_us(self) -> int:
        return self.config.epoch_unix_us + int(self.time_s * 1e6)

    def ned_to_global(self, n: float, e: float, d: float) -> GeoPoint:
        return global_from_ned(self.origin, n, e, d)

    def ekf_origin(self) -> GeoPoint:
        """Where MAVLink's local frame starts: the EKF origin, on the ground this vehicle booted on."""
        on, oe = self.ekf_origin_ne
        return self.ned_to_global(on, oe, self.boot_ground_d)

    def local_ne(self, n: float, e: float) -> tuple[float, float]:
        """MAVLink's local north/east (from this vehicle's EKF origin) of a point of the sim's frame."""
        on, oe = self.ekf_origin_ne
        return n - on, e - oe

    def sim_ne(self, x: float, y: float) -> tuple[float, float]:
        """The sim's north/east of MAVLink's local x/y (local_ne's inverse)."""
        on, oe = self.ekf_origin_ne
        return x + on, y + oe

    def ned_of(self, lat: float, lon: float, alt_amsl: float) -> Vector3:
        return ned_from_global(self.origin, lat, lon, alt_amsl)

    def position_global(self) -> GeoPoint:
        b = self.body
        return global_from_ned(self.origin, b.n_m, b.e_m, b.d_m)

    def landed_state(self) -> str:
        """ON_GROUND, TAKEOFF, IN_AIR or LANDING (MAV_LANDED_STATE names)."""
        if self.landed:
            return "ON_GROUND"
        return self.mode.landed_state_hint(self.ctx) or "IN_AIR"

    def prearm_failure(self) -> str | None:
        """The first failing pre-arm check, worded as ArduCopter's 'PreArm: ...', or None."""
        return prearm_failure(self)

    def is_armable(self) -> bool:
        """Every pre-arm check passes now (an ARM's view; SYS_STATUS shows prearm_passed, the
        once-a-second verdict)."""
        return self.prearm_failure() is None

    def prearm_checked(self, failures: list[str]) -> None:
        """The pre-arm checks were run (an ARM, RUN_PREARM_CHECKS) and found `failures`."""
        self.prearm_passed = not failures

    def notify(self, text: str, severity: int = Severity.INFO) -> None:
        events = self.events
        if len(events) >= MAX_PENDING_TEXTS:  # as ArduPilot's queue: the oldest gives way
            del events[0]
        events.append((int(severity), text))
        if self.text_listener is not None:
            self.text_listener(int(severity), text)

    def poll_stores(self, link_s: float) -> None:
        """The link time now, for the stores' writes; the writes that are due."""
        self.params.file.poll(link_s)
        self.mission.file.poll(link_s)

    def drain_events(self) -> list[tuple[int, str]]:
        events, self.events = self.events, []
        return events

    def _param_changed(self, name: str, value: float) -> None:
        self.cascade.configure(self._gains)
        self._loiter_speed_max = self.params["LOIT_SPEED"] / 100.0 * 2.0
        if name == "WPNAV_SPEED":
            self.nav_speed_m_s = value / 100.0
        elif name == "FENCE_ENABLE":
            self.fence.follow_param(self.params)
        elif name == "AVD_ENABLE":
            self.avoidance.switched = None
        if name in ("ADSB_TYPE", "AVD_ENABLE"):
            self._want_adsb()
        elif name.startswith("EK3_SRC"):
            self._estimate_jumps(self.estimate.follow_sources)
        elif name in ("FOLL_ENABLE", "DEV_OPTIONS"):
            self._hear_positions()

    # ----- commands: arming ------------------------------------------------------------------
    def arm(self, force: bool = False) -> Result:
        if self.armed or self._arming_stuck or self.motor_test.running:  # (a test's motors are armed)
            return Result.ACCEPTED
        refusals = arm_refusals(self, force)
        if refusals:
            for text in refusals:
                self.notify(text, Severity.CRITICAL)
            if not force:  # (a forced ARM runs no pre-arm checks)
                self.prearm_checked(prearm_failures(self, REPORTED_CHECKS))
            return Result.FAILED
        if not force:
            self.prearm_passed = True
        est = self.estimate
        if self.home_ned is None and est.origin_known() and est.local_position_known():  # else it stays unset
            self._set_home_here()
        self.arming.arm(self.attitude[2], self.time_s)
        b = self.body
        self.return_path.set_home(self.has_position(), (b.n_m, b.e_m, b.d_m), self.time_s)
        self.land_detector.set_landed()
        self.auto_disarm.restart(self.time_s)
        self.cascade.reset()
        self._say_arming_change("Arming motors")
        return Result.ACCEPTED

    def disarm(self, reason: str = "", force: bool = False) -> Result:
        if not self.armed:
            return Result.ACCEPTED
        if not force and not self.landed:
            return Result.FAILED  # ArduCopter refuses in silence
        self._disarm_now("Disarming motors")
        return Result.ACCEPTED

    def _disarm_now(self, text: str | None) -> None:
        self.arming.disarm()
        self.mission_progress.reset()  # as ArduCopter: a mission flown again starts over
        if text is not None:
            self._say_arming_change(text)
        for mode in self.modes.values():  # after that text, as ArduCopter's AutoTune says its own
            mode.on_disarm(self.ctx, mode is self.mode)

    def _say_arming_change(self, text: str) -> None:
        """Unless ARMING_OPTIONS bit 1 asks for silence (measured: no text either way)."""
        if not int(self.params["ARMING_OPTIONS"]) & NO_ARMING_CHANGE_TEXT:
            self.notify(text)

    def _set_home_here(self, in_flight: bool = False) -> None:
        """Home where the vehicle is; set in flight (the first fix after a take-off without GPS)
        at the height of the ground it booted on, as ArduCopter's set_home_to_current_location_inflight
        takes the EKF origin's altitude, not the flight's."""
        b = self.body
        self.home_ned = (b.n_m, b.e_m, self.boot_ground_d if in_flight else b.d_m)
        self.home_sets += 1

    # ----- commands: modes and navigation ------------------------------------------------------
    def set_mode(self, number: int) -> Result:
        new = self.modes.get(number)
        if new is None:
            self.notify(f"No such mode {number}", Severity.WARNING)
            return Result.FAILED
        if new is self.mode:
            return Result.ACCEPTED
        # As ArduCopter, a disarmed vehicle may enter any mode: the checks guard flight only.
        reason = "requires position" if self.armed and new.requires_position and not self.has_position() else None
        ready = self._needs_met(new)
        if reason is None and not ready and self.armed:
            reason = "requires home"
        if reason is None and ready and new.requires_flow and not self.optical_flow.healthy(self.time_s):
            reason = "init failed"  # ArduCopter's FLOWHOLD init(): the sensor enabled and healthy
        if reason is None and ready:
            reason = new.enter(self.ctx)
        if reason is not None:
            self.notify(f"Mode change to {new.text_name} failed: {reason}", Severity.WARNING)
            return Result.FAILED
        if self._mode_entered:
            self.mode.exit(self.ctx)
        self.mode = new
        self.mode_changes += 1
        self._mode_entered = ready
        self.cascade.reset_position()
        self.failsafes.fence.mode_changed(self, self.time_s)
        return Result.ACCEPTED

    def use_gains(self, gains: Mapping[str, float] | None) -> None:
        """Fly these ATC_* gains in place of the parameters' (None: the parameters' own), until
        told otherwise: AUTOTUNE's trial sets, which ArduCopter neither saves nor announces."""
        self._gains = self.params if not gains else GainOverlay(self.params, gains)
        self.cascade.configure(self._gains)

    def restart_position_control(self) -> None:
        """Bumpless hand-over to the position loop inside a mode (GUIDED from an attitude target)."""
        self.cascade.reset_position()

    def _needs_met(self, mode: Mode) -> bool:
        """Whether the vehicle has what `mode` declares it needs to fly (Mode.requires_home)."""
        return self.home_ned is not None or not mode.requires_home

    @property
    def mode_flying(self) -> bool:
        """Whether the current mode has been entered for real (not waiting for what it needs)."""
        return self._mode_entered

    def takeoff(self, alt_m: float) -> Result:
        """User takeoff to alt_m above home: only armed, landed, in a mode with user takeoff."""
        if not (self.armed and self.landed and self.mode.has_user_takeoff) or not math.isfinite(alt_m):
            return Result.FAILED
        alt_m = max(alt_m, self.params["PILOT_TKOFF_ALT"] / 100.0)
        if alt_m <= self.height_ref_d - self.body.d_m:
            return Result.FAILED
        self.mode.user_takeoff(self.ctx, alt_m)
        self.arming.auto_armed = True
        self.auto_disarm.cancel()
        return Result.ACCEPTED

    def guided_goto(self, n: float, e: float, d: float | None, yaw: float | None = None,
                    vel_ff: Vector3 = (0.0, 0.0, 0.0), terrain: bool = False) -> Result:
        yaw = None if yaw is None else wrap_pi(yaw)  # as ArduPilot wraps a heading it is given
        return Result.ACCEPTED if self.mode.goto(self.ctx, n, e, d, yaw, vel_ff, terrain) else Result.DENIED

    def guided_velocity(self, vn: float, ve: float, vd: float, yaw: float | None = None) -> Result:
        yaw = None if yaw is None else wrap_pi(yaw)
        return Result.ACCEPTED if self.mode.set_velocity(self.ctx, vn, ve, vd, yaw) else Result.DENIED

    def guided_target(self, pos: Vector3 | None, vel: Vector3 | None, accel: Vector3 | None,
                      yaw: float | None = None, yaw_rate: float | None = None, yaw_relative: bool = False,
                      terrain: bool = False) -> Result:
        """A GUIDED target of any kind (Mode.set_target); DENIED where no mode takes it."""
        yaw = None if yaw is None or yaw_relative else wrap_pi(yaw)
        ok = self.mode.set_target(self.ctx, pos, vel, accel, yaw, yaw_rate, yaw_relative, terrain)
        return Result.ACCEPTED if ok else Result.DENIED

    def guided_attitude(self, attitude: Vector3 | None, rates: Vector3, climb_or_thrust: float,
                        use_thrust: bool) -> Result:
        ok = self.mode.set_attitude(self.ctx, attitude, rates, climb_or_thrust, use_thrust)
        return Result.ACCEPTED if ok else Result.DENIED

    def guided_stop(self) -> None:
        """A GUIDED target ArduCopter finds invalid makes it stop (Mode.stop)."""
        self.mode.stop(self.ctx)

    def pause(self, paused: bool) -> Result:
        """DO_PAUSE_CONTINUE: FAILED where the mode cannot stop or go on."""
        return Result.ACCEPTED if self.mode.pause(self.ctx, paused) else Result.FAILED

    def set_vertical_speed(self, up_m_s: float | None, dn_m_s: float | None) -> Result:
        """DO_CHANGE_SPEED's climb or descent speed: FAILED where the mode flies none."""
        return Result.ACCEPTED if self.mode.set_vertical_speed(self.ctx, up_m_s, dn_m_s) else Result.FAILED

    def set_yaw(self, angle_deg: float, relative: bool, direction: int, rate_deg_s: float = 0.0) -> Result:
        """CONDITION_YAW: to a heading, or by an angle (relative); direction -1 counter-clockwise,
        1 clockwise, 0 the shorter way; at rate_deg_s (not above 0: the default slew)."""
        if not -360.0 <= angle_deg <= 360.0:
            return Result.FAILED
        rate = math.radians(rate_deg_s) if rate_deg_s > 0 else 0.0  # NaN: the default too
        # ArduCopter accepts it in every mode; only modes that steer the heading act on it.
        self.mode.turn(self.ctx, math.radians(angle_deg), rate, direction, relative)
        return Result.ACCEPTED

    def turn_by(self, offset_deg: float) -> None:
        """ArduCopter's AutoYaw::set_yaw_angle_offset_deg: the heading turned by this much, in the
        modes that steer it (DO_MOUNT_CONTROL's yaw for a gimbal that cannot pan)."""
        self.mode.turn(self.ctx, math.radians(abs(offset_deg)), 0.0, 1 if offset_deg >= 0 else -1, True)

    def set_roi(self, roi: tuple[float, float, float] | None) -> Result:
        """DO_SET_ROI and its kin as commands: the point (north, east, up above home) to look at,
        None to clear. ArduCopter accepts it in every mode and state: a gimbal that pans looks,
        else the modes whose heading follows one turn the vehicle (payload/mount.py's take_roi)."""
        take_roi(self.mount, partial(self.mode.set_roi, self.ctx), roi)
        return Result.ACCEPTED

    def fence_enable(self, action: int, fences: int) -> Result:
        """DO_FENCE_ENABLE as a command: fences switched on or off at run time (FENCE_ENABLE kept)."""
        ok = self.fence.command(action, fences, int(self.params["FENCE_TYPE"]), bool(self.fence_items()))
        return Result.ACCEPTED if ok else Result.FAILED

    def fence_enable_item(self, action: int) -> None:
        """DO_FENCE_ENABLE as a mission item: every configured fence, and AP_Mission's words."""
        said = self.fence.mission_item(action, int(self.params["FENCE_TYPE"]))
        if said is not None:
            self.notify(said, Severity.NOTICE)

    def set_home(self, ned: Vector3 | None) -> Result:
        """DO_SET_HOME: here (None) or at a local NED point within HOME_RANGE_M; FAILED before the
        EKF has an origin (a GPS fix), as ArduCopter's."""
        if not self.estimate.origin_known():
            return Result.FAILED
        if ned is None:
            self._set_home_here()
            return Result.ACCEPTED
        if not all(math.isfinite(x) for x in ned) or math.hypot(ned[0], ned[1]) > HOME_RANGE_M \
                or abs(ned[2]) > LOCATION_ALT_MAX_M:
            return Result.DENIED
        n, e, d = ned
        self.home_ned = (n, e, d)
        self.home_sets += 1
        return Result.ACCEPTED

    def set_speed(self, speed_m_s: float) -> Result:
        """DO_CHANGE_SPEED: only the modes that fly at a set speed take it (ArduCopter: FAILED else)."""
        if not self.mode.takes_speed_change or not speed_m_s > 0:  # infinity: the cap
            return Result.FAILED
        self.nav_speed_m_s = min(speed_m_s, self.params["WPNAV_SPEED"] / 100.0 * SPEED_MAX_WPNAV)
        return Result.ACCEPTED

    # ----- commands: the mission ---------------------------------------------------------------
    def set_mission_current(self, seq: int) -> bool:
        """MISSION_SET_CURRENT: a running mission flies that item at once; otherwise it is where
        the mission resumes. False (nothing changes) for a seq the list does not have."""
        return self.mission_progress.set_current(seq)

    def mission_start(self) -> Result:
        """MISSION_START: switch to AUTO and let the mission begin even from the ground."""
        result = self.set_mode(ModeNumber.AUTO)
        if result == Result.ACCEPTED:
            self.arming.auto_armed = self.armed
            # AUTO waiting for home starts (or resumes) the mission itself once it is entered
            if not self.mission_progress.running and self._mode_entered:
                self.mission_progress.start_or_resume(self.params["MIS_RESTART"] == 1)
        return result

    def auto_rtl(self, via: str) -> Result:
        """DO_LAND_START ("land_start") / DO_RETURN_PATH_START ("return_path"): AUTO RTL joining
        the mission only that way (modes/auto_rtl.py)."""
        mode = self.modes[ModeNumber.AUTO_RTL]
        assert isinstance(mode, AutoRtl)
        mode.via = via
        try:
            return self.set_mode(ModeNumber.AUTO_RTL)
        finally:
            mode.via = EITHER

    @property
    def in_mission_mode(self) -> bool:
        """MISSION_CURRENT's mission_mode: the current mode flies the mission."""
        return self.mode.number in (ModeNumber.AUTO, ModeNumber.AUTO_RTL)

    # ----- the loop ----------------------------------------------------------------------------
    def step(self) -> None:
        """One physics tick: the work due at this tick (sensors, flight mode), then the cascade."""
        self._advance(1)

    def run_until(self, t_s: float) -> None:
        """Step until sim time reaches t_s (to within 1 ns), in as few cascade runs as it takes."""
        dt, steps = self.sim.dt, self.sim.steps
        t_s -= self.powered_on_at_s  # the runner's clock -> this vehicle's, which started at its power-on
        target = max(steps, math.floor((t_s - 1e-9) / dt) - 1)
        while target * dt < t_s - 1e-9:  # the same test as time_s < t_s - 1e-9, step by step
            target += 1
        while self.sim.steps < target:
            self._advance(target - self.sim.steps)

    def _advance(self, most: int) -> None:
        """The Python work due at this physics step, then up to `most` steps of the cascade,
        stopping before the next step that has Python work."""
        steps = self.sim.steps
        est = self.estimate
        if steps % est.gps_every == 0:
            jump = est.sample_gps()
            if jump is not None:  # the GPS again, after a position a client told
                self._position_reset(*jump)
            # home with the origin, once the EKF has a horizontal position to put it at (measured:
            # none with GPS1_TYPE 0 and no external navigation, whatever the origin)
            if self.home_ned is None and est.origin_known() and est.local_position_known():
                self._set_home_here(in_flight=not self.land_detector.landed)
        if steps % est.temperature_every == 0:
            home = self.home_ned
            est.sample_temperature(self.boot_ground_d if home is None else home[2])  # height_ref_d
        if steps % self._mode_every == 0:
            self._mode_tick()
        sp = self.setpoint
        if est.position_offset_ne is not None:  # the estimate is off the truth (external navigation, a told position)
            sp = in_true_frame(sp, est.position_offset_ne, est.alt_error_m)
        elif est.alt_error_m and sp.pos_d is not None:
            sp = in_true_frame(sp, None, est.alt_error_m)
        if self.motor_test.running:  # the test drives the motors, the controllers rest
            self.cascade.run_fixed(min(most, self._chunk - steps % self._chunk), self._motor_test_omega)
            return
        arming, mode = self.arming, self.mode
        spinning = arming.armed and not (self.motors_emergency_stopped or mode.motors_stopped)
        if spinning and self.sim.time_s < arming.interlock_at_s:  # the arming delay
            if mode.skips_arming_delay:
                arming.interlock_at_s = self.sim.time_s
            else:
                spinning = False
        self.cascade.command(sp, spinning,
                             self.land_detector.landed,
                             min(sp.speed_xy, self._loiter_speed_max))
        self.cascade.run(min(most, self._chunk - steps % self._chunk))

    def _mode_tick(self) -> None:
        # The try blocks cost nothing until they catch (CPython 3.11); a helper function here
        # would cost a call at 100 Hz (3 % of a headless flight's instructions, measured).
        try:
            dt, now = self._dt_mode, self.sim.time_s
            estimate = self.estimate
            estimate.track_barometer()
            if self._rangefinder_every and self.sim.steps % self._rangefinder_every == 0:
                self.rangefinder.update(now, self.sim.read_sonar())
                if self.rangefinder.down:
                    self._track_surface(now)
            if self.optical_flow.kind:
                self.optical_flow.update(now, self.sim.read_flow())
            if self.precland.kind:
                self._precland_tick(now)
            rc = self.rc
            rc.read(now)  # ArduCopter's rc_loop: the channels, then (when they moved) the switches
            if rc.switches_dirty:
                self._read_mode_switch(now)
            if now >= self.startup.next_due_s:
                self.startup.say_due(now, self.origin.alt_m, self.notify)
            if self.script is not None:
                try:  # a scenario's step that raises must not starve the mode and the checks below
                    self.script.run_due(self)
                except Exception as exc:  # noqa: BLE001
                    self.internal_error(exc, "scenario script")
            if self._mode_entered or self._enter_when_ready():
                try:
                    self.mode.update(self.ctx, self.setpoint, dt)
                except Exception as exc:  # noqa: BLE001 - the checks below must still run
                    self.internal_error(exc, f"{self.mode.name} update")
            if self.camera.busy:  # a picture, an interval or distance triggering under way
                self.camera.update()
            if self.motor_test.running:
                self._motor_test_tick(now)
            if self.mount.fitted and now >= self.mount.next_update_s - 1e-9:
                self._mount_tick(now)
            if self.parachute.enabled:
                self._parachute_tick(now)
            if self.sprayer.running and now >= self.sprayer.next_update_s - 1e-9:
                b = estimate.body
                self.sprayer.update(now, math.hypot(b.vn_m_s, b.ve_m_s))
            if self.sitl_parachute.ready:
                self.sitl_parachute.update()
            if self.gripper.fitted and now >= self.gripper.next_update_s - 1e-9:
                self.gripper.update(now)
            if self.sitl_gripper.ready:
                self.sitl_gripper.update(now, -self.sim.state.body.d_m)
            if self.winch.kind and now >= self.winch.next_update_s - 1e-9:
                self.winch.update(now)
            armed, detector = self.arming.armed, self.land_detector
            if armed or not detector.landed:  # disarmed on the ground neither check has anything to do
                body = estimate.body
                home = self.home_ned
                home_d = self.boot_ground_d if home is None else home[2]  # height_ref_d, inlined
                if detector.update(body, armed, home_d, self.cascade.thrust_t, now):
                    self.auto_disarm.restart(now)
                if armed:
                    landed = detector.landed
                    # A mode that never auto-disarms (THROW, waiting armed) counts as wanting to climb.
                    wants_climb = landed and (self.setpoint.wants_climb(body.d_m) or not self.mode.auto_disarms)
                    # ArduCopter's check: throttle above half the hover's while landed, motors at full
                    # range; asked by the mode (the thrust of a landing's last tick does not count)
                    if wants_climb and self.mode.climbs_without_takeoff and \
                            self.cascade.thrust_t > 0.5 * detector.weight_n:
                        self._climbed_while_landed()
                    delay = self.params["DISARM_DELAY"]
                    if self.motors_emergency_stopped:  # ArduCopter halves it: nothing spins to show it is armed
                        delay /= 2
                        wants_climb = False
                    if self.auto_disarm.due(armed, landed, wants_climb, delay, now):
                        self.disarm("auto")
            if self.sim.steps % (self._mode_every * FAILSAFE_EVERY) == 0:
                self.failsafes.check(self)
                avoidance = self.avoidance
                if self._adsb_wanted or avoidance.on or avoidance.switched:
                    self._adsb_update(now)
                if self.proximity.kind:
                    self._proximity_update(now)
                self._read_aux_switches(now)
                self.thrust_loss.check(self, FAILSAFE_EVERY * dt)
                if self.servo_relay.repeating:
                    self.servo_relay.update(now)
                self._return_path_due -= 1
                if self._return_path_due <= 0:
                    self._return_path_due = RETURN_PATH_EVERY
                    self._update_return_path(now)
                if now >= self._prearm_display_at_s - 1e-9:
                    self._prearm_display_at_s = now + PREARM_DISPLAY_PERIOD_S
                    self._display_prearm(now)
        except Exception as exc:  # noqa: BLE001 - a bug is an internal error, never an exit
            self.internal_error(exc, f"{self.mode.name} tick")

    def _mount_tick(self, now: float) -> None:
        """The gimbal's 50 Hz update (payload/mount.py), from where the vehicle is above home and
        its RC channels."""
        b = self.estimate.body
        ref_d = self.height_ref_d
        here = (b.n_m, b.e_m, ref_d - b.d_m) if self.has_position() else None
        home = self.home_ned
        self.mount.update(now, self.attitude, here, None if home is None else (home[0], home[1], 0.0),
                          read_rc(self.params, self.rc.channel_us))

    def _parachute_tick(self, now: float) -> None:
        """The parachute's output, and its release on a sink rate (payload/parachute.py)."""
        vd = self.estimate.body.vd_m_s
        self.parachute.update(now, self.arming.armed, self.land_detector.landed, self.mode.checks_for_crashes,
                              vd, self.height_above_home_m())

    def _display_prearm(self, now: float) -> None:
        options = int(self.params["ARMING_OPTIONS"])
        failures = lambda: prearm_failures(self, REPORTED_CHECKS)  # noqa: E731
        display = self.prearm_display
        for reason in display.update(now, self.arming.armed, failures, options):
            self.notify(f"PreArm: {reason}", Severity.CRITICAL)
        self.prearm_passed = display.last_passed  # (armed: passed, as ArduCopter's checks pass armed)

    def _update_return_path(self, now: float) -> None:
        """Offer the position to SMART_RTL's path: kept while armed in any other mode."""
        b = self.estimate.body
        save = self.arming.armed and self.mode.number != ModeNumber.SMART_RTL
        self.return_path.update(self.has_position(), save, (b.n_m, b.e_m, b.d_m), now)

    def _climbed_while_landed(self) -> None:
        """ArduCopter's land detector finds the motors lifting a vehicle it thinks is landed while
        no takeoff runs: it records an internal error (and lets the vehicle fly)."""
        if self.internal_errors.flag(FLOW_OF_CONTROL, LAND_DETECTOR_ERROR_LINE, "land detector: climbing while landed"):
            self.notify(self.internal_errors.announcement(), Severity.CRITICAL)

    def _enter_when_ready(self) -> bool:
        """A mode chosen before what it needs was there is entered once it is; until then the
        setpoint asks for nothing (the vehicle is disarmed: only a disarmed vehicle waits)."""
        if not self._needs_met(self.mode):
            self.setpoint.clear()
            return False
        reason = self.mode.enter(self.ctx)
        if reason is not None:  # refused now (a disarmed mode never is today): STABILIZE takes over
            self.notify(f"Mode change to {self.mode.text_name} failed: {reason}", Severity.WARNING)
            self.mode = self.modes[ModeNumber.STABILIZE]
            self.mode.enter(self.ctx)  # STABILIZE refuses nothing
        self._mode_entered = True
        return True

    # ----- internal errors -----------------------------------------------------------------------
    def internal_error(self, exc: BaseException, where: str, in_flight_code: bool = True) -> None:
        """A bug raised inside the vehicle: counted and reported as ArduPilot reports its internal
        errors (SYS_STATUS, HEARTBEAT CRITICAL, a pre-arm failure that refuses arming). When the
        code that failed flies the vehicle (in_flight_code), it flies on in a mode that needs
        nothing from that code: an armed vehicle lands where it is; if LAND itself failed, it
        comes down level at LAND_SPEED. (A failed message handler changes no mode.)"""
        if self.internal_errors.record(exc, where):
            self.notify(self.internal_errors.announcement(), Severity.CRITICAL)
        if not (in_flight_code and self.armed):
            return
        land = self.modes[ModeNumber.LAND]
        if self.mode is not land:
            try:
                self.mode.exit(self.ctx)
            except Exception as again:  # noqa: BLE001 - the failed mode's tidy-up: LAND all the same
                self.internal_errors.record(again, f"{self.mode.name} exit")
            self.mode, self._mode_entered = land, True
            try:
                land.enter(self.ctx)
                return
            except Exception as again:  # noqa: BLE001
                self.internal_errors.record(again, "LAND entry")
        self._descend_level()

    def constraining_nan(self) -> None:
        """A NaN from a client reached a limit (ArduPilot's constrain of a NaN: its internal
        error constraining_nan, announced, refusing arming from then on); the vehicle flies on."""
        if self.internal_errors.flag(CONSTRAINING_NAN):
            self.notify(self.internal_errors.announcement(), Severity.CRITICAL)

    def _descend_level(self) -> None:
        """The last resort when LAND itself raised: level, straight down at LAND_SPEED."""
        sp = self.setpoint
        sp.clear()
        sp.lean = (0.0, 0.0)
        sp.vel_d = sp.speed_dn = self.params["LAND_SPEED"] / 100.0


def in_true_frame(sp: Setpoint, offset_ne: tuple[float, float] | None, alt_error_m: float) -> Setpoint:
    """The setpoint as the cascade, which flies the true state, must see it when the estimate is
    off the truth: by offset_ne horizontally (external navigation's error, or a told position's), and reading
    alt_error_m high: holding an estimated height means being that much lower."""
    true_sp = Setpoint()
    for name in Setpoint.__slots__:
        setattr(true_sp, name, getattr(sp, name))
    if sp.pos_d is not None:
        true_sp.pos_d = sp.pos_d + alt_error_m
    if offset_ne is not None and sp.pos_ne is not None:
        true_sp.pos_ne = (sp.pos_ne[0] - offset_ne[0], sp.pos_ne[1] - offset_ne[1])
    return true_sp

"""The state estimate: what the vehicle knows of itself, and the sensor samples it is made of.

The estimate is ideal, as a perfect EKF would be (the sim's own state), except its height, which
is the barometer's, as ArduCopter's EKF takes it: a drifting barometer moves the estimate, and
the vehicle holds the height it believes in while truly sinking or climbing. With the source
set's POSXY 6 (EK3_SRC1_POSXY unless another set is chosen) the horizontal position is external
navigation's instead (external_nav.py), with its error; with its POSZ 6 the height too.
GPS1_TYPE 0 (read at boot) is no GPS at all. The GPS, barometer and downward temperature sensor
are sampled here at fixed sim rates, never when telemetry asks, so what a client requests cannot
change a noise stream. The battery is read as a perfect monitor reads it.

While dead-reckoning, a position a client gives (MAV_CMD_EXTERNAL_POSITION_ESTIMATE) becomes the
estimate's at once, whatever it is, as EKF3's setLatLng resets it: Firefly holds the error that
leaves (`told_offset_ne`) until a position source is fused again. Measured on ArduCopter SITL: it
is refused while a position was fused within POSITION_FUSED_RECENTLY_S, once the EKF stops aiding
(AIDING_STOPS_S after the last), and without an origin; it keeps neither the position trusted nor
the EKF failsafe away. What a fix back then does depends on the told accuracy (_fix_after_told).
"""
from __future__ import annotations

import math

from firefly.sim.battery import remaining_fraction
from firefly.sim.physics import specific_force_body
from firefly.sim.sensors import NO_FIX, GpsReading

from .external_nav import GATE_SIGMAS, SOURCE_EXTNAV, SOURCE_NONE, ExternalNav
from .params import ParamStore
from .startup import Startup
from firefly.sim.rigid_body import euler_from_quaternion, ned_to_body

GPS_RATE_HZ = 10  # GPS and barometer samples
# The earth's magnetic field the compass reads (NED, milligauss): as ArduCopter SITL reports it at
# its default home (-35.36, 149.17). Firefly does not model how the field changes from place to place.
EARTH_FIELD_NED_MGAUSS = (232.0, 52.0, -528.0)
TEMPERATURE_RATE_HZ = 10
# ArduCopter's EKF3 dead-reckons after its last GPS position: only once none has come for this
# long (posRetryTimeNoVel_ms, no other velocity source) does it time the position out. Measured on
# ArduCopter SITL: SIM_GPS1_ENABLE 0 in a hover, then the EKF failsafe's LAND 8 s later (7 s here,
# then its check's 1 s).
DEAD_RECKONING_S = 7.0
# EKF3's deadReckonDeclare_ms: a told position is refused while a position was fused this recently
POSITION_FUSED_RECENTLY_S = 1.0
# EKF3's tiltDriftTimeMax_ms: this long after the last position fused it stops aiding ("stopped
# aiding" measured 15.0-15.2 s after SIM_GPS1_ENABLE 0), and a told position is refused from then on
AIDING_STOPS_S = 15.0
# A fix back after a told position: within EKF3's gate (GATE_SIGMAS standard deviations of the
# told position, its accuracy but at least EK3_POSNE_M_NSE's POSNE_NOISE_M, and what the dead
# reckoning and the fix add, DEAD_RECKONING_VARIANCE_M2) it is fused; past it, held off until this
# long after the last fix, then the estimate resets to it (measured: 20 m off, the GPS back 4.5 s
# after it was lost, reset 10.2 s after the loss). The added variance is fitted to the measured
# 1 m accurate positions: a fix 8 m off fused, one 20 m off held off (0.28 to 7 m^2 fit both).
GPS_GLITCH_RESET_S = 10.0
POSNE_NOISE_M = 0.5
DEAD_RECKONING_VARIANCE_M2 = 1.0
GLITCH_RADIUS_M = 25.0  # EK3_GLITCH_RAD's default: a told variance past it resets to the fix at once
TOLD_DELAY_MAX_S = 5.0  # EKF3 takes a told position's time stamp no older than this
EXTNAV_HEIGHT_FRESH_S = 0.5  # EKF3's extNavDataIsFresh: an older pose's height gives way to the barometer's


NO_GPS = 0  # GPS_FIX_TYPE_NO_GPS: GPS1_TYPE 0, no receiver
GPS_TYPE_NONE, GPS_TYPE_MAVLINK = 0, 14  # GPS1_TYPE: none, a companion's GPS_INPUT
# A companion's fix (GPS1_TYPE 14) is the receiver's reading until it is this old; then the
# receiver reports no fix (AP_GPS's driver timeout; measured on ArduCopter SITL: fix type 1 and 0
# satellites 4.2 s after the last GPS_INPUT)
GPS_INPUT_TIMEOUT_S = 4.0


class StateEstimate:
    def __init__(self, sim, physics_hz: int, startup: Startup, params: ParamStore):
        self.sim = sim
        self.startup = startup
        self.params = params
        gps_type = int(params["GPS1_TYPE"])  # read at boot, as AP_GPS
        self.gps_fitted = gps_type != GPS_TYPE_NONE
        self.gps_from_mavlink = gps_type == GPS_TYPE_MAVLINK
        self.gps_input: tuple[float, GpsReading] | None = None  # (sim time, reading) of the last GPS_INPUT
        self.external_nav = ExternalNav(params)
        # The horizontal error external navigation gives the estimate (north, east), None while
        # the GPS is the source: the common case costs one test
        self.nav_offset_ne: tuple[float, float] | None = None
        # The horizontal error a told position left the dead-reckoned estimate with (None: none)
        self.told_offset_ne: tuple[float, float] | None = None
        # How far the horizontal estimate is off the truth, whatever made it so (None: it is not)
        self.position_offset_ne: tuple[float, float] | None = None
        self.told_variance_m2 = 0.0  # the told position's, north or east, as the EKF took it
        self.gps_held_off = False  # a fix back, rejected as a glitch against a told position
        self.posxy_source = self.posz_source = 0
        self.source_set = 1  # EK3_SRCn_*'s n in use (MAV_CMD_SET_EKF_SOURCE_SET)
        self.no_source_since_s = -math.inf  # switched to no horizontal position source then
        self.follow_sources()
        self.battery_reset_mah: float | None = None  # the monitor's count less the pack's, after a reset
        self.gps_every = max(1, physics_hz // GPS_RATE_HZ)  # physics steps between GPS samples
        self.temperature_every = max(1, physics_hz // TEMPERATURE_RATE_HZ)
        self.gps = self._gps_reading()  # a realistic start-up's first tick has no fix either
        self.baro_alt_m = 0.0  # the barometer's last sample (altitude above the origin)
        self.temperature = (0.0, math.nan)  # (sim time of the sample, degrees C)
        self.alt_error_m = 0.0  # how far the barometer, and so the height estimate, reads high
        self.last_fix_s = -math.inf  # sim time of the last GPS sample with a fix in use
        self.origin_set_by_message = False  # SET_GPS_GLOBAL_ORIGIN gave the EKF its origin

    # ----- sampling, called by the vehicle loop ------------------------------------------------
    def sample_gps(self) -> tuple[float, float] | None:
        """The GPS and barometer samples; the jump (north, east) of the estimate when a fix puts
        an end to a told position's error, else None."""
        sim = self.sim
        self.gps = self._gps_reading()
        self.baro_alt_m = sim.baro.altitude_m(sim.state.body, sim.time_s)
        if self.gps.fix_type >= 3 and self.startup.gps_in_use(sim.time_s):
            told = self.told_offset_ne
            if told is not None and self.posxy_source != SOURCE_NONE:
                return self._fix_after_told(told, sim.time_s)
            self.last_fix_s = sim.time_s
        return None

    def _fix_after_told(self, told: tuple[float, float], now: float) -> tuple[float, float] | None:
        """A fix after a told position, as EKF3 takes one (measured in a GUIDED hover): the
        estimate resets to it (returned: the jump, which the point held follows) when the position
        had timed out (DEAD_RECKONING_S), or the told position's variance is past the glitch
        radius (accuracy 30 m); within the gate it is fused, and the vehicle flies the told error
        (accuracy 1 m, 8 m off; 5 m, 20 m off); further off it is a glitch, held off until
        GPS_GLITCH_RESET_S after the last fix, then reset to (1 m, 20 m off)."""
        b, gps = self.sim.state.body, self.gps
        since = now - self.last_fix_s
        reset = True
        if self.gps_held_off:
            if since < GPS_GLITCH_RESET_S:
                return None
        elif since <= DEAD_RECKONING_S and 2.0 * self.told_variance_m2 <= GLITCH_RADIUS_M ** 2:
            gate = GATE_SIGMAS * math.sqrt(2.0 * (self.told_variance_m2 + DEAD_RECKONING_VARIANCE_M2))
            if math.hypot(gps.n_m - b.n_m - told[0], gps.e_m - b.e_m - told[1]) > gate:
                self.gps_held_off = True
                return None
            reset = False  # fused: the point held stays where it was in the local frame
        self.told_offset_ne = None
        self._offsets_changed()
        self.last_fix_s = now
        return (-told[0], -told[1]) if reset else None

    def _gps_reading(self):
        gps = self.sim.gps.read(self.sim.state.body, self.sim.time_s)
        if not self.gps_fitted:
            return gps._replace(satellites=0, fix_type=NO_GPS)
        if self.gps_from_mavlink:  # the companion's fix while it comes, else none
            given = self.gps_input
            if given is None:  # (ArduCopter: no fix, once its driver is up, 10 s after boot)
                return gps._replace(satellites=0, fix_type=NO_FIX)
            if self.sim.time_s - given[0] > GPS_INPUT_TIMEOUT_S:
                return given[1]._replace(satellites=0, fix_type=NO_FIX)
            return given[1]
        if not self.startup.gps_powered_up(self.sim.time_s):  # still acquiring: no fix, no satellites
            gps = gps._replace(satellites=0, fix_type=0)
        return gps

    @property
    def gps_detected(self) -> bool:
        """A receiver is there: fitted, and a companion's once it has sent its first GPS_INPUT."""
        return self.gps_fitted and (not self.gps_from_mavlink or self.gps_input is not None)

    def take_gps_input(self, reading: GpsReading) -> bool:
        """A companion's GPS_INPUT (GPS1_TYPE 14), in the sim's frame; whether it is the first."""
        first = self.gps_input is None
        self.gps_input = (self.sim.time_s, reading)
        return first

    # ----- external navigation ---------------------------------------------------------------

    def external_pose(self, frame_origin_ned: tuple[float, float, float], xyz: tuple[float, float, float],
                      quality: int, reset_counter: int) -> None:
        """A companion's pose, xyz in its frame, which starts at frame_origin_ned of the sim's:
        fused by the sensor, and taken by the estimate when it is the source."""
        ext = self.external_nav
        b = self.sim.state.body
        if ext.pose(self.sim.time_s, frame_origin_ned, xyz, (b.n_m, b.e_m, b.d_m), quality, reset_counter):
            self.follow_sources()

    def use_source_set(self, n: int) -> None:
        """EK3_SRCn_* become the sources (1..3)."""
        self.source_set = n
        self.follow_sources()

    def follow_sources(self) -> None:
        """The set in use's POSXY and POSZ as they are now (called when EK3_SRC* change, and on
        each pose), and the horizontal error from external navigation while it is the source.
        Switched onto a source, the estimate resets to it (onto external navigation, to its last
        pose); switched to no source, it keeps the error it had (dead reckoning from there)."""
        p = self.params
        was = self.posxy_source
        n = self.source_set
        self.posxy_source = int(p[f"EK3_SRC{n}_POSXY"])
        self.posz_source = int(p[f"EK3_SRC{n}_POSZ"])
        ext = self.external_nav
        if self.posxy_source == SOURCE_NONE:
            if was != SOURCE_NONE:  # dead-reckoned from here, from where the estimate was
                self.no_source_since_s = self.sim.time_s
        else:
            if self.posxy_source != was:
                self.told_offset_ne = None
            if self.posxy_source == SOURCE_EXTNAV and was != SOURCE_EXTNAV:
                ext.take_latest(self.sim.time_s)
            uses = ext.poses > 0 and self.posxy_source == SOURCE_EXTNAV
            self.nav_offset_ne = ext.offset_ned[:2] if uses else None
        self._offsets_changed()

    # ----- a position told (MAV_CMD_EXTERNAL_POSITION_ESTIMATE) --------------------------------
    def last_position_s(self) -> float:
        """When the EKF last fused a horizontal position: the pose's while external navigation is
        the source, the switch's to no source, else the GPS fix's."""
        if self.posxy_source == SOURCE_EXTNAV:
            return self.external_nav.fused_s
        if self.posxy_source == SOURCE_NONE:
            return self.no_source_since_s
        return self.last_fix_s

    def has_origin(self) -> bool:
        """Whether the EKF has ever had an origin (from the message or a first fix): once set, it stays."""
        return self.origin_set_by_message or self.last_fix_s > -math.inf

    def aiding(self) -> bool:
        """Whether the EKF still aids its position (a position fused within AIDING_STOPS_S)."""
        return self.sim.time_s - self.last_position_s() <= AIDING_STOPS_S

    def takes_told_position(self) -> bool:
        """Whether a told position would be taken now: with an origin, while dead-reckoning
        (no position fused for POSITION_FUSED_RECENTLY_S) and still aiding (AIDING_STOPS_S)."""
        since = self.sim.time_s - self.last_position_s()
        return POSITION_FUSED_RECENTLY_S <= since <= AIDING_STOPS_S and self.has_origin()

    def take_told_position(self, n_m: float, e_m: float, age_s: float, accuracy_m: float) -> None:
        """The estimate jumps to (n_m, e_m) of the sim's frame as it was age_s ago (0 to
        TOLD_DELAY_MAX_S), moved on by the velocity since, as EKF3 corrects a delayed one. Its
        accuracy (NaN, or under POSNE_NOISE_M: that) decides what a returning fix does."""
        b = self.sim.state.body
        off = (n_m + b.vn_m_s * age_s - b.n_m, e_m + b.ve_m_s * age_s - b.e_m)
        if self.posxy_source == SOURCE_EXTNAV and self.nav_offset_ne is not None:
            ext = self.external_nav  # the pose's gate then measures the next poses against it
            ext.offset_ned = (*off, ext.offset_ned[2])
            ext.rejected_since = None
            self.nav_offset_ne = off
        else:
            self.told_offset_ne = off
        accuracy_m = POSNE_NOISE_M if math.isnan(accuracy_m) else max(accuracy_m, POSNE_NOISE_M)
        self.told_variance_m2 = accuracy_m * accuracy_m  # (inf past 1e154, never an OverflowError)
        self.gps_held_off = False
        self._offsets_changed()

    def _offsets_changed(self) -> None:
        told = self.told_offset_ne
        self.position_offset_ne = told if told is not None else self.nav_offset_ne

    def sample_temperature(self, home_d_m: float) -> None:
        self.temperature = (self.sim.time_s, self.sim.read_temperature(home_d_m))

    def track_barometer(self) -> None:
        """Follow the barometer's error into the height estimate (at the flight-mode rate), or
        external navigation's while it is the height source and fresh."""
        ext = self.external_nav
        if ext.poses and self.posz_source == SOURCE_EXTNAV and self.sim.time_s - ext.heard_s < EXTNAV_HEIGHT_FRESH_S:
            self.alt_error_m = -ext.offset_ned[2]
            return
        baro = self.sim.baro
        self.alt_error_m = baro.error_m(self.sim.time_s) if baro.drift_m_s else 0.0

    # ----- what the vehicle believes ---------------------------------------------------------
    @property
    def body(self):
        """Position, velocity, attitude quaternion and rates (sim.rigid_body.BodyState)."""
        b = self.sim.state.body
        off = self.position_offset_ne
        if off is not None:
            return b._replace(n_m=b.n_m + off[0], e_m=b.e_m + off[1], d_m=b.d_m - self.alt_error_m)
        return b._replace(d_m=b.d_m - self.alt_error_m) if self.alt_error_m else b

    @property
    def attitude(self) -> tuple:
        """(roll, pitch, yaw) in radians."""
        b = self.sim.state.body
        return euler_from_quaternion(b.qw, b.qx, b.qy, b.qz)

    def has_position(self) -> bool:
        """Whether the horizontal position is known: with a 3D GPS fix the EKF uses, and for
        DEAD_RECKONING_S after the last one."""
        now = self.sim.time_s
        if self.posxy_source == SOURCE_NONE:  # no source (a source set left at its defaults)
            return now - self.no_source_since_s <= DEAD_RECKONING_S
        if self.nav_offset_ne is not None:  # external navigation is the source (no origin needed)
            ext = self.external_nav
            return not ext.lost and now - ext.measured_s <= DEAD_RECKONING_S
        if self.gps.fix_type >= 3 and self.startup.gps_in_use(now):
            return True
        return now - self.last_fix_s <= DEAD_RECKONING_S

    def local_position_known(self) -> bool:
        """Whether the EKF has a position in its local frame to report (LOCAL_POSITION_NED): with
        no GPS fitted, or external navigation the source, only once a pose has been fused; with a
        companion's GPS (GPS1_TYPE 14), once its first GPS_INPUT came, whatever its fix
        (ArduCopter SITL sent none before its EKF had the companion's fix, a few seconds later)."""
        if self.gps_fitted and self.posxy_source != SOURCE_EXTNAV:
            return not self.gps_from_mavlink or self.gps_input is not None
        return self.external_nav.poses > 0

    def origin_known(self) -> bool:
        """Whether the EKF has an origin (set from a 3D fix), so home can be set."""
        return self.origin_set_by_message or (self.gps.fix_type >= 3 and self.startup.origin_set(self.sim.time_s))

    def attitude_known(self) -> bool:
        """Whether the EKF has aligned its attitude (false only during a realistic start-up)."""
        return self.startup.attitude_known(self.sim.time_s)

    @property
    def battery(self):
        """The pack as a perfect monitor reads it: voltage_v, current_a, consumed_mah (counted
        from the last BATTERY_RESET, as ArduPilot's monitor counts it; the pack itself is not
        changed by a reset)."""
        pack = self.sim.battery
        if self.battery_reset_mah is None:
            return pack
        return pack._replace(consumed_mah=pack.consumed_mah + self.battery_reset_mah)

    @property
    def battery_remaining(self) -> float:
        """Remaining charge, 0..1."""
        if self.battery_reset_mah is None:
            return self.sim.battery_remaining
        return remaining_fraction(self.battery, self.sim.airframe.battery_capacity_mah)

    def reset_battery(self, percentage: float) -> None:
        """MAV_CMD_BATTERY_RESET: the monitor counts as if `percentage` of the pack were left
        (0..100), as AP_BattMonitor's reset_remaining sets its consumed charge."""
        capacity = self.sim.airframe.battery_capacity_mah
        left = min(max(percentage, 0.0), 100.0) / 100.0
        self.battery_reset_mah = (1.0 - left) * capacity - self.sim.battery.consumed_mah

    # ----- the inertial sensors and the air, as telemetry reports them -----------------------
    @property
    def accel_body(self) -> tuple:
        """What the accelerometer reads (FRD, m/s^2): noise-free, as the rest of the estimate."""
        sim = self.sim
        force = specific_force_body(sim.state, sim.airframe, sim.wind_ned)
        push = sim.shove_accel_frd
        if push is not None:
            force = (force[0] + push[0], force[1] + push[1], force[2] + push[2])
        payloads = sim.payload_accel_ned  # a parachute's drag, a load's weight: felt as any other force
        if payloads is not None:
            extra = ned_to_body(sim.state.body, payloads)
            force = (force[0] + extra[0], force[1] + extra[1], force[2] + extra[2])
        return force

    @property
    def mag_body_mgauss(self) -> tuple:
        return ned_to_body(self.sim.state.body, EARTH_FIELD_NED_MGAUSS)

    @property
    def wind_ned(self) -> tuple:
        """The wind the vehicle flies in (NED velocity of the air, m/s), known as a converged
        wind estimate would know it."""
        return self.sim.wind_ned

    @property
    def true_body(self):
        """The simulator's own state, not the estimate (for SIMSTATE, which reports exactly that)."""
        return self.sim.state.body

    @property
    def motor_speeds_rad_s(self) -> tuple:
        return self.sim.state.omega_rad_s

"""Parameters: the table of those that act, the full set served, and a store that persists them.

PARAM_TABLE holds the parameters Firefly models (each acts on the vehicle), with ArduCopter's
names, units and ranges. Over MAVLink the vehicle serves exactly the reference ArduCopter's set
(autopilot/reference_params.py), in its order and with its MAVLink types, then Firefly's own link
faults; one that Firefly does not model is stored, persisted and reported, and does nothing.
ArduPilot 4.5's names of parameters 4.7 renamed stay known in-process only (scenarios, scripts,
the Python API, older saved files), as ArduPilot converts them when it loads old storage.
Where the two tables disagree is written down in autopilot/params_differences.py.

Values follow ArduCopter's units (cm, cm/s, centidegrees) so that ground stations show what they
expect; the controller converts at construction. Integers are sent by value in the float field,
as ArduPilot does.

SIM_* parameters inject faults into the simulated world (autopilot/faults/world.py), with ArduPilot
SITL's names where it has one. Unlike ArduPilot's they are never saved: a run's faults come from
its scenario and from what is set during the run, so a restart does not bring back a failed motor.
"""
from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

from .io.persist import JsonFile, read_json
from .params_differences import FIREFLY_ONLY, OLD_NAMES
from .reference_params import reference_params

# MAV_PARAM_TYPE numbers ArduPilot uses (INT8, INT16, INT32, REAL32), and what each integer type holds.
MAV_PARAM_TYPE_INT8, MAV_PARAM_TYPE_INT16, MAV_PARAM_TYPE_INT32, MAV_PARAM_TYPE_REAL32 = 2, 4, 6, 9
INT_TYPE_BOUNDS = {2: (-2.0**7, 2.0**7 - 1), 4: (-2.0**15, 2.0**15 - 1), 6: (-2.0**31, 2.0**31 - 1)}
FLOAT32_MAX = 3.4028234663852886e38  # a PARAM_VALUE carries a float32


# Values counted from what is stored elsewhere at every start, never saved themselves (MIS_TOTAL:
# the mission's length, home included, kept by the mission service).
COUNTED = frozenset({"MIS_TOTAL"})


def is_saved(name: str) -> bool:
    """Whether a value persists across restarts: everything but the simulation's faults (SIM_*)
    and the counted values."""
    return not name.startswith("SIM_") and name not in COUNTED


@dataclass(frozen=True)
class ParamSpec:
    name: str
    default: float
    low: float
    high: float
    is_int: bool = False
    doc: str = ""
    mav_type: int | None = None  # MAV_PARAM_TYPE served; filled in for SERVED (see _served_spec)

    @property
    def saved(self) -> bool:
        return is_saved(self.name)


def _f(name, default, low, high, doc=""):
    return ParamSpec(name, float(default), float(low), float(high), False, doc)


def _i(name, default, low, high, doc=""):
    return ParamSpec(name, float(default), float(low), float(high), True, doc)


def _i8(name, default, low=-128, high=127, doc=""):
    """An integer ArduPilot keeps in an int8 (served as MAV_PARAM_TYPE_INT8 where the reference's
    set does not list it)."""
    return ParamSpec(name, float(default), float(low), float(high), True, doc, MAV_PARAM_TYPE_INT8)


PARAM_TABLE: tuple[ParamSpec, ...] = (
    # Identity
    _i("MAV_SYSID", 1, 1, 255, "MAVLink system id of this vehicle"),
    _i("FRAME_CLASS", 1, 0, 15, "1 = quad"),
    _i("FRAME_TYPE", 0, 0, 18, "0 = plus"),
    # Position controller (ArduCopter AC_PosControl)
    _f("PSC_POSXY_P", 1.0, 0.5, 2.0, "horizontal position error to velocity [1/s]"),
    _f("PSC_VELXY_P", 2.0, 0.1, 6.0, "horizontal velocity error to acceleration [1/s]"),
    _f("PSC_VELXY_I", 1.0, 0.02, 1.0, "horizontal velocity integrator"),
    _f("PSC_VELXY_D", 0.5, 0.0, 1.0, "horizontal velocity derivative"),
    _f("PSC_VELXY_FLTD", 5.0, 0.0, 100.0, "its filter [Hz] on a shaped trajectory's error, 0 = none"),
    _f("PSC_VELXY_IMAX", 1000, 0, 4500, "horizontal integrator limit [cm/s/s]"),
    _f("PSC_POSZ_P", 1.0, 1.0, 3.0, "vertical position error to climb rate [1/s]"),
    _f("PSC_VELZ_P", 5.0, 1.0, 8.0, "climb rate error to acceleration [1/s]"),
    _f("PSC_VELZ_I", 0.5, 0.02, 1.0, "climb rate integrator"),
    _f("PSC_VELZ_IMAX", 1000, 1, 1000, "vertical integrator limit [cm/s/s]"),
    _f("PSC_ACCZ_P", 0.5, 0.2, 1.5, "vertical acceleration error to thrust"),
    _f("PSC_ACCZ_I", 1.0, 0.0, 3.0, "vertical acceleration integrator"),
    # Attitude controller (ArduCopter AC_AttitudeControl)
    _f("ATC_ANG_RLL_P", 4.5, 3.0, 12.0, "roll angle error to rate [1/s]"),
    _f("ATC_ANG_PIT_P", 4.5, 3.0, 12.0, "pitch angle error to rate [1/s]"),
    _f("ATC_ANG_YAW_P", 4.5, 3.0, 12.0, "yaw angle error to rate [1/s]"),
    _f("ATC_RAT_RLL_P", 0.135, 0.01, 0.5), _f("ATC_RAT_RLL_I", 0.135, 0.01, 2.0),
    _f("ATC_RAT_RLL_D", 0.0036, 0.0, 0.05), _f("ATC_RAT_RLL_IMAX", 0.5, 0.0, 1.0),
    _f("ATC_RAT_PIT_P", 0.135, 0.01, 0.5), _f("ATC_RAT_PIT_I", 0.135, 0.01, 2.0),
    _f("ATC_RAT_PIT_D", 0.0036, 0.0, 0.05), _f("ATC_RAT_PIT_IMAX", 0.5, 0.0, 1.0),
    # Yaw: this airframe's reaction torque is small (c = d/b = 2.4 cm), so ArduPilot's 0.18 would
    # give a yaw-rate loop slower than the angle loop; 1.0 puts it near 8 rad/s.
    _f("ATC_RAT_YAW_P", 1.0, 0.1, 2.5), _f("ATC_RAT_YAW_I", 0.1, 0.01, 1.0),
    _f("ATC_RAT_YAW_D", 0.0, 0.0, 0.02), _f("ATC_RAT_YAW_IMAX", 0.5, 0.0, 1.0),
    _f("ANGLE_MAX", 3000, 1000, 8000, "maximum lean angle [cdeg]"),
    _f("ATC_RATE_R_MAX", 0, 0, 1080, "roll rate limit [deg/s], 0 = 360"),
    _f("ATC_RATE_Y_MAX", 0, 0, 1080, "yaw rate limit [deg/s], 0 = 90"),
    _f("PILOT_Y_RATE", 202.5, 1, 500, "pilot yaw rate at full stick [deg/s]"),
    # Navigation
    _f("WPNAV_SPEED", 1000, 20, 2000, "horizontal speed in AUTO/GUIDED [cm/s]"),
    _f("WPNAV_SPEED_UP", 250, 10, 1000, "climb speed [cm/s]"),
    _f("WPNAV_SPEED_DN", 150, 10, 500, "descent speed [cm/s]"),
    _f("WPNAV_ACCEL", 250, 50, 500, "horizontal acceleration [cm/s/s]"),
    _f("WPNAV_RADIUS", 200, 5, 1000, "waypoint radius [cm]"),
    _i("WP_YAW_BEHAVIOR", 2, 0, 3, "AUTO/GUIDED/RTL heading: 0 hold, 1 face the way, 2 not in RTL, 3 course"),
    _f("WPNAV_ACCEL_Z", 100, 50, 500, "vertical acceleration of waypoint legs [cm/s/s]"),
    _f("WPNAV_ACCEL_C", 0, 0, 500, "cornering acceleration [cm/s/s], 0 = 2 x WPNAV_ACCEL"),
    _f("WPNAV_JERK", 1, 1, 20, "jerk limit of waypoint legs [m/s/s/s]"),
    _f("GUID_TIMEOUT", 3, 0.1, 5, "GUIDED stops when velocity/acceleration/attitude targets stop for [s]"),
    _i("GUID_OPTIONS", 0, 0, 255, "GUIDED options: bit 3 SET_ATTITUDE_TARGET's thrust is thrust"),
    _f("LOIT_SPEED", 1250, 20, 3500, "loiter max speed [cm/s]"),
    _f("PILOT_SPEED_UP", 250, 50, 500, "pilot climb rate [cm/s]"),
    _f("PILOT_SPEED_DN", 0, 0, 500, "pilot descent rate [cm/s], 0 = PILOT_SPEED_UP"),
    _f("PILOT_TKOFF_ALT", 0, 0, 1000, "pilot takeoff altitude [cm]"),
    _f("TKOFF_SLEW_TIME", 2.0, 0.25, 5, "a pilot takeoff's throttle slew from zero to full [s]"),
    _f("TKOFF_THR_MAX", 0.9, 0, 0.9, "the throttle at which a pilot takeoff leaves the ground"),
    _f("LAND_SPEED", 50, 30, 200, "final descent speed [cm/s]"),
    _f("LAND_SPEED_HIGH", 0, 0, 2500, "descent speed above LAND_ALT_LOW [cm/s], 0 = WPNAV_SPEED_DN"),
    _f("LAND_ALT_LOW", 1000, 100, 10000, "altitude below which LAND_SPEED applies [cm]"),
    _f("RTL_ALT", 1500, 200, 300000, "RTL return altitude [cm]"),
    _f("RTL_ALT_FINAL", 0, 0, 1000, "RTL final altitude [cm], 0 = land"),
    _f("RTL_SPEED", 0, 0, 2000, "RTL speed [cm/s], 0 = WPNAV_SPEED"),
    _f("RTL_LOIT_TIME", 5000, 0, 60000, "RTL loiter over home before descending [ms]"),
    _f("RTL_CLIMB_MIN", 0, 0, 3000, "RTL minimum climb [cm]"),
    _f("RTL_CONE_SLOPE", 3.0, 0, 10, "RTL climbs at most this times the distance home, below 0.5 = no cone"),
    _i("RTL_ALT_TYPE", 0, 0, 1, "RTL's return altitude: 0 above home, 1 above terrain"),
    _f("DISARM_DELAY", 10, 0, 127, "auto-disarm on the ground after [s], 0 = never"),
    _f("MOT_SPIN_ARM", 0.10, 0.0, 0.2, "motor output when armed, throttle zero"),
    _f("MOT_THST_HOVER", 0.35, 0.125, 0.6875, "hover throttle (learned)"),
    # Arming
    _i("ARMING_CHECK", 1, 0, 0x7FFFF, "pre-arm checks bitmask, 0 = none"),
    # Failsafes
    _i("FS_THR_ENABLE", 1, 0, 7, "radio failsafe action: 1 RTL, 3 LAND, ... (SIM_RC_FAIL loses the radio)"),
    _i("FS_THR_VALUE", 975, 910, 1100, "throttle PWM below which the radio is lost [us]"),
    _f("RC_FS_TIMEOUT", 1.0, 0.5, 10, "seconds without RC frames before the radio failsafe"),
    _i("FS_OPTIONS", 16, 0, 0x7FFFFFFF, "failsafe options: bit 0 continue AUTO, 2 continue GUIDED, "
                                      "3 continue landing on a radio failsafe"),
    _i("FS_GCS_ENABLE", 0, 0, 7), _f("FS_GCS_TIMEOUT", 5, 2, 120),
    _i("BATT_FS_LOW_ACT", 0, 0, 6), _i("BATT_FS_CRT_ACT", 0, 0, 7, "critical battery action (as BATT_FS_LOW_ACT)"),
    _f("BATT_LOW_VOLT", 10.5, 0, 120), _f("BATT_CRT_VOLT", 0, 0, 120),
    _i("BATT_LOW_TIMER", 10, 0, 120, "seconds a voltage must stay below BATT_LOW/CRT_VOLT to count, 0 = never"),
    _f("BATT_LOW_MAH", 0, 0, 500000), _f("BATT_CRT_MAH", 0, 0, 500000),
    _f("BATT_CAPACITY", 5000, 0, 500000, "battery capacity [mAh]"),
    _i("FENCE_ENABLE", 0, 0, 1), _i("FENCE_TYPE", 7, 0, 15), _i("FENCE_ACTION", 1, 0, 5),
    _f("FENCE_ALT_MAX", 100, 10, 1000), _f("FENCE_RADIUS", 300, 30, 10000),
    _i("FS_EKF_ACTION", 1, 1, 3, "EKF failsafe: 1 LAND, 2 ALT_HOLD, 3 LAND even in STABILIZE"),
    _f("FS_EKF_THRESH", 0.8, 0, 1, "EKF failsafe variance threshold, 0 = no EKF failsafe"),
    # Telemetry stream rates of the first link (Hz; ArduPilot 4.5 named them SR0_*; Firefly streams unasked)
    _i("MAV1_RAW_SENS", 2, 0, 50), _i("MAV1_EXT_STAT", 2, 0, 50), _i("MAV1_POSITION", 4, 0, 50), _i("MAV1_EXTRA1", 10, 0, 50),
    _i("MAV1_EXTRA2", 4, 0, 50), _i("MAV1_EXTRA3", 2, 0, 50),
    _i("MAV1_RC_CHAN", 0, 0, 50, "RC_CHANNELS and SERVO_OUTPUT_RAW: not streamed unasked"),
    # Simulation faults (ArduPilot SITL's SIM_ names; SIM_GPS_DISABLE is 4.5's, SIM_LINK_* are Firefly's own)
    _i("SIM_ENGINE_FAIL", 0, 0, 2**31 - 1, "mask of the motor outputs SIM_ENGINE_MUL scales (bit 0 = output 1), 0 = none"),
    _f("SIM_ENGINE_MUL", 0, 0, 1, "PWM multiplier of the motors in SIM_ENGINE_FAIL, 0 = failed"),
    _i("SIM_GPS_DISABLE", 0, 0, 1, "1 = the GPS has no fix"),
    _i("SIM_GPS1_ENABLE", 1, 0, 1, "0 = the GPS has no fix (ArduPilot 4.7's inverse of SIM_GPS_DISABLE)"),
    _f("SIM_GPS1_GLTCH_X", 0, -1, 1, "GPS latitude offset [deg]"),
    _f("SIM_GPS1_GLTCH_Y", 0, -1, 1, "GPS longitude offset [deg]"),
    _f("SIM_GPS1_GLTCH_Z", 0, -1000, 1000, "GPS altitude offset [m]"),
    _i("SIM_GPS1_NUMSATS", 10, 0, 40, "satellites the GPS reports (the fix does not depend on them, as in SITL)"),
    _f("SIM_BARO_DRIFT", 0, -10, 10, "barometer altitude drift [m/s], 0 = none"),
    _f("SIM_WIND_SPD", 0, 0, 100, "mean wind speed [m/s], from the scenario's [wind]"),
    _f("SIM_WIND_DIR", 0, 0, 360, "direction the wind blows from [deg], from the scenario's [wind]"),
    _f("SIM_WIND_TURB", 0, 0, 20, "turbulence, standard deviation per axis [m/s]"),
    _f("SIM_WIND_TC", 5, 0, 120, "time over which a wind change takes effect [s]"),
    # (no ranges, as ArduPilot's: any value is taken; sim/wind.py keeps the wind it makes physical)
    _i8("SIM_WIND_T", 0, doc="how the wind weakens near the ground: 0 square root, 1 none, 2 linear"),
    _f("SIM_WIND_T_ALT", 60, -FLOAT32_MAX, FLOAT32_MAX, "height from which the wind blows whole [m]"),
    _f("SIM_WIND_T_COEF", 0.01, -FLOAT32_MAX, FLOAT32_MAX, "linear profile: less this much a metre below SIM_WIND_T_ALT"),
    _i("SIM_RC_FAIL", 0, 0, 2, "RC receiver: 1 no frames, 2 throttle at 950 us"),
    _f("SIM_BATT_VOLTAGE", 12.6, 0, 100, "battery resting voltage [V]; setting it re-initialises the charge"),
    _f("SIM_LINK_DOWN", 0, 0, 3600, "ground-station link cut for this many wall seconds, then 0"),
    _f("SIM_LINK_LOSS", 0, 0, 100, "share of MAVLink frames lost each way [%]"),
    # Other air traffic (sim/traffic.py, adsb/sitl_transceiver.py), as ArduPilot SITL's SIM_ADSB_*
    _i("SIM_ADSB_COUNT", -1, -1, 32767, "simulated aircraft; -1: no SITL transceiver (0 or more at boot attaches "
       "it, as ArduPilot's on SERIAL1); 200 or more: none"),
    _f("SIM_ADSB_RADIUS", 10000, 0, 1e6, "aircraft spawn this spread around the vehicle, and respawn farther [m]"),
    _f("SIM_ADSB_ALT", 1000, -1e5, 1e5, "aircraft spawn this high (its size) [m]"),
    _i("SIM_ADSB_TX", 0, 0, 1, "served, unread (SITL's transceiver health report)"),
    _i("SIM_ADSB_TYPES", 1, 0, 255, "bit 0: the transceiver reports as MAVLink ADSB_VEHICLE"),
    # SITL's precision-landing beacon (sim/precland.py), as SIM_PLD_*
    _i("SIM_PLD_ENABLE", 0, 0, 1, "1: the beacon reports the vehicle; 0: it stops reporting (its last health stands)"),
    _f("SIM_PLD_LAT", 0, -90, 90, "the beacon's latitude [deg], taken as a float32 as SITL takes it"),
    _f("SIM_PLD_LON", 0, -180, 180, "the beacon's longitude [deg], likewise"),
    _f("SIM_PLD_HEIGHT", 0, 0, 10000, "the beacon's height above the origin [m]"),
    _f("SIM_PLD_ALT_LMT", 15, 0, 100, "the beacon sees no higher than this above it [m]"),
    _f("SIM_PLD_DIST_LMT", 10, 5, 100, "nor farther than this sideways (type 0), in its cone (1), away (2) [m]"),
    _i("SIM_PLD_TYPE", 0, 0, 2, "0 cylinder, 1 cone, 2 sphere"),
    _i("SIM_PLD_OPTIONS", 0, 0, 1, "bit 0: the beacon gives its distance (no rangefinder needed)"),
    # SITL's optical flow camera (sim/optical_flow.py), as SIM_FLOW_*
    _i8("SIM_FLOW_ENABLE", 0, 0, 1, "1: the camera makes samples (read by FLOW_TYPE 10's driver)"),
    _i("SIM_FLOW_RATE", 10, 0, 800, "samples a second [Hz]"),
    _i8("SIM_FLOW_DELAY", 0, 0, 20, "the sample handed out is this many samples old"),
    _f("SIM_FLOW_RND", 0.05, 0, 1, "uniform noise within +- this on each flow rate [rad/s]"),
    *(_f(f"SIM_FLOW_POS_{axis}", 0, -5, 5, f"the camera's {axis} offset on the body [m]") for axis in "XYZ"),
    # SITL's parachute (payload/sitl_parachute.py), as SIM_PARA_*: fires once its pin reaches 1250 us
    _i8("SIM_PARA_ENABLE", 0, 0, 1, "1: a simulated parachute is fitted"),
    _i8("SIM_PARA_PIN", -1, -1, 16, "the output (1-16) that fires it; -1 none"),
    # SITL's servo gripper (payload/sitl_gripper.py), as SIM_GRPS_*: jaws that hold a 1 kg load
    _i8("SIM_GRPS_ENABLE", 0, 0, 1, "1: a simulated gripper is fitted"),
    _i8("SIM_GRPS_PIN", -1, -1, 16, "the output (1-16) that moves its jaws; -1 none"),
    replace(_i("SIM_GRPS_GRAB", 2000, 1000, 2000, "the PWM that shuts its jaws [us]"), mav_type=MAV_PARAM_TYPE_INT16),
    replace(_i("SIM_GRPS_RELEASE", 1000, 1000, 2000, "the PWM that opens them [us]"), mav_type=MAV_PARAM_TYPE_INT16),
    _i8("SIM_GRPS_REVERSE", 0, 0, 1, "1: the jaws move the other way"),
    # FOLLOW's lead (AP_Follow, follow_target.py): ArduCopter shows them once FOLL_ENABLE is 1
    _i("FOLL_SYSID", 0, 0, 255, "the lead's system id; 0 = the first other system heard"),
    _f("FOLL_DIST_MAX", 100, 0, 1000, "a lead farther than this is not followed [m]; 0 = no limit"),
    _i("FOLL_OFS_TYPE", 0, 0, 1, "offsets 0 north-east-down, 1 turned with the lead's heading"),
    *(_f(f"FOLL_OFS_{axis}", 0, -100, 100, f"offset {way} of the lead [m]")
      for axis, way in (("X", "north / forward"), ("Y", "east / right"), ("Z", "below"))),
    _i("FOLL_YAW_BEHAVE", 1, 0, 3, "heading: 0 kept, 1 face the lead, 2 the lead's, 3 along the flight"),
    _f("FOLL_POS_P", 0.1, 0, 1, "served; unread, as in ArduCopter 4.7"),
    _i("FOLL_ALT_TYPE", 1, 0, 1, "the lead's altitude: 0 above sea level, 1 above home"),
    _i("FOLL_OPTIONS", 0, 0, 1, "bit 0: the mount follows the lead (no mount: no effect)"),
    # the lead estimate's shaping limits: acceleration and jerk per axis (m and deg, per s^2 and s^3)
    *(spec for axis, accel, accel_high, jerk, jerk_high in (("NE", 2.5, 5, 5, 20), ("D", 2.5, 2.5, 5, 5),
                                                            ("H", 90, 90, 360, 360))
      for spec in (_f(f"FOLL_ACCEL_{axis}", accel, 0, accel_high), _f(f"FOLL_JERK_{axis}", jerk, 0, jerk_high))),
    # The camera (AP_Camera, payload/camera.py): ArduCopter shows CAM1_* but the type once CAM1_TYPE is set
    _i("CAM1_TYPE", 0, 0, 8, "0 none, 1 a servo output (SERVOn_FUNCTION 10), 2 a relay (RELAYn_FUNCTION 4), "
                              "6 a MAVLink camera v2 (the thermal camera, component 100); read at boot"),
    _f("CAM1_DURATION", 0.1, 0, 5, "seconds the shutter is held"),
    _i("CAM1_SERVO_ON", 1300, 1000, 2000, "trigger output while the shutter is held [us]"),
    _i("CAM1_SERVO_OFF", 1100, 1000, 2000, "trigger output otherwise [us]"),
    _f("CAM1_TRIGG_DIST", 0, 0, 1000, "a picture every this many metres moved, 0 = off"),
    _i("CAM1_RELAY_ON", 1, 0, 1, "the relay's state while the shutter is held"),
    _f("CAM1_INTRVAL_MIN", 0, 0, 10, "seconds at least between pictures; one asked for sooner waits"),
    _i("CAM1_FEEDBAK_PIN", -1, -1, 127, "served; SITL has no hot-shoe pin"),
    _i("CAM1_FEEDBAK_POL", 1, 0, 1, "served; SITL has no hot-shoe pin"),
    _i("CAM1_OPTIONS", 0, 0, 1, "served; bit 0 records video while armed (no video here)"),
    _i("CAM1_MNT_INST", 0, 0, 2, "served; no mount"),
    _f("CAM1_HFOV", 0, 0, 360, "served; field of view [deg], 0 unknown"),
    _f("CAM1_VFOV", 0, 0, 180, "served; field of view [deg], 0 unknown"),
    _i("CAM_AUTO_ONLY", 0, 0, 1, "1: distance triggering in AUTO only"),
    _i("CAM_MAX_ROLL", 0, 0, 180, "no distance-triggered picture while rolled beyond this [deg], 0 = any roll"),
    # The parachute (AP_Parachute, payload/parachute.py): ArduCopter shows CHUTE_* but CHUTE_ENABLED
    # once it is set, with these types and defaults (measured); each acts at once
    _i8("CHUTE_ENABLED", 0, 0, 1, "1: the parachute may be released (DO_PARACHUTE 0 / 1 set it)"),
    _i8("CHUTE_TYPE", 0, 0, 10, "the release: 0-3 a relay (RELAYn_FUNCTION 3), 10 a servo (SERVOn_FUNCTION 27)"),
    replace(_i("CHUTE_SERVO_ON", 1300, 1000, 2000, "the servo while released [us]"), mav_type=MAV_PARAM_TYPE_INT16),
    replace(_i("CHUTE_SERVO_OFF", 1100, 1000, 2000, "the servo otherwise [us]"), mav_type=MAV_PARAM_TYPE_INT16),
    replace(_i("CHUTE_ALT_MIN", 10, 0, 32000, "no release asked for below this height above home [m], 0 = any"),
            mav_type=MAV_PARAM_TYPE_INT16),
    replace(_i("CHUTE_DELAY_MS", 500, 0, 5000, "from the motors' stop to the release [ms]"),
            mav_type=MAV_PARAM_TYPE_INT16),
    _f("CHUTE_CRT_SINK", 0, 0, 15, "sinking faster than this for a second releases it [m/s], 0 = never"),
    replace(_i("CHUTE_OPTIONS", 0, 0, 3, "bit 0: held open for ever, bit 1: released without disarming"),
            mav_type=MAV_PARAM_TYPE_INT32),
    # The sprayer (AC_Sprayer, payload/sprayer.py): ArduCopter shows SPRAY_* but SPRAY_ENABLE once it is set
    _i8("SPRAY_ENABLE", 0, 0, 1, "1: DO_SPRAYER may switch the sprayer on"),
    _f("SPRAY_PUMP_RATE", 10, 0, 100, "the pump's share of its range per m/s of ground speed [%]"),
    replace(_i("SPRAY_SPINNER", 1300, 1000, 2000, "the spinner while spraying [us]"), mav_type=MAV_PARAM_TYPE_INT16),
    _f("SPRAY_SPEED_MIN", 100, 0, 1000, "sprays from this ground speed up [cm/s]"),
    _i8("SPRAY_PUMP_MIN", 0, 0, 100, "the pump's least share of its range while spraying [%]"),
    # The gripper (AP_Gripper, payload/gripper.py): ArduCopter shows GRIP_* but GRIP_ENABLE once it is
    # set, with these types and defaults (measured); GRIP_ENABLE and GRIP_TYPE make it at boot
    _i8("GRIP_ENABLE", 0, 0, 1, "1: DO_GRIPPER acts (read at boot with GRIP_TYPE, then it switches it)"),
    _i8("GRIP_TYPE", 0, 0, 2, "made at boot: 1 a servo (SERVOn_FUNCTION 28); 0 none, 2 an EPM (not modelled)"),
    replace(_i("GRIP_GRAB", 1900, 1000, 2000, "the servo grabbing [us]"), mav_type=MAV_PARAM_TYPE_INT16),
    replace(_i("GRIP_RELEASE", 1100, 1000, 2000, "the servo releasing [us]"), mav_type=MAV_PARAM_TYPE_INT16),
    replace(_i("GRIP_NEUTRAL", 1500, 0, 2000, "the servo at boot [us]"), mav_type=MAV_PARAM_TYPE_INT16),
    _i8("GRIP_REGRAB", 0, 0, 255, "served, unread (an EPM's regrab interval) [s]"),
    replace(_i("GRIP_CAN_ID", 0, 0, 255, "served, unread (a DroneCAN hardpoint)"), mav_type=MAV_PARAM_TYPE_INT16),
    _f("GRIP_AUTOCLOSE", 0, 0, 255, "a released gripper grabs again this long after [s], 0 = never"),
    # The winch (AP_Winch, payload/winch.py): ArduCopter shows WINCH_* but WINCH_TYPE once it is set;
    # the type is read at boot, the rest as the winch runs
    _i8("WINCH_TYPE", 0, 0, 2, "made at boot: 1 a PWM winch (SERVOn_FUNCTION 88); 0 none, 2 Daiwa (never healthy)"),
    _f("WINCH_RATE_MAX", 1.0, 0, 10, "the fastest the line runs either way, and the output's full scale [m/s]"),
    _f("WINCH_POS_P", 1.0, 0.01, 10, "length control: the rate asked per metre short of the target [1/s]"),
    replace(_i("WINCH_OPTIONS", 7, -32768, 32767, "bit 0 relaxed at boot, 1 say each length asked, 2 (Daiwa) retry if stuck"),
            mav_type=MAV_PARAM_TYPE_INT16),
    # The camera mount (AP_Mount, payload/mount.py): ArduCopter shows MNT1_* but the type once MNT1_TYPE
    # is set and the vehicle rebooted; types and ranges as its parameter documentation gives them
    _i8("MNT1_TYPE", 0, 0, 14, "made at boot: 1 a servo gimbal it steadies, 7 a brushless gimbal on PWM; 0 none"),
    _i8("MNT1_DEFLT_MODE", 3, 0, 6, "the mode at boot and after an ROI is cleared (MAV_MOUNT_MODE; 3 RC targeting)"),
    *(replace(_i(f"MNT1_{name}", default, low, high, doc), mav_type=MAV_PARAM_TYPE_INT16)
      for name, default, low, high, doc in (
          ("RC_RATE", 0, 0, 90, "RC targeting: a rate at full stick [deg/s]; 0 = angles"),
          ("ROLL_MIN", -30, -180, 180, "roll at the output's minimum [deg]"),
          ("ROLL_MAX", 30, -180, 180, "roll at its maximum [deg]"),
          ("PITCH_MIN", -90, -90, 90, "pitch at the output's minimum [deg]"),
          ("PITCH_MAX", 20, -90, 90, "pitch at its maximum [deg]"),
          ("YAW_MIN", -180, -180, 180, "pan at the output's minimum [deg]"),
          ("YAW_MAX", 180, -180, 180, "pan at its maximum [deg]"))),
    *(_f(f"MNT1_{name}_{axis}", 0, -180, 180, f"{what} {axis_name} [deg]")
      for name, what in (("RETRACT", "retracted (mode 0):"), ("NEUTRAL", "neutral (mode 1):"))
      for axis, axis_name in (("X", "roll"), ("Y", "pitch"), ("Z", "yaw"))),
    _f("MNT1_LEAD_RLL", 0, 0, 0.2, "served; the servo gimbal's roll lead [s] (not modelled)"),
    _f("MNT1_LEAD_PTCH", 0, 0, 0.2, "served; the servo gimbal's pitch lead [s] (not modelled)"),
    _i8("MNT1_SYSID_DFLT", 0, doc="the system mode 5 points at, from boot"),
    replace(_i("MNT1_DEVID", 0, -2**31, 2**31 - 1, "served; a driver's device id"), mav_type=MAV_PARAM_TYPE_INT32),
    _i8("MNT1_OPTIONS", 0, 0, 3, "bit 0: RC targeting keeps the last target's yaw lock; bit 1 (RC failsafe) unread"),
    # The rangefinder (AP_RangeFinder, rangefinder.py): ArduCopter shows RNGFND1_* but the type once
    # RNGFND1_TYPE is set and the vehicle rebooted, with these types and defaults (measured). No
    # documented range: an int8's, or a float's.
    _i8("RNGFND1_TYPE", 0, doc="0 none, 10 a companion's DISTANCE_SENSOR, 100 SITL's beam; read at boot"),
    _i8("RNGFND1_PIN", -1, doc="served; an analog sensor's pin (SITL's beam has none)"),
    _f("RNGFND1_SCALING", 3.0, -FLOAT32_MAX, FLOAT32_MAX, "served; an analog sensor's metres per volt"),
    _f("RNGFND1_OFFSET", 0.0, -FLOAT32_MAX, FLOAT32_MAX, "served; an analog sensor's volts at zero"),
    _i8("RNGFND1_FUNCTION", 0, doc="served; an analog sensor's curve"),
    _f("RNGFND1_MIN", 0.20, -FLOAT32_MAX, FLOAT32_MAX, "shorter ranges are out of range low [m]"),
    _f("RNGFND1_MAX", 7.00, -FLOAT32_MAX, FLOAT32_MAX, "longer ranges are out of range high [m]"),
    _i8("RNGFND1_STOP_PIN", -1, doc="served; a pin that stops the sensor"),
    _i8("RNGFND1_RMETRIC", 1, doc="served; an analog sensor's ratiometric reading"),
    replace(_i("RNGFND1_PWRRNG", 0, 0, 32767, "served; the height above terrain above which it sleeps [m]"),
            mav_type=MAV_PARAM_TYPE_INT16),
    _f("RNGFND1_GNDCLR", 0.10, 0.05, 1.5, "served; the range it reads on the ground [m]"),
    _i8("RNGFND1_ADDR", 0, 0, 127, "served; a bus address"),
    *(_f(f"RNGFND1_POS_{axis}", 0.0, -5, 5, "served; where it sits on the body [m] (SITL's beam starts at the centre)")
      for axis in "XYZ"),
    _i8("RNGFND1_ORIENT", 25, doc="the way it faces: 25 down (RANGEFINDER, the laser-position bit)"),
    _i8("FLOW_TYPE", 0, doc="0 none, 10 SITL's camera; the driver made at boot, the sensor enabled while set"),
    # FLOWHOLD's (modes/flowhold.py), with ArduCopter's names and defaults
    _f("FHLD_XY_P", 0.2, 0.1, 6.0, "the flow controller's P gain [ANGLE_MAX per m/s]"),
    _f("FHLD_XY_I", 0.3, 0.02, 1.0, "its I gain"),
    _f("FHLD_XY_IMAX", 3000, 0, 4500, "its integrator's limit"),
    _f("FHLD_XY_FILT_HZ", 5, 0, 100, "its input filter [Hz]"),
    _f("FHLD_FLOW_MAX", 0.6, 0.1, 2.5, "each flow rate clamped to this [rad/s]"),
    _f("FHLD_FILT_HZ", 5, 1, 100, "the flow's own filter [Hz]"),
    _i8("FHLD_QUAL_MIN", 10, 0, 127, "below this (filtered) quality FLOWHOLD flies as ALT_HOLD"),
    _i8("FHLD_BRAKE_RATE", 8, 1, 30, "the braking on release [deg/s]"),
    # The optical flow sensor (AP_OpticalFlow, optical_flow.py): ArduCopter shows FLOW_* but the type once
    # FLOW_TYPE is set (measured: these defaults); the scalers and the yaw act on the SITL driver's flow
    replace(_i("FLOW_FXSCALER", 0, -800, 800, "the x flow's scale correction [parts per thousand]"),
            mav_type=MAV_PARAM_TYPE_INT16),
    replace(_i("FLOW_FYSCALER", 0, -800, 800, "the y flow's scale correction [parts per thousand]"),
            mav_type=MAV_PARAM_TYPE_INT16),
    replace(_i("FLOW_ORIENT_YAW", 0, -17999, 18000, "the sensor's yaw on the body [cdeg]: the flow turned by it"),
            mav_type=MAV_PARAM_TYPE_INT16),
    *(_f(f"FLOW_POS_{axis}", 0, -5, 5, f"served; the sensor's {axis} offset on the body [m] (the EKF's)")
      for axis in "XYZ"),
    _i8("FLOW_ADDR", 0, 0, 127, "served; a bus address"),
    # The path planner round the fence (AP_OAPathPlanner, path_planning/): ArduCopter shows OA_* once
    # OA_TYPE is set (no reboot needed to see them, one to plan), with these types and defaults
    # (measured). The OA_DB_* are the obstacle database of proximity obstacles (obstacle_database.py).
    _i8("OA_TYPE", 0, 0, 3, "0 none, 1 BendyRuler round the fence and proximity obstacles, 2 Dijkstra round the "
                            "fence, 3 Dijkstra with BendyRuler round proximity obstacles; read at boot"),
    _f("OA_MARGIN_MAX", 5.0, 0.1, 100, "the path keeps this far out from the fence's corners [m]"),
    replace(_i("OA_OPTIONS", 1, 0, 32767, "bit 2: fast waypoints (fly on while planning and through the corners)"),
            mav_type=MAV_PARAM_TYPE_INT16),
    *(replace(_i(f"OA_DB_{name}", default, low, high, doc), mav_type=MAV_PARAM_TYPE_INT16)
      for name, default, low, high, doc in (
          ("SIZE", 100, 0, 10000, "obstacles the database keeps, read at boot (0: none made)"),
          ("EXPIRE", 10, 0, 500, "an obstacle is forgotten this long after it was last seen (0: never) [s]"),
          ("QUEUE_SIZE", 80, 1, 200, "readings queued for the database, read at boot (0: none made)"))),
    _i8("OA_DB_OUTPUT", 1, 0, 3, "served; which obstacles go to the ground station (proximity's never at 1)"),
    _f("OA_BR_LOOKAHEAD", 15.0, 1, 100, "BendyRuler looks this far ahead for obstacles (at least 1) [m]"),
    _f("OA_BR_CONT_RATIO", 1.5, 1.1, 2, "BendyRuler turns more than OA_BR_CONT_ANGLE only for this many times the margin"),
    replace(_i("OA_BR_CONT_ANGLE", 75, 20, 180, "BendyRuler resists turning more than this from its bearing [deg]"),
            mav_type=MAV_PARAM_TYPE_INT16),
    _i8("OA_BR_TYPE", 1, 1, 2, "BendyRuler's search: 1 horizontal (a bearing), 2 vertical (a climb or descent)"),
    *(_f(f"OA_DB_{name}", default, low, high, doc)
      for name, default, low, high, doc in (
          ("BEAM_WIDTH", 5.0, 1, 10, "an obstacle's radius is its distance times tan of this (read at boot) [deg]"),
          ("RADIUS_MIN", 0.01, 0, 10, "an obstacle's radius at least [m]"),
          ("DIST_MAX", 0.0, 0, 10, "readings whose near edge is further are dropped (0: none) [m]"),
          ("ALT_MIN", 0.0, 0, 4, "within 3 m of home, no readings below this height (0: any) [m]"))),
    # ADS-B (adsb/): the receiver's list (AP_ADSB) and avoidance (AP_Avoidance). ArduCopter shows
    # the rest of each group once ADSB_TYPE / AVD_ENABLE is set, with these types and defaults
    # (measured); both act without a reboot.
    _i8("ADSB_TYPE", 0, doc="0 off; any other type takes traffic as ADSB_VEHICLE (SITL's and a ground station's)"),
    replace(_i("ADSB_LIST_MAX", 25, 1, 100, "aircraft the list holds; read when the receiver starts"),
            mav_type=MAV_PARAM_TYPE_INT16),
    replace(_i("ADSB_LIST_RADIUS", 2000, 0, 100000, "traffic farther than this is not listed [m], 0 = any"),
            mav_type=MAV_PARAM_TYPE_INT32),
    replace(_i("ADSB_ICAO_ID", 0, -1, 16777215, "served; this vehicle's own ICAO address (no transponder here)"),
            mav_type=MAV_PARAM_TYPE_INT32),
    _i8("ADSB_EMIT_TYPE", 14, 0, 19, "served; this vehicle's emitter type"),
    _i8("ADSB_LEN_WIDTH", 1, 0, 15, "served; this vehicle's size class"),
    _i8("ADSB_OFFSET_LAT", 4, 0, 7, "served; the GPS antenna's lateral offset class"),
    _i8("ADSB_OFFSET_LON", 1, 0, 1, "served; the GPS antenna's longitudinal offset class"),
    _i8("ADSB_RF_SELECT", 1, 0, 3, "served; the transponder's receive and transmit bits"),
    replace(_i("ADSB_SQUAWK", 1200, 0, 7777, "served; the squawk code, octal digits"), mav_type=MAV_PARAM_TYPE_INT16),
    _i8("ADSB_RF_CAPABLE", 0, 0, 15, "served; the transponder's bands"),
    replace(_i("ADSB_LIST_ALT", 0, 0, 32767, "traffic more than this above or below is not listed [m], 0 = any"),
            mav_type=MAV_PARAM_TYPE_INT16),
    replace(_i("ADSB_ICAO_SPECL", 0, 0, 16777215, "this ICAO address is listed wherever it is"),
            mav_type=MAV_PARAM_TYPE_INT32),
    _i8("ADSB_LOG", 1, 0, 2, "served; what the dataflash log records of traffic"),
    replace(_i("ADSB_OPTIONS", 0, 0, 15, "served; transponder options"), mav_type=MAV_PARAM_TYPE_INT32),
    _i8("AVD_ENABLE", 0, 0, 1, "1: traffic is judged as threats (COLLISION) and acted on"),
    _i8("AVD_F_ACTION", 1, 0, 6, "a HIGH threat's action: 0 none, 1 report, 2 climb or descend, 3 move "
        "horizontally, 4 move away, 5 RTL, 6 hover"),
    _i8("AVD_W_ACTION", 1, 0, 1, "served; ArduCopter reads it nowhere"),
    _i8("AVD_F_RCVRY", 2, 0, 3, "after a threat: 0 stay, 1 the mode before, 2 RTL, 3 AUTO if it was in AUTO"),
    _i8("AVD_OBS_MAX", 20, 1, 127, "obstacles kept; read when avoidance starts"),
    _i8("AVD_W_TIME", 30, 0, 120, "seconds ahead a LOW threat is looked for [s]"),
    _i8("AVD_F_TIME", 30, 0, 120, "seconds ahead a HIGH threat is looked for [s]"),
    _f("AVD_W_DIST_XY", 300, 0, 2000, "closer than this within AVD_W_TIME is LOW [m]"),
    replace(_i("AVD_F_DIST_XY", 100, 0, 2000, "closer than this within AVD_F_TIME is HIGH [m]"),
            mav_type=MAV_PARAM_TYPE_INT16),
    _f("AVD_W_DIST_Z", 300, 0, 1000, "farther apart than this vertically is no threat [m]"),
    replace(_i("AVD_F_DIST_Z", 100, 0, 1000, "farther apart than this vertically is LOW, not HIGH [m]"),
            mav_type=MAV_PARAM_TYPE_INT16),
    replace(_i("AVD_F_ALT_MIN", 0, 0, 1000, "below this altitude (above sea level) a HIGH threat is only "
               "reported [m], 0 = off"), mav_type=MAV_PARAM_TYPE_INT16),
    # Precision landing (AC_PrecLand, precland.py): ArduCopter shows PLND_* but PLND_ENABLED once it is
    # set, with these types and defaults (measured); PLND_TYPE is read at boot
    _i8("PLND_ENABLED", 0, 0, 1, "1: precision landing; read at boot with PLND_TYPE, then it switches it"),
    _i8("PLND_TYPE", 0, 0, 4, "the sensor, made at boot: 1 a companion's LANDING_TARGET, 4 SITL's beacon"),
    _f("PLND_YAW_ALIGN", 0, 0, 36000, "served, unread (the sensor's yaw on the body) [cdeg]"),
    _f("PLND_LAND_OFS_X", 0, -20, 20, "land this far north of the target [cm] (ArduCopter: forward)"),
    _f("PLND_LAND_OFS_Y", 0, -20, 20, "land this far east of the target [cm] (ArduCopter: right)"),
    _i8("PLND_EST_TYPE", 1, 0, 1, "0 the raw sensor (acquired at once), 1 the Kalman filter (after 2 s)"),
    _f("PLND_ACC_P_NSE", 2.5, 0.5, 5, "served, unread (the filter's acceleration noise)"),
    *(_f(f"PLND_CAM_POS_{axis}", 0, -5, 5, "served, unread (where the sensor sits) [m]") for axis in "XYZ"),
    _i8("PLND_BUS", -1, -1, 3, "served, unread (an IRLock's bus)"),
    _f("PLND_LAG", 0.02, 0.02, 0.25, "served, unread (the sensor's lag) [s]"),
    _f("PLND_XY_DIST_MAX", 2.5, 0, 10, "LAND holds its height while farther than this from the target [m], 0 off"),
    _i8("PLND_STRICT", 1, 0, 2, "a target lost: 0 land where it is, 1 retry then hold 7 s and land, 2 retry then hold"),
    _i8("PLND_RET_MAX", 4, 0, 10, "retries a landing mode may fly, 0 none (the failsafe instead)"),
    _f("PLND_TIMEOUT", 4, 0, 20, "a lost target's descent before a retry [s]"),
    _i8("PLND_RET_BEHAVE", 0, 0, 1, "a retry flies over where the target was last seen from (0) or over the target (1)"),
    _f("PLND_ALT_MIN", 0.75, 0, 5, "the target is in the sensor's range above this rangefinder height [m]"),
    _f("PLND_ALT_MAX", 8, 0, 50, "and below this [m]; both 0: always"),
    replace(_i("PLND_OPTIONS", 0, 0, 7, "bit 2: no slow final descent"), mav_type=MAV_PARAM_TYPE_INT16),
    # External navigation (external_nav.py): VISO_TYPE and GPS1_TYPE are read at boot; ArduCopter
    # shows the rest of VISO_* once VISO_TYPE is set; EK3_SRCn_* act at once
    _i8("GPS1_TYPE", 1, 0, 29, "0 no GPS (read at boot); any other type is the simulated receiver"),
    _i8("VISO_TYPE", 0, 0, 3, "1 (2, 3): a companion's pose over MAVLink (read at boot), 0 none"),
    _f("VISO_SCALE", 1.0, 0.0, FLOAT32_MAX, "the companion's positions are multiplied by this"),
    _i8("VISO_QUAL_MIN", 0, -1, 100, "a pose of lower quality is not fused"),
    *(_f(f"VISO_POS_{axis}", 0.0, -5, 5, "served, unread (where the camera sits) [m]") for axis in "XYZ"),
    _i8("VISO_ORIENT", 0, 0, 100, "served, unread (the camera's orientation)"),
    replace(_i("VISO_DELAY_MS", 10, 0, 250, "served, unread (the pose's lag) [ms]"), mav_type=MAV_PARAM_TYPE_INT16),
    _f("VISO_VEL_M_NSE", 0.1, 0.05, 5.0, "served, unread (velocity noise) [m/s]"),
    _f("VISO_POS_M_NSE", 0.2, 0.1, 10.0, "served, unread (position noise) [m]"),
    _f("VISO_YAW_M_NSE", 0.2, 0.05, 1.0, "served, unread (yaw noise) [rad]"),
    # Three source sets; MAV_CMD_SET_EKF_SOURCE_SET or RC function 90 chooses the one in use
    *(spec for n, (posxy, velxy, velz, yaw) in enumerate(((3, 3, 3, 1), (0, 0, 0, 0), (0, 0, 0, 0)), start=1)
      for spec in (
          _i8(f"EK3_SRC{n}_POSXY", posxy, 0, 6, "the horizontal position's source: 0 none, 3 GPS, 6 external navigation"),
          _i8(f"EK3_SRC{n}_VELXY", velxy, 0, 6, "the horizontal velocity's source (Firefly's velocity is the truth's)"),
          _i8(f"EK3_SRC{n}_POSZ", 1, 0, 6, "the height's source: 1 barometer, 6 external navigation"),
          _i8(f"EK3_SRC{n}_VELZ", velz, 0, 6, "the vertical velocity's source (Firefly's velocity is the truth's)"),
          _i8(f"EK3_SRC{n}_YAW", yaw, 0, 6, "the heading's source (Firefly's heading is the truth's)"))),
    # Mission (AP_Mission)
    _i("MIS_RESTART", 0, 0, 1, "AUTO after leaving it: 0 resumes the mission, 1 restarts it"),
    # The pilot's radio (autopilot/rc/): channel roles, the mode switch, overrides, the ground station
    _i("RCMAP_ROLL", 1, 1, 16), _i("RCMAP_PITCH", 2, 1, 16), _i("RCMAP_THROTTLE", 3, 1, 16), _i("RCMAP_YAW", 4, 1, 16),
    _i("THR_DZ", 100, 0, 300, "throttle dead band either side of mid-stick in ALT_HOLD and alike [thousandths]"),
    _i("FLTMODE_CH", 5, 0, 16, "channel of the 6-position flight-mode switch, 0 = none"),
    *(_i(f"FLTMODE{n}", mode, 0, 29, f"flight mode at switch position {n}")
      for n, mode in enumerate((7, 9, 6, 3, 5, 0), start=1)),  # SITL's copter.parm
    _f("RC_OVERRIDE_TIME", 3.0, -1, 120, "seconds an RC override lasts, 0 = overrides off, -1 = forever"),
    _i("RC_OPTIONS", 32, 0, 0x7FFFFFFF, "bit 0 ignore the receiver, 1 ignore overrides, 5 allow reversed switches"),
    _i("MAV_GCS_SYSID", 255, 1, 255, "the ground station's system id: RC overrides and MANUAL_CONTROL from it only"),
    _i("MAV_OPTIONS", 0, 0, 65535, "bit 0: hear only the ground station (MAV_GCS_SYSID) and this vehicle's own system"),
    *(spec for n in range(1, 17) for spec in (
        _i(f"RC{n}_MIN", 1000 if n <= 8 else 1100, 800, 2200, f"channel {n} lowest PWM [us]"),
        _i(f"RC{n}_TRIM", 1500, 800, 2200, f"channel {n} centre PWM [us]"),
        _i(f"RC{n}_MAX", 2000 if n <= 8 else 1900, 800, 2200, f"channel {n} highest PWM [us]"),
        _i(f"RC{n}_REVERSED", 0, 0, 1),
        _i(f"RC{n}_DZ", {1: 20, 2: 20, 3: 30, 4: 20}.get(n, 0), 0, 200, f"channel {n} dead zone [us]"),
        _i(f"RC{n}_OPTION", 7 if n == 7 else 0, 0, 400, f"channel {n} aux function (rc/aux.py)"))),
)

SPEC_BY_NAME = {spec.name: spec for spec in PARAM_TABLE}  # the modelled parameters: what acts


def _stored_spec(ref) -> ParamSpec:
    """A reference parameter Firefly does not model: its documented range (widened to hold the
    reference's own default, which the documentation does not always respect), within its type's."""
    low, high = INT_TYPE_BOUNDS.get(ref.mav_type, (-FLOAT32_MAX, FLOAT32_MAX))
    if ref.low is not None:
        low = max(low, min(ref.low, ref.default))
        high = min(high, max(ref.high, ref.default))
    return ParamSpec(ref.name, ref.default, low, high, ref.mav_type in INT_TYPE_BOUNDS, mav_type=ref.mav_type)


def _served_table() -> tuple[ParamSpec, ...]:
    """The reference's parameters in its order (a modelled one keeps Firefly's default and range,
    under the reference's name and type), then Firefly's own (FIREFLY_ONLY)."""
    served = []
    for ref in reference_params():
        modelled = SPEC_BY_NAME.get(ref.name)
        if modelled is None:
            served.append(_stored_spec(ref))
        else:
            served.append(replace(modelled, name=ref.name, mav_type=ref.mav_type,
                                  is_int=modelled.is_int or ref.mav_type in INT_TYPE_BOUNDS))
    names = {spec.name for spec in served}
    served.extend(replace(spec, mav_type=spec.mav_type or (MAV_PARAM_TYPE_INT32 if spec.is_int else MAV_PARAM_TYPE_REAL32))
                  for spec in PARAM_TABLE if spec.name not in names and spec.name in FIREFLY_ONLY)
    return tuple(served)


SERVED: tuple[ParamSpec, ...] = _served_table()  # every parameter served, in PARAM_VALUE index order
SERVED_BY_NAME = {spec.name: spec for spec in SERVED}
SERVED_NAMES = [spec.name for spec in SERVED]
INDEX_BY_NAME = {name: i for i, name in enumerate(SERVED_NAMES)}
# Names known to set() and reads but not served (params_differences.IN_PROCESS_ONLY): modelled
# ones the reference does not have, and ArduPilot 4.5's names of renamed ones (sharing their value).
UNSERVED = tuple(spec for spec in PARAM_TABLE if spec.name not in SERVED_BY_NAME)
KNOWN_BY_NAME = SERVED_BY_NAME | {spec.name: spec for spec in UNSERVED} \
    | {old: SERVED_BY_NAME[new] for old, new in OLD_NAMES.items()}
STORED_AS = {name: OLD_NAMES.get(name, name) for name in KNOWN_BY_NAME}  # where each value is kept
DEFAULTS = {STORED_AS[name]: spec.default for name, spec in KNOWN_BY_NAME.items()}


INVERSE_OLD_NAMES = {"SIM_GPS_DISABLE": "SIM_GPS1_ENABLE"}  # 4.5's name of a 0/1 that 4.7 inverted

# Parameters a command sets with whatever it is sent, outside their range too, as ArduCopter does
# (measured: DO_SET_CAM_TRIGG_DIST with NaN, -5, 21196 or inf is accepted, and PARAM_VALUE then
# reads CAM1_TRIGG_DIST as exactly that).
SET_UNCHECKED_BY_COMMANDS = {"CAM1_TRIGG_DIST": "MAV_CMD_DO_SET_CAM_TRIGG_DIST"}


def served_equivalent(name: str, value: float) -> tuple[str, float]:
    """The served parameter and value that mean what setting `name` to `value` means: for a
    caller that sets a name known in-process only (IN_PROCESS_ONLY) over MAVLink."""
    if name in INVERSE_OLD_NAMES:
        return INVERSE_OLD_NAMES[name], 0.0 if value else 1.0
    return OLD_NAMES.get(name, name), value


class ParamError(ValueError):
    pass


def checked_value(name: str, value) -> float:
    """The value `name` would take (integers rounded), or ParamError naming what is wrong."""
    spec = KNOWN_BY_NAME.get(name)
    if spec is None:
        raise ParamError(f"unknown parameter {name}")
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise ParamError(f"{name}: not a number") from None
    if not math.isfinite(value):
        raise ParamError(f"{name}: value must be finite")
    if not spec.low <= value <= spec.high:
        raise ParamError(f"{name}: {value:g} out of range {spec.low:g}..{spec.high:g}")
    return float(round(value)) if spec.is_int else value


class ParamStore:
    """Current values of every known parameter by name, with range checks and atomic persistence
    of those that differ from their default to a JSON file. Listeners hear a change made under an
    old name (OLD_NAMES) under the reference's (the one the vehicle's code reads)."""

    def __init__(self, path: Path | None = None, wipe: bool = False):
        self.path = path
        self._values = dict(DEFAULTS)
        self._defaults = dict(DEFAULTS)  # DEFAULTS, with what the vehicle's code moved (set_default)
        # Values still in use whose saved copy PREFLIGHT_STORAGE erased: left out of the file
        # until they are set again, so that the next boot starts from the defaults (as ArduPilot's
        # AP_Param::erase_all leaves the values in RAM and writes only those set after it).
        self._erased: set[str] = set()
        self._listeners: list[Callable[[str, float], None]] = []
        # Names the vehicle's own code saved (set(in_range=False)), for the ground stations: as
        # AP_Param::save sends each value it saves to every link. The MAVLink session drains it.
        self.vehicle_saved: list[str] = []
        self.file = JsonFile(path)
        if path is not None and path.exists() and not wipe:
            self._load(path)

    def _load(self, path: Path) -> None:
        saved = read_json(path)  # an unreadable file is ignored; defaults stand until the next save
        for name, value in saved.items() if isinstance(saved, dict) else ():
            if not is_saved(name):
                continue
            try:
                self._values[STORED_AS[name]] = checked_value(name, value)
            except (ParamError, KeyError):
                continue

    def names(self) -> list[str]:
        """Every served name, in PARAM_VALUE index order."""
        return list(SERVED_NAMES)

    def __len__(self) -> int:
        return len(SERVED)

    def __contains__(self, name: str) -> bool:
        """Whether `name` is served (over MAVLink); set() and reads know IN_PROCESS_ONLY's too."""
        return name in SERVED_BY_NAME

    def __getitem__(self, name: str) -> float:
        return self._values[STORED_AS[name]]

    def get(self, name: str, default=None):
        return self._values[STORED_AS[name]] if name in STORED_AS else default

    def index_of(self, name: str) -> int:
        return INDEX_BY_NAME[name]

    def mav_type(self, name: str) -> int:
        """The MAV_PARAM_TYPE `name` is served with (the reference's, for the reference's names)."""
        mav_type = SERVED_BY_NAME[name].mav_type
        return MAV_PARAM_TYPE_REAL32 if mav_type is None else mav_type  # every served spec has one

    def acts(self, name: str) -> bool:
        """Whether setting `name` changes the vehicle (a modelled parameter) or is only stored."""
        return STORED_AS.get(name) in SPEC_BY_NAME

    def on_change(self, callback: Callable[[str, float], None]) -> None:
        self._listeners.append(callback)

    def set(self, name: str, value, in_range: bool = True, announce: bool = True) -> float:
        """Set and persist; raises ParamError (naming the problem) and changes nothing on bad input.
        in_range=False: as the vehicle's own code sets a value (AUTOTUNE saving its gains, which
        may leave the documented ranges as ArduCopter's do): finite, not range-checked, and sent
        to every ground station unless `announce` is False (a value set while booting)."""
        if in_range:
            value = checked_value(name, value)
        elif name not in STORED_AS or not math.isfinite(float(value)):
            raise ParamError(f"{name}: unknown, or value not finite")
        else:
            value = float(value)
            if announce:
                self.vehicle_saved.append(name)
        name = STORED_AS[name]
        if value == self._values[name]:
            return value  # nothing changes: a GCS re-sending its whole list must not re-trigger faults
        self._values[name] = value
        self._erased.discard(name)
        if is_saved(name):
            self._save()
        for callback in self._listeners:
            callback(name, value)
        return value

    def set_default(self, name: str, value: float) -> None:
        """As AP_Param's set_default, for this run: a parameter still at its default takes the new
        one (not saved: at the next boot it is back unless the code moves it again); one set
        keeps its value."""
        name = STORED_AS[name]
        if self._values[name] == self._defaults[name] and self._values[name] != value:
            self._values[name] = float(value)
            for callback in self._listeners:
                callback(name, float(value))
        self._defaults[name] = float(value)

    def save_all(self) -> None:
        self._save()

    def erase_saved(self) -> bool:
        """Forget every saved value (the values in use stay until the next boot); whether the
        file took it."""
        self._erased = {n for n, v in self._values.items() if v != self._defaults[n]}
        return self._save()

    def report(self, name: str, value: float) -> None:
        """Set a value the vehicle only reports (as SITL reports SIM_SPEEDUP, its command line's
        --speedup): not range-checked, not saved, no listener told."""
        self._values[STORED_AS[name]] = float(value)

    @property
    def save_errors(self) -> int:
        return self.file.save_errors

    @property
    def last_save_error(self) -> str:
        return self.file.last_save_error

    def _save(self) -> bool:
        """Persist (persist.JsonFile: a refused save is counted, the value still takes effect in
        flight: the vehicle must not stop or half-apply a change for it)."""
        erased = self._erased
        defaults = self._defaults
        return self.file.save(lambda: {n: v for n, v in self._values.items()
                                       if v != defaults[n] and is_saved(n) and n not in erased})

"""Arming: ArduCopter's pre-arm checks as a table, the rules that refuse an ARM, and the state
that arming starts (armed, and ArduCopter's auto_armed flag).

The checks read the vehicle through its pre-arm view (views.PrearmView); each returns the words
ArduCopter puts after "PreArm: ", or None when it passes.
"""
from __future__ import annotations

import math
from collections.abc import Callable

from ..modes.numbers import ModeNumber
from ..terrain import FROM_DATABASE, FROM_RANGEFINDER
from ..rc.radio import ARMING_CHECK_THROTTLE, ARMING_SKIP_CHECK_RPY
from ..views import PrearmView
from .simple_avoid import USE_PROXIMITY

PROXIMITY_CLEAR_M = 0.6  # ArduCopter's pre-arm: nothing this near
FORCE_ARM_MAGIC = 2989  # COMPONENT_ARM_DISARM param2 that skips the checks (ArduPilot's)
FORCE_DISARM_MAGIC = 21196  # ... and that disarms even in flight
# Modes a ground station may arm with the throttle stick up (allows_GCS_or_SCR_arming_with_throttle_high)
ARM_WITH_THROTTLE_UP = frozenset((ModeNumber.GUIDED, ModeNumber.GUIDED_NOGPS, ModeNumber.AUTO))


def _starting_up(v: PrearmView) -> list[str]:
    """A realistic start-up's sensor and EKF stages (startup.py); none by default."""
    return v.startup_arm_blockers(v.time_s)


def _need_position(v: PrearmView) -> str | None:
    """Modes that fly by position need home and the estimate's position; as ArduCopter words it,
    "AHRS: waiting for home" before the EKF has an origin, then "Need 3D Fix" while the GPS has
    no fix (the EKF's dead reckoning after a lost fix does not arm), "Need Position Estimate"
    while the EKF does not use it yet."""
    if not v.mode_requires_position:
        return None
    if v.home_ned is None:  # (external navigation has a position before any origin: measured)
        return "AHRS: waiting for home"
    if v.has_position() and (v.gps.fix_type >= 3 or v.navigating_externally()):
        return None
    return "Need 3D Fix" if v.gps.fix_type < 3 else "Need Position Estimate"


def _visual_odometry(v: PrearmView) -> str | None:
    """AP_Arming's visual odometry check: a sensor set up (VISO_TYPE) must be sending."""
    ext = v.external_nav
    return "VisOdom: not healthy" if ext.kind and not ext.healthy(v.time_s) else None


# EK3_SRCn_* values AP_NavEKF_Source takes for each part (others: "Check EK3_SRCn_<part>"), and the
# sensor each source needs
VALID_SOURCES = {"POSXY": (0, 3, 4, 6), "VELXY": (0, 3, 5, 6, 7), "POSZ": (0, 1, 2, 3, 4, 6), "VELZ": (0, 3, 6)}
SOURCE_SENSOR = {3: "GPS", 4: "Beacon", 5: "OpticalFlow", 6: "VisualOdom", 7: "WheelEncoder"}
SOURCE_SETS = 3


def _ekf_sources(v: PrearmView) -> str | None:
    """AP_NavEKF_Source::pre_arm_check, for a mode that needs a position: every source set's
    position and velocity sources valid, and each sensor they name there (a GPS detected, VISO_TYPE
    set, a downward rangefinder for a height from it; Firefly has no beacon, optical flow or wheel
    encoder). ArduCopter says the first failure."""
    if not v.mode_requires_position:
        return None
    p, needed = v.params, []
    for n in range(1, SOURCE_SETS + 1):
        for part, valid in VALID_SOURCES.items():
            source = int(p[f"EK3_SRC{n}_{part}"])
            if source not in valid:
                return f"AHRS: Check EK3_SRC{n}_{part}"
            if part == "POSZ" and source in (1, 2):
                needed.append("Baro" if source == 1 else "RangeFinder")
            elif source in SOURCE_SENSOR:
                needed.append(SOURCE_SENSOR[source])
    available = {"Baro", "GPS"} if v.gps_detected else {"Baro"}
    if v.external_nav.kind:
        available.add("VisualOdom")
    if v.rangefinder_down:
        available.add("RangeFinder")
    for sensor in ("Baro", "Beacon", "GPS", "OpticalFlow", "RangeFinder", "VisualOdom", "WheelEncoder"):
        if sensor in needed and sensor not in available:
            return f"AHRS: EK3 sources require {sensor}"
    return None


def _throttle_below_failsafe(v: PrearmView) -> str | None:
    """With the radio failsafe on, a throttle channel reading under FS_THR_VALUE (a receiver in
    its own failsafe, SIM_RC_FAIL 2) refuses arming."""
    p = v.params
    if not p["FS_THR_ENABLE"]:
        return None
    throttle_us = v.rc_channels_us()[int(p["RCMAP_THROTTLE"]) - 1]
    return "Throttle below failsafe" if throttle_us < p["FS_THR_VALUE"] else None


def _emergency_stopped(v: PrearmView) -> str | None:
    return "Motors Emergency Stopped" if v.motors_emergency_stopped else None


def _safety_switch(v: PrearmView) -> str | None:
    """AP_Arming::hardware_safety_check: the safety switch, turned on by DO_SET_SAFETY_SWITCH_STATE."""
    return "Hardware safety switch" if v.safety_on else None


def _internal_errors(v: PrearmView) -> str | None:
    return v.internal_error_prearm_text()


def _gps_glitching(v: PrearmView) -> str | None:
    return "GPS glitching" if v.gps_glitching else None


def _leaning(v: PrearmView) -> str | None:
    roll, pitch, _ = v.attitude
    return "Leaning" if max(abs(roll), abs(pitch)) > math.radians(v.params["ANGLE_MAX"] / 100.0) else None


def _battery_low(v: PrearmView) -> str | None:
    """AP_BattMonitor's checks on its one battery, the first failing in ArduPilot's order (each
    wording measured: BATT_ARM_VOLT's, BATT_LOW_VOLT's failsafe)."""
    p, volts = v.params, v.battery.voltage_v
    arm = p["BATT_ARM_VOLT"]
    if arm > 0 and volts < arm:
        return "Battery 1 below minimum arming voltage"
    low = p["BATT_LOW_VOLT"]
    return "Battery 1 low voltage failsafe" if low > 0 and volts < low else None


def _rangefinder(v: PrearmView) -> str | None:
    """AP_Arming::rangefinder_checks: a rangefinder set up must be there and have data (out of
    range is data: it may arm on the ground, below RNGFND1_MIN)."""
    return v.rangefinder_prearm_failure()


def _parachute(v: PrearmView) -> str | None:
    """AP_Parachute's arming check (AP_Arming's system checks, after the rangefinder's): enabled,
    its release output is set up and it has not been released since boot (measured)."""
    return v.parachute_prearm_failure()


def _proximity(v: PrearmView) -> str | None:
    """AP_Arming's proximity check and ArduCopter's: a sensor set up must have data, and nothing
    may be within 0.6 m while avoidance uses it (measured, both)."""
    prox = v.proximity
    if not prox.kind:
        return None
    if not prox.good:
        return "PRX1: No Data"
    closest = prox.closest() if int(v.params["AVOID_ENABLE"]) & USE_PROXIMITY else None
    if closest is not None and closest[1] <= PROXIMITY_CLEAR_M:
        return f"Proximity {int(closest[0])} deg, {closest[1]:4.2f}m (want > {PROXIMITY_CLEAR_M:0.1f}m)"
    return None


def _adsb_threat(v: PrearmView) -> str | None:
    """ArduCopter's parameter checks: not while ADS-B avoidance is acting on a threat (on the
    ground with AVD_F_ACTION above a report, a HIGH threat keeps it acting: measured)."""
    return "ADSB threat detected" if v.adsb_threat else None


def _object_avoidance(v: PrearmView) -> str | None:
    """AP_Arming_Copter::oa_checks: the path planner OA_TYPE names was made at boot."""
    return v.path_planner_prearm_failure()


def _winch(v: PrearmView) -> str | None:
    """AP_Arming_Copter::winch_checks: with WINCH_TYPE set, the winch made at boot must have its
    output (SERVOn_FUNCTION 88); set since boot, there is none: unhealthy too."""
    return v.winch_prearm_failure()


RTL_ABOVE_TERRAIN = 1  # RTL_ALT_TYPE


def _rtl_terrain(v: PrearmView) -> str | None:
    """ArduCopter's parameter checks for RTL_ALT_TYPE 1 (above terrain): a terrain source, and with
    the rangefinder one, RTL_ALT (cm) within its range (RNGFND1_MAX, m). The database's own check
    is _terrain_data's."""
    p = v.params
    if int(p["RTL_ALT_TYPE"]) != RTL_ABOVE_TERRAIN:
        return None
    source = v.terrain_source()
    if source is None:
        return "RTL_ALT_TYPE is above-terrain but no terrain data"
    if source == FROM_RANGEFINDER and p["RTL_ALT"] > p["RNGFND1_MAX"] * 100.0:
        return "RTL_ALT_TYPE is above-terrain but RTL_ALT (in cm) above RNGFND_MAX (in metres)"
    return None


def _terrain_data(v: PrearmView) -> str | None:
    """A mission at heights above terrain, or RTL above terrain over the database, needs the
    terrain database (AP_Arming::terrain_checks): every block wanted filled, the heights under the
    vehicle and home known. Until a ground station has served the tiles: "Arm: waiting for terrain
    data", and no arming (measured, both). Not when the waypoint navigator follows the terrain by
    rangefinder (terrain_database_required)."""
    if v.terrain_from_rangefinder():  # the rangefinder: no database needed
        return None
    rtl_above_terrain = int(v.params["RTL_ALT_TYPE"]) == RTL_ABOVE_TERRAIN and v.terrain_source() == FROM_DATABASE
    if not (rtl_above_terrain or v.mission_uses_terrain()):
        return None
    if not v.params["TERRAIN_ENABLE"]:
        return "terrain disabled"
    v.terrain_update()
    return v.terrain.prearm_failure(v.params)


# In ArduCopter's order; a check gives its words, a list of them, or None when it passes.
PREARM_CHECKS: tuple[Callable[[PrearmView], str | list[str] | None], ...] = (
    _starting_up, _rtl_terrain, _adsb_threat, _object_avoidance, _winch, _throttle_below_failsafe, _safety_switch, _internal_errors, _need_position, _visual_odometry, _ekf_sources, _gps_glitching, _leaning, _battery_low,
    _rangefinder, _parachute, _proximity, _terrain_data, _emergency_stopped)


# Run by an ARM only (AP_Arming_Copter::arm_checks), never in the report said unasked
ARM_ONLY_CHECKS = (_leaning,)
REPORTED_CHECKS = tuple(check for check in PREARM_CHECKS if check not in ARM_ONLY_CHECKS)


def prearm_failures(v: PrearmView, checks=PREARM_CHECKS) -> list[str]:
    """Every failing pre-arm check, in order ([] when all pass or ARMING_CHECK is 0): an ARM
    refused by them is answered with each, as ArduCopter reports every failing check. The
    report a disarmed vehicle says unasked runs REPORTED_CHECKS."""
    if v.params["ARMING_CHECK"] == 0:
        return []
    if v.startup_initialising(v.time_s):
        return ["System not initialised"]  # nothing else is checked yet
    failures: list[str] = []
    for check in checks:
        reason = check(v)
        if reason:
            failures.extend([reason] if isinstance(reason, str) else reason)
    return failures


def prearm_failure(v: PrearmView) -> str | None:
    """The first failing pre-arm check, or None."""
    failures = prearm_failures(v)
    return failures[0] if failures else None


def arm_refusals(v: PrearmView, force: bool) -> list[str]:
    """The STATUSTEXTs that refuse an ARM in the vehicle's state; [] to arm."""
    if v.mode_number == ModeNumber.AUTO and not v.mission_status()[1]:
        return ["Arm: Mode requires mission"]  # ArduCopter's first word on arming in an empty AUTO
    if not v.mode_allows_arming:
        return [f"Arm: {v.mode_name} mode not armable"]
    if force:
        return []
    failures = prearm_failures(v)
    if failures:  # ArduPilot prefixes the checks an ARM runs "Arm:", its periodic report "PreArm:"
        return [f"Arm: {reason}" for reason in failures]
    if v.params["ARMING_CHECK"] and v.mode_number not in ARM_WITH_THROTTLE_UP and _throttle_up(v):
        return ["Arm: Throttle too high"]
    return [f"Arm: {reason}" for reason in rc_arm_failures(v)] if v.params["ARMING_CHECK"] else []


def rc_arm_failures(v: PrearmView) -> list[str]:
    """AP_Arming::rc_arm_checks, the last an ARM runs: no two channels with one aux function, the
    flight-mode channel free of one, roll, pitch and yaw centred (unless RC_OPTIONS skips it) and,
    with RC_OPTIONS' throttle check (SITL's default 32), the throttle at the bottom."""
    if not v.radio_input_valid:
        return []
    p = v.params
    failures = []
    options = [int(p[f"RC{n}_OPTION"]) for n in range(1, 17)]
    used = [o for o in options if o]
    if len(used) != len(set(used)):
        failures.append("Duplicate Aux Switch Options")
    mode_channel = int(p["FLTMODE_CH"])
    if 1 <= mode_channel <= 16 and options[mode_channel - 1]:
        failures.append(f"Mode channel and RC{mode_channel}_OPTION conflict")
    rc_options, pilot = int(p["RC_OPTIONS"]), v.pilot
    if not rc_options & ARMING_SKIP_CHECK_RPY:
        for name, role, value in (("Roll", "RCMAP_ROLL", pilot.roll), ("Pitch", "RCMAP_PITCH", pilot.pitch),
                                  ("Yaw", "RCMAP_YAW", pilot.yaw)):
            if value != 0.0:
                failures.append(f"{name} (RC{int(p[role])}) is not neutral")
    if rc_options & ARMING_CHECK_THROTTLE and pilot.throttle != 0.0:
        failures.append(f"Throttle (RC{int(p['RCMAP_THROTTLE'])}) is not neutral")
    return failures


def _throttle_up(v: PrearmView) -> bool:
    """ArduCopter's arm check: the stick above ALT_HOLD's dead band, or in a manual-throttle mode
    (and DRIFT) above its bottom."""
    if v.mode_manual_throttle or v.mode_number == ModeNumber.DRIFT:
        return v.pilot.throttle > 0.0
    return v.pilot_climb_rate() > 0.0


def arm_refusal(v: PrearmView, force: bool) -> str | None:
    """The first STATUSTEXT that refuses an ARM, or None to arm."""
    refusals = arm_refusals(v, force)
    return refusals[0] if refusals else None


# ArduCopter keeps the motors stopped this long after arming (ARMING_DELAY_SEC; measured on its
# SITL: SERVO_OUTPUT_RAW reads MOT_PWM_MIN for 2.0-2.2 s after the arming ACK, in every mode but
# THROW), then spools them up to ground idle.
ARMING_DELAY_S = 2.0


class Arming:
    """Whether the motors are armed, and ArduCopter's auto_armed: AUTO may start its
    mission from the ground (set by MISSION_START while armed and by a takeoff; cleared on disarm)."""

    def __init__(self) -> None:
        self.armed = False
        self.auto_armed = False
        self.changes = 0  # arms and disarms so far: a reader that looks now and then sees each one
        # The heading when last armed [rad] (ArduCopter's initial_armed_bearing): RTL turns back to it
        self.armed_yaw = 0.0
        # Sim time the arming delay ends: the motors may spin from then on (ArduCopter's interlock)
        self.interlock_at_s = 0.0
        self.armed_at_s = 0.0  # sim time of the last arming (ArduCopter's arm_time_ms)

    def arm(self, yaw: float = 0.0, now_s: float = 0.0) -> None:
        self.armed = True
        self.armed_yaw = yaw
        self.armed_at_s = now_s
        self.interlock_at_s = now_s + ARMING_DELAY_S
        self.changes += 1

    def disarm(self) -> None:
        self.armed = False
        self.auto_armed = False
        self.changes += 1

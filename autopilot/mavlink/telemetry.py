"""Vehicle state -> telemetry messages, one builder per message id, and ArduPilot's stream groups."""
from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from ..mission.progress import MissionState
from .. import version
from ..modes import MODE_BY_NUMBER
from ..safety.fence_switch import ALT_MAX, ALT_MIN, CIRCLE, POLYGON
from ..views import StreamedView, TelemetryView
from .dialect import mavlink as mav
from .encoding import deg_e7 as _deg_e7
from .encoding import time_boot_ms as _ms
from .encoding import u16
from .adsb_messages import BUILDERS as ADSB_BUILDERS
from .camera_messages import BUILDERS as CAMERA_BUILDERS
from .mount_messages import BUILDERS as MOUNT_BUILDERS
from .optical_flow_messages import BUILDERS as OPTICAL_FLOW_BUILDERS
from .rangefinder_messages import BUILDERS as RANGEFINDER_BUILDERS
from .sensor_messages import BUILDERS as SENSOR_BUILDERS
from .terrain import BUILDERS as TERRAIN_BUILDERS
from .winch_messages import BUILDERS as WINCH_BUILDERS
from .terrain import REQUEST_MIN_INTERVAL_S

LANDED_STATE = {"ON_GROUND": mav.MAV_LANDED_STATE_ON_GROUND, "IN_AIR": mav.MAV_LANDED_STATE_IN_AIR,
                "TAKEOFF": mav.MAV_LANDED_STATE_TAKEOFF, "LANDING": mav.MAV_LANDED_STATE_LANDING}

SENSORS = (mav.MAV_SYS_STATUS_SENSOR_3D_GYRO | mav.MAV_SYS_STATUS_SENSOR_3D_ACCEL
           | mav.MAV_SYS_STATUS_SENSOR_3D_MAG | mav.MAV_SYS_STATUS_SENSOR_ABSOLUTE_PRESSURE
           | mav.MAV_SYS_STATUS_SENSOR_GPS | mav.MAV_SYS_STATUS_SENSOR_ANGULAR_RATE_CONTROL
           | mav.MAV_SYS_STATUS_SENSOR_ATTITUDE_STABILIZATION | mav.MAV_SYS_STATUS_SENSOR_YAW_POSITION
           | mav.MAV_SYS_STATUS_SENSOR_Z_ALTITUDE_CONTROL | mav.MAV_SYS_STATUS_SENSOR_XY_POSITION_CONTROL
           | mav.MAV_SYS_STATUS_SENSOR_MOTOR_OUTPUTS | mav.MAV_SYS_STATUS_AHRS
           | mav.MAV_SYS_STATUS_SENSOR_BATTERY)
PREARM = mav.MAV_SYS_STATUS_PREARM_CHECK
# Reported present, enabled and healthy as ArduCopter SITL does: RC input (its SITL's stand-in, here
# RC override / MANUAL_CONTROL), terrain following (no data needed to report it healthy), logging
# and propulsion. Proximity is reported healthy though not present, as ArduPilot does.
ALWAYS_ON = (mav.MAV_SYS_STATUS_SENSOR_RC_RECEIVER | mav.MAV_SYS_STATUS_TERRAIN
             | mav.MAV_SYS_STATUS_LOGGING | mav.MAV_SYS_STATUS_SENSOR_PROPULSION)
CONTROL = mav.MAV_SYS_STATUS_SENSOR_Z_ALTITUDE_CONTROL | mav.MAV_SYS_STATUS_SENSOR_XY_POSITION_CONTROL
RANGEFINDER = mav.MAV_SYS_STATUS_SENSOR_LASER_POSITION
VISION = mav.MAV_SYS_STATUS_SENSOR_VISION_POSITION
FLOW = mav.MAV_SYS_STATUS_SENSOR_OPTICAL_FLOW


def heartbeat(v: TelemetryView, codec):
    base = mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED | mav.MAV_MODE_FLAG_STABILIZE_ENABLED \
        | mav.MAV_MODE_FLAG_MANUAL_INPUT_ENABLED
    if v.controls_position():
        base |= mav.MAV_MODE_FLAG_GUIDED_ENABLED
    if v.motors_armed:
        base |= mav.MAV_MODE_FLAG_SAFETY_ARMED
    # As ArduCopter: BOOT while it starts, then any failsafe or internal error makes it CRITICAL,
    # on the ground (armed or not) it is STANDBY.
    if v.startup_initialising(v.time_s):  # as ArduCopter until "ArduPilot Ready" (startup.py)
        status = mav.MAV_STATE_BOOT
    elif v.failsafe_active or v.internal_error_bits:
        status = mav.MAV_STATE_CRITICAL
    elif v.landed:
        status = mav.MAV_STATE_STANDBY
    else:
        status = mav.MAV_STATE_ACTIVE
    return codec.heartbeat_encode(mav.MAV_TYPE_QUADROTOR, mav.MAV_AUTOPILOT_ARDUPILOTMEGA, base,
                                  v.mode_number, status)


def fence_status(v: TelemetryView, codec):
    """Streamed only while a fence is on, as ArduCopter's: the breaches kept now, the count since
    boot, the kind (a boundary over the ceiling over the floor) and whether avoidance is holding
    the vehicle back."""
    if not v.fence.enabled:
        return None
    breaches = v.fence_breaches
    kind = mav.FENCE_BREACH_NONE
    if breaches & ALT_MIN:
        kind = mav.FENCE_BREACH_MINALT
    if breaches & ALT_MAX:
        kind = mav.FENCE_BREACH_MAXALT
    if breaches & (CIRCLE | POLYGON):
        kind = mav.FENCE_BREACH_BOUNDARY
    mitigation = mav.FENCE_MITIGATE_VEL_LIMIT if v.avoid_limits_active() else mav.FENCE_MITIGATE_NONE
    return codec.fence_status_encode(int(breaches != 0), v.fence_breach_count, kind, v.fence_breach_time_ms,
                                     mitigation)


def sys_status(v: TelemetryView, codec):
    present = SENSORS | PREARM | ALWAYS_ON | mav.MAV_SYS_STATUS_GEOFENCE
    # The altitude and position controllers are enabled (and healthy) only in modes that use them.
    enabled = present & ~CONTROL & ~mav.MAV_SYS_STATUS_GEOFENCE
    if not v.mode_manual_throttle:
        enabled |= mav.MAV_SYS_STATUS_SENSOR_Z_ALTITUDE_CONTROL
    if v.controls_position():
        enabled |= mav.MAV_SYS_STATUS_SENSOR_XY_POSITION_CONTROL
    if v.fence.enabled and v.params["FENCE_ACTION"] != 0:  # as AC_Fence: a fence that only reports is not enabled
        enabled |= mav.MAV_SYS_STATUS_GEOFENCE
    healthy = (enabled & ~PREARM & ~mav.MAV_SYS_STATUS_GEOFENCE) | mav.MAV_SYS_STATUS_SENSOR_PROXIMITY
    if v.armed or v.prearm_passed:  # as ArduPilot: armed, or the checks' last verdict (1 Hz)
        healthy |= PREARM
    if v.battery_failsafe_level:
        healthy &= ~mav.MAV_SYS_STATUS_SENSOR_BATTERY
    if v.gps.fix_type < 3:  # as ArduCopter: the GPS is healthy only with a 3D fix
        healthy &= ~mav.MAV_SYS_STATUS_SENSOR_GPS
    # As ArduPilot: the fence bit is healthy unless a fence is enabled and breached (MAVProxy
    # reads a missing health bit as a breach even when no fence exists).
    if not v.fence_breaches:
        healthy |= mav.MAV_SYS_STATUS_GEOFENCE
    if v.rangefinder_kind:  # (one plain read when there is none, as on most vehicles)
        if v.rangefinder_down:  # as ArduCopter: present with a downward rangefinder, enabled at boot and by
            present |= RANGEFINDER  # the RANGEFINDER aux switch, healthy while enabled with data
        if v.rangefinder_enabled:
            enabled |= RANGEFINDER
            if v.rangefinder_reading().has_data:
                healthy |= RANGEFINDER
    prox = v.proximity
    if prox.kind:  # as ArduCopter: a proximity sensor is present and enabled, healthy with data
        present |= mav.MAV_SYS_STATUS_SENSOR_PROXIMITY
        enabled |= mav.MAV_SYS_STATUS_SENSOR_PROXIMITY
        if not prox.good:
            healthy &= ~mav.MAV_SYS_STATUS_SENSOR_PROXIMITY
    flow = v.optical_flow
    if flow.enabled:  # as ArduCopter: FLOW_TYPE set (live), healthy while samples come
        present |= FLOW
        enabled |= FLOW
        if flow.healthy(v.time_s):
            healthy |= FLOW
    ext = v.external_nav
    if ext.kind:  # as ArduCopter: visual odometry is present and enabled, healthy with data
        present |= VISION
        enabled |= VISION
        if ext.healthy(v.time_s):
            healthy |= VISION
    if not v.gps_fitted:  # GPS1_TYPE 0: no receiver to report
        present &= ~mav.MAV_SYS_STATUS_SENSOR_GPS
        enabled &= ~mav.MAV_SYS_STATUS_SENSOR_GPS
        healthy &= ~mav.MAV_SYS_STATUS_SENSOR_GPS
    if v.precland_kind and v.params["PLND_ENABLED"]:  # as ArduCopter: precision landing's sensor
        present |= VISION
        enabled |= VISION
        if v.precland_healthy:
            healthy |= VISION
    batt = v.battery
    errors1, errors2, errors4 = v.internal_error_fields()
    return codec.sys_status_encode(present, enabled, healthy, 100,
                                   int(batt.voltage_v * 1000), int(batt.current_a * 100),
                                   int(round(v.battery_remaining * 100)), 0, 0, errors1, errors2, 0, errors4)


def battery_status(v: TelemetryView, codec):
    batt = v.battery
    volts = [min(int(batt.voltage_v * 1000), 65534)] + [65535] * 9
    return codec.battery_status_encode(0, mav.MAV_BATTERY_FUNCTION_ALL, mav.MAV_BATTERY_TYPE_LIPO,
                                       32767, volts, int(batt.current_a * 100),
                                       int(batt.consumed_mah), -1,
                                       int(round(v.battery_remaining * 100)))


def global_position_int(v: TelemetryView, codec):
    b = v.body
    hdg = int(round(math.degrees(v.attitude[2]) * 100)) % 36000
    if v.home_ned is None and v.gps.fix_type < 3 and not v.origin_known():  # as ArduCopter: no location at all
        return codec.global_position_int_encode(_ms(v), 0, 0, 0, 0, 0, 0, 0, 0)
    pos = v.position_global()
    home_alt = v.home.alt_m if v.home else v.origin.alt_m
    return codec.global_position_int_encode(_ms(v), _deg_e7(pos.lat_deg), _deg_e7(pos.lon_deg),
                                            int(pos.alt_m * 1000), int((pos.alt_m - home_alt) * 1000),
                                            int(b.vn_m_s * 100), int(b.ve_m_s * 100),
                                            int(b.vd_m_s * 100), hdg)


def local_position_ned(v: TelemetryView, codec):
    if not v.local_position_known():  # as ArduCopter: not sent before the EKF has a position
        return None
    b = v.body
    x, y = v.local_ne(b.n_m, b.e_m)
    return codec.local_position_ned_encode(_ms(v), x, y, b.d_m, b.vn_m_s, b.ve_m_s, b.vd_m_s)


def gps_raw_int(v: TelemetryView, codec):
    g = v.gps
    pos = v.ned_to_global(g.n_m, g.e_m, g.d_m)
    speed = math.hypot(g.vn_m_s, g.ve_m_s)
    cog = int(round(math.degrees(math.atan2(g.ve_m_s, g.vn_m_s)) * 100)) % 36000 if speed > 0.2 else 0
    return codec.gps_raw_int_encode(int(v.time_s * 1e6), g.fix_type, _deg_e7(pos.lat_deg),
                                    _deg_e7(pos.lon_deg), int(pos.alt_m * 1000), 80, 120,
                                    u16(speed * 100), cog, g.satellites)  # a companion's GPS_INPUT may say anything


def attitude(v: TelemetryView, codec):
    b = v.body
    roll, pitch, yaw = v.attitude
    return codec.attitude_encode(_ms(v), roll, pitch, yaw, b.p_rad_s, b.q_rad_s, b.r_rad_s)


def attitude_quaternion(v: TelemetryView, codec):
    b = v.body
    return codec.attitude_quaternion_encode(_ms(v), b.qw, b.qx, b.qy, b.qz, b.p_rad_s, b.q_rad_s,
                                            b.r_rad_s, [0.0, 0.0, 0.0, 0.0])


def vfr_hud(v: TelemetryView, codec):
    b = v.body
    gs = math.hypot(b.vn_m_s, b.ve_m_s)
    heading = int(round(math.degrees(v.attitude[2]))) % 360
    throttle = int(min(100, max(0, 100 * v.thrust_demand_n / v.thrust_max_n)))
    return codec.vfr_hud_encode(gs, gs, heading, throttle, v.position_global().alt_m, -b.vd_m_s)


def home_position(v: TelemetryView, codec):
    home_ned = v.home_ned
    if home_ned is None:
        return None
    n, e, d = home_ned
    home = v.ned_to_global(n, e, d)  # v.home
    n, e = v.local_ne(n, e)
    return codec.home_position_encode(_deg_e7(home.lat_deg), _deg_e7(home.lon_deg),
                                      int(home.alt_m * 1000), n, e, d, [1.0, 0.0, 0.0, 0.0],
                                      0.0, 0.0, 0.0, int(v.time_s * 1e6))


def gps_global_origin(v: TelemetryView, codec):
    """The EKF origin; ArduCopter sends it with HOME_POSITION when asked for home or home moves.
    Before it has one there is none to send; an origin without home (SET_GPS_GLOBAL_ORIGIN to a
    vehicle with no horizontal position) is sent too (measured, GPS1_TYPE 0)."""
    if v.home_ned is None and not v.origin_known():
        return None
    origin = v.ekf_origin()
    return codec.gps_global_origin_encode(_deg_e7(origin.lat_deg), _deg_e7(origin.lon_deg),
                                          int(origin.alt_m * 1000), int(v.time_s * 1e6))


def extended_sys_state(v: TelemetryView, codec):
    return codec.extended_sys_state_encode(mav.MAV_VTOL_STATE_MC, LANDED_STATE[v.landed_state()])


def system_time(v: TelemetryView, codec):
    return codec.system_time_encode(v.unix_time_us(), _ms(v))


MISSION_STATE = {MissionState.NOT_STARTED: mav.MISSION_STATE_NOT_STARTED, MissionState.ACTIVE: mav.MISSION_STATE_ACTIVE,
                 MissionState.COMPLETE: mav.MISSION_STATE_COMPLETE}


def mission_current(v: TelemetryView, codec, seq: int | None = None):
    """MISSION_CURRENT as ArduCopter fills it: the current navigation item (or `seq`, to echo a
    MISSION_SET_CURRENT), the item count without home, and whether AUTO is flying the mission."""
    current, total, progress_state = v.mission_status()
    state = MISSION_STATE[progress_state] if total else mav.MISSION_STATE_NO_MISSION
    return codec.mission_current_encode(current if seq is None else seq, total, state,
                                        1 if v.in_mission_mode else 0)


def autopilot_version(v: TelemetryView, codec):
    """As the reference ArduCopter SITL fills it (version.py)."""
    return codec.autopilot_version_encode(version.CAPABILITIES, version.FLIGHT_SW_VERSION, 0, 0, 0,
                                          version.FLIGHT_CUSTOM_VERSION, [0] * 8, [0] * 8, 0, 0, 0,
                                          version.uid2(v.board_id))


TEMPERATURE_NAME = b"GND_TEMP"  # downward radiometer reading, degrees C; time_boot_ms = sample time


def ground_temperature(v: TelemetryView, codec):
    t_s, value = v.temperature
    own = codec.named_value_float_encode(int(t_s * 1000.0) & 0xFFFFFFFF, TEMPERATURE_NAME, value)
    named = v.mode_named_float  # FLOWHOLD's height estimate "HEST", as ArduCopter sends it
    if named is None:
        return own
    return [own, codec.named_value_float_encode(_ms(v), named[0], named[1])]


# What ArduCopter's EKF3 reports flying on a GPS or a visual odometry sensor's pose (measured);
# EKF_POS_VERT_AGL only with a terrain height estimate (terrain_height_known): a rangefinder's.
EKF_GOOD = (mav.EKF_ATTITUDE | mav.EKF_VELOCITY_HORIZ | mav.EKF_VELOCITY_VERT | mav.EKF_POS_HORIZ_REL
            | mav.EKF_POS_HORIZ_ABS | mav.EKF_POS_VERT_ABS | mav.EKF_PRED_POS_HORIZ_REL | mav.EKF_PRED_POS_HORIZ_ABS)
# Without a position (measured, area ekf_variances): while the EKF still aids, attitude, vertical
# velocity and height only (0x25, from 7 s after the GPS went in a hover, as with a visual odometry
# sensor whose pose is lost); once it stops aiding (15 s after the last position, or never having
# had one: booted without a GPS), constant position mode, which also vouches for the horizontal
# velocity (0xa7).
EKF_CONSTANT_POSITION = (mav.EKF_ATTITUDE | mav.EKF_VELOCITY_HORIZ | mav.EKF_VELOCITY_VERT | mav.EKF_POS_VERT_ABS
                         | mav.EKF_CONST_POS_MODE)
EKF_NO_POSITION = mav.EKF_ATTITUDE | mav.EKF_VELOCITY_VERT | mav.EKF_POS_VERT_ABS
EKF_GPS_GLITCH = 32768  # MAVLink's EKF_GPS_GLITCH flag, newer than this pymavlink's dialect


# EKF3's height and compass test ratios as ArduCopter SITL reports them, settled, hovering and
# with its GPS jammed alike (0.00 and 0.02): the ideal estimate here has no innovations of its own.
HEIGHT_TEST_RATIO, COMPASS_TEST_RATIO = 0.0, 0.02


def ekf_status_report(v: TelemetryView, codec):
    """Flags for what the estimate knows; the velocity and horizontal position variances as the
    EKF check models them (the square roots of EKF3's GPS test ratios, 1 at its gate), held from
    the last fix while the EKF dead-reckons without one (measured: ArduCopter's stay where they
    were), nothing once it holds a constant position."""
    if not v.attitude_known():  # a realistic start-up before the EKF has aligned
        return codec.ekf_status_report_encode(mav.EKF_UNINITIALIZED, 1.0, 1.0, 1.0, 1.0, 0.0)
    velocity, position = v.ekf_test_ratios
    if v.has_position():
        flags = EKF_GOOD
    elif v.ekf_aiding():
        flags = EKF_NO_POSITION  # the last fix's ratios held
    else:  # fusing a constant position: its ratios, nothing (measured 0.00-0.01)
        flags, velocity, position = EKF_CONSTANT_POSITION, 0.0, 0.0
    if v.terrain_height_known():
        flags |= mav.EKF_POS_VERT_AGL
    if v.gps_glitching:
        flags |= EKF_GPS_GLITCH
    return codec.ekf_status_report_encode(flags, velocity, position, HEIGHT_TEST_RATIO, COMPASS_TEST_RATIO, 0.0)


# msg id -> builder(vehicle, codec): the message, or None when there is nothing to send.
Builder = Callable[[StreamedView, Any], Any]
BUILDERS: dict[int, Builder] = {
    mav.MAVLINK_MSG_ID_HEARTBEAT: heartbeat,
    mav.MAVLINK_MSG_ID_SYS_STATUS: sys_status,
    mav.MAVLINK_MSG_ID_BATTERY_STATUS: battery_status,
    mav.MAVLINK_MSG_ID_GLOBAL_POSITION_INT: global_position_int,
    mav.MAVLINK_MSG_ID_LOCAL_POSITION_NED: local_position_ned,
    mav.MAVLINK_MSG_ID_GPS_RAW_INT: gps_raw_int,
    mav.MAVLINK_MSG_ID_ATTITUDE: attitude,
    mav.MAVLINK_MSG_ID_ATTITUDE_QUATERNION: attitude_quaternion,
    mav.MAVLINK_MSG_ID_VFR_HUD: vfr_hud,
    mav.MAVLINK_MSG_ID_HOME_POSITION: home_position,
    mav.MAVLINK_MSG_ID_GPS_GLOBAL_ORIGIN: gps_global_origin,
    mav.MAVLINK_MSG_ID_EXTENDED_SYS_STATE: extended_sys_state,
    mav.MAVLINK_MSG_ID_SYSTEM_TIME: system_time,
    mav.MAVLINK_MSG_ID_MISSION_CURRENT: mission_current,
    mav.MAVLINK_MSG_ID_FENCE_STATUS: fence_status,
    mav.MAVLINK_MSG_ID_AUTOPILOT_VERSION: autopilot_version,
    mav.MAVLINK_MSG_ID_EKF_STATUS_REPORT: ekf_status_report,
    mav.MAVLINK_MSG_ID_NAMED_VALUE_FLOAT: ground_temperature,
    **SENSOR_BUILDERS,
    **TERRAIN_BUILDERS,
    **CAMERA_BUILDERS,
    **MOUNT_BUILDERS,
    **RANGEFINDER_BUILDERS,
    **OPTICAL_FLOW_BUILDERS,
    **ADSB_BUILDERS,
    **WINCH_BUILDERS,
}

# ArduPilot's stream groups (REQUEST_DATA_STREAM ids), the MAV1_ parameter that sets each rate,
# and their messages, as ArduCopter fills them (GCS_MAVLink_Parameters.cpp) for what Firefly has.
_ID = mav.__dict__
ADSB_STREAM = -1
_STREAM_GROUP_NAMES = {
    mav.MAV_DATA_STREAM_RAW_SENSORS: ("MAV1_RAW_SENS", ("RAW_IMU", "SCALED_IMU2", "SCALED_IMU3",
                                                      "SCALED_PRESSURE", "SCALED_PRESSURE2")),
    mav.MAV_DATA_STREAM_EXTENDED_STATUS: ("MAV1_EXT_STAT", ("SYS_STATUS", "POWER_STATUS", "MEMINFO",
                                                          "MISSION_CURRENT", "GPS_RAW_INT",
                                                          "NAV_CONTROLLER_OUTPUT", "FENCE_STATUS",
                                                          "POSITION_TARGET_GLOBAL_INT")),
    mav.MAV_DATA_STREAM_POSITION: ("MAV1_POSITION", ("GLOBAL_POSITION_INT", "LOCAL_POSITION_NED")),
    mav.MAV_DATA_STREAM_RC_CHANNELS: ("MAV1_RC_CHAN", ("SERVO_OUTPUT_RAW", "RC_CHANNELS")),
    # ATTITUDE_QUATERNION is Firefly's addition to EXTRA1 (ArduCopter sends it only when asked).
    mav.MAV_DATA_STREAM_EXTRA1: ("MAV1_EXTRA1", ("ATTITUDE", "ATTITUDE_QUATERNION", "SIMSTATE", "AHRS2",
                                               "ESC_TELEMETRY_1_TO_4", "WINCH_STATUS")),
    mav.MAV_DATA_STREAM_EXTRA2: ("MAV1_EXTRA2", ("VFR_HUD",)),
    # EXTENDED_SYS_STATE is Firefly's addition to EXTRA3 (ArduCopter sends it only when asked).
    mav.MAV_DATA_STREAM_EXTRA3: ("MAV1_EXTRA3", ("AHRS", "WIND", "RANGEFINDER", "DISTANCE_SENSOR",
                                               "SYSTEM_TIME", "TERRAIN_REPORT",
                                               "TERRAIN_REQUEST", "BATTERY_STATUS", "OPTICAL_FLOW", "EKF_STATUS_REPORT",
                                               "VIBRATION", "EXTENDED_SYS_STATE",
                                               "GIMBAL_DEVICE_ATTITUDE_STATUS")),
    # ArduPilot's ADSB stream has no REQUEST_DATA_STREAM id of its own: only MAV_DATA_STREAM_ALL
    # (0) and MAV1_ADSB reach it, so its key here is one no request names.
    ADSB_STREAM: ("MAV1_ADSB", ("ADSB_VEHICLE",)),
}
STREAM_GROUPS: dict[int, tuple[str, tuple[int, ...]]] = {
    group: (param, tuple(_ID[f"MAVLINK_MSG_ID_{name}"] for name in names))
    for group, (param, names) in _STREAM_GROUP_NAMES.items()}
# What Firefly streams before any client asks (ArduCopter streams nothing unasked): what a ground
# station shows of a vehicle. The rest of each group comes once a client asks for the group.
UNASKED = frozenset(_ID[f"MAVLINK_MSG_ID_{name}"] for name in (
    "SCALED_PRESSURE", "SYS_STATUS", "MISSION_CURRENT", "GPS_RAW_INT", "GLOBAL_POSITION_INT",
    "LOCAL_POSITION_NED", "ATTITUDE", "ATTITUDE_QUATERNION", "VFR_HUD", "SYSTEM_TIME", "BATTERY_STATUS",
    "EKF_STATUS_REPORT", "EXTENDED_SYS_STATE"))
# Sent no more often than this whatever the stream rate asks.
MIN_INTERVAL_S = {mav.MAVLINK_MSG_ID_TERRAIN_REQUEST: REQUEST_MIN_INTERVAL_S}
# Always streamed regardless of groups: heartbeat at 1 Hz, home position at 0.5 Hz.
# The ground temperature goes out at the sensor's own 10 Hz so every sample reaches the client.
FIXED_RATES_HZ = {mav.MAVLINK_MSG_ID_HEARTBEAT: 1.0, mav.MAVLINK_MSG_ID_HOME_POSITION: 0.5,
                  mav.MAVLINK_MSG_ID_NAMED_VALUE_FLOAT: 10.0}


def mode_name(number: int) -> str:
    cls = MODE_BY_NUMBER.get(number)
    return cls.name if cls else str(number)

"""Raw sensor, subsystem and navigator telemetry that ArduCopter streams with the others: the IMU
(RAW_IMU, SCALED_IMU2/3), the second barometer, the attitude estimators (AHRS, AHRS2), the
simulator's truth (SIMSTATE), vibration, wind, power and memory, RC input, servo and ESC outputs
and the navigation controller's targets. Field conventions and the values of things Firefly does
not model (memory, board voltage) are ArduCopter SITL's, as measured on it.
"""
from __future__ import annotations

import math

from firefly.sim.airframe import GRAVITY_M_S2
from firefly.sim.rigid_body import euler_from_quaternion

from ..control.attitude import wrap_pi
from ..motor_outputs import in_output_order
from ..views import SensorView
from .dialect import mavlink as mav
from .encoding import deg_e7, time_boot_ms, u16

MILLI_G = 1000.0 / GRAVITY_M_S2  # accelerations go out in milli-g, as ArduPilot scales them
# ArduCopter SITL's MEMINFO and POWER_STATUS: memory it never runs out of, a 5 V board rail.
FREE_MEMORY_16, FREE_MEMORY_32 = 65535, 524288
BOARD_VCC_MV = 5000
RC_CHANNELS_USED = 8
ESC_TEMPERATURE_C = 32  # what ArduCopter SITL's simulated ESCs report; Firefly models no ESC heat


def air_temperature_cdeg(v: SensorView) -> int:
    """The standard atmosphere's temperature at the vehicle's altitude [centi-degrees C]."""
    return int(round((15.0 - 0.0065 * v.position_global().alt_m) * 100))


def _imu_fields(v: SensorView) -> tuple[int, ...]:
    """(xacc, yacc, zacc [mg], xgyro, ygyro, zgyro [mrad/s], xmag, ymag, zmag [mgauss])."""
    b = v.body
    acc = tuple(int(round(a * MILLI_G)) for a in v.accel_body)
    gyro = tuple(int(round(w * 1000.0)) for w in (b.p_rad_s, b.q_rad_s, b.r_rad_s))
    mag = tuple(int(round(m)) for m in v.mag_body_mgauss)
    return acc + gyro + mag


def raw_imu(v: SensorView, codec):
    return codec.raw_imu_encode(int(v.time_s * 1e6), *_imu_fields(v), 0, air_temperature_cdeg(v))


def scaled_imu2(v: SensorView, codec):
    """The second IMU: Firefly simulates one, and reports it here too."""
    return codec.scaled_imu2_encode(time_boot_ms(v), *_imu_fields(v), air_temperature_cdeg(v))


def scaled_imu3(v: SensorView, codec):
    """As ArduCopter SITL: a third compass without a third IMU (inertial fields zero)."""
    mag = _imu_fields(v)[6:]
    return codec.scaled_imu3_encode(time_boot_ms(v), 0, 0, 0, 0, 0, 0, *mag, 0)


def _barometer_fields(v: SensorView) -> tuple[float, float, int, int]:
    """The barometer as ArduPilot reports it: absolute pressure [hPa], differential pressure and
    temperature [cdegC] of the International Standard Atmosphere at the altitude the (possibly
    drifting) sensor reads, and no differential sensor's temperature."""
    alt_m = v.origin.alt_m + v.baro_alt_m
    pressure_hpa = 1013.25 * (1.0 - 2.25577e-5 * alt_m) ** 5.25588
    return pressure_hpa, 0.0, int(round((15.0 - 0.0065 * alt_m) * 100)), 0


def scaled_pressure(v: SensorView, codec):
    return codec.scaled_pressure_encode(time_boot_ms(v), *_barometer_fields(v))


def scaled_pressure2(v: SensorView, codec):
    """The second barometer: Firefly simulates one, and reports it here too."""
    return codec.scaled_pressure2_encode(time_boot_ms(v), *_barometer_fields(v))


def ahrs(v: SensorView, codec):
    """DCM's gyro drift and error terms: Firefly's estimate has no drift, so zeros."""
    return codec.ahrs_encode(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


def ahrs2(v: SensorView, codec):
    roll, pitch, yaw = v.attitude
    pos = v.position_global()
    return codec.ahrs2_encode(roll, pitch, yaw, pos.alt_m, deg_e7(pos.lat_deg), deg_e7(pos.lon_deg))


def simstate(v: SensorView, codec):
    """The simulator's truth (not the estimate): attitude, accelerations [m/s^2], rates, place."""
    body = v.true_body
    roll, pitch, yaw = euler_from_quaternion(body.qw, body.qx, body.qy, body.qz)
    ax, ay, az = v.accel_body
    true_pos = v.ned_to_global(body.n_m, body.e_m, body.d_m)
    return codec.simstate_encode(roll, pitch, yaw, ax, ay, az, body.p_rad_s, body.q_rad_s, body.r_rad_s,
                                 deg_e7(true_pos.lat_deg), deg_e7(true_pos.lon_deg))


def vibration(v: SensorView, codec):
    """Firefly's rotors and frame do not vibrate and its accelerometer never clips."""
    return codec.vibration_encode(int(v.time_s * 1e6), 0.0, 0.0, 0.0, 0, 0, 0)


DRAG_FUSION = ("EK3_DRAG_BCOEF_X", "EK3_DRAG_BCOEF_Y", "EK3_DRAG_MCOEF")


def wind(v: SensorView, codec):
    """Where the wind blows from [deg, -180..180 as ArduPilot sends it], its horizontal speed and
    its vertical speed (positive up), as ArduCopter estimates it: only when its EKF fuses the
    rotors' drag (any of DRAG_FUSION above zero) and only in the air; otherwise zero (measured,
    parity area `wind`: 0 with a 5 m/s wind blowing, and on the ground with drag fusion on)."""
    params = v.params
    if v.landed or not any(params[name] > 0.0 for name in DRAG_FUSION):
        wn = we = wd = 0.0
    else:
        wn, we, wd = v.wind_ned
    return codec.wind_encode(math.degrees(math.atan2(-we, -wn)), math.hypot(wn, we), -wd)


def meminfo(v: SensorView, codec):
    return codec.meminfo_encode(0, FREE_MEMORY_16, FREE_MEMORY_32)


def power_status(v: SensorView, codec):
    return codec.power_status_encode(BOARD_VCC_MV, 0, 0)


def rc_pwm(v: SensorView) -> list[int]:
    """The 16 channels as the radio last read them (autopilot/rc/radio.py): the receiver's 8, or
    the ground station's overrides while they last (channels 9-16 read 0 but overridden)."""
    return list(v.rc_channels_us())


def rc_channels(v: SensorView, codec):
    """All 16 channels, and the receiver's channel count (8) as ArduPilot's valid count."""
    chans = rc_pwm(v)
    return codec.rc_channels_encode(time_boot_ms(v), RC_CHANNELS_USED, *chans, *([0] * (18 - len(chans))), 255)


def motor_pwm(v: SensorView) -> list[int]:
    """Each motor's PWM as ArduCopter's motor library makes it, on its outputs (motor_outputs.py): thrust as a fraction of the most
    a rotor gives, turned into throttle through the MOT_THST_EXPO curve, spread over
    MOT_SPIN_MIN..MOT_SPIN_MAX of the MOT_PWM_MIN..MOT_PWM_MAX range; MOT_PWM_MIN disarmed, and for
    a motor commanded to stop (armed with the motors shut down: the arming delay, emergency stop,
    THROW waiting); MOT_SPIN_ARM at ground idle."""
    if v.safety_on:  # SITL's safety switch writes 0 us to every motor output
        return [0] * 4
    test = v.motor_test_pwm
    if test is not None:  # a motor test writes the outputs itself
        return test
    params = v.params
    low, high = v.pwm_range
    if not v.armed:
        return [low] * 4
    expo, spin_min, spin_max = params["MOT_THST_EXPO"], params["MOT_SPIN_MIN"], params["MOT_SPIN_MAX"]
    out = []
    idle = v.omega_idle_rad_s
    for omega in in_output_order(v.motor_commands):
        if omega <= 0.0:
            out.append(low)
            continue
        if omega == idle:  # at ground idle: ArduCopter's MOT_SPIN_ARM, reached MOT_SPOOL_TIME after the arming delay
            spool = params["MOT_SPOOL_TIME"]
            share = max(0.0, min(1.0, (v.time_s - v.interlock_at_s) / spool)) if spool > 0.0 else 1.0
            out.append(int(round(low + (high - low) * params["MOT_SPIN_ARM"] * share)))
            continue
        thrust = min(max(omega / v.omega_max_rad_s, 0.0), 1.0) ** 2
        throttle = thrust if expo <= 0 else \
            ((expo - 1.0) + math.sqrt((1.0 - expo) ** 2 + 4.0 * expo * thrust)) / (2.0 * expo)
        out.append(int(round(low + (high - low) * (spin_min + (spin_max - spin_min) * throttle))))
    return out


def servo_output_raw(v: SensorView, codec):
    servos = motor_pwm(v) + v.servo_pwm[4:]  # the quad's motors on 1-4, then what events set
    return codec.servo_output_raw_encode(int(v.time_s * 1e6) & 0xFFFFFFFF, 0, *servos)


def esc_telemetry_1_to_4(v: SensorView, codec):
    """Each ESC's voltage, a quarter of the pack current and charge, and its rotor's speed."""
    batt = v.battery
    rpm = [u16(round(w * 60.0 / (2.0 * math.pi))) for w in in_output_order(v.motor_speeds_rad_s)]
    count = int(v.time_s * 10) & 0xFFFF  # reports received: one per 100 ms of vehicle time
    return codec.esc_telemetry_1_to_4_encode(
        [ESC_TEMPERATURE_C] * 4, [u16(batt.voltage_v * 100)] * 4,
        [u16(batt.current_a * 25)] * 4, [u16(batt.consumed_mah / 4)] * 4, rpm, [count] * 4)


def nav_controller_output(v: SensorView, codec):
    """The lean the position loop asks for [deg], the heading wanted, the bearing and distance to
    the mode's destination and the height still to go (ArduCopter fills xtrack only for planes)."""
    roll_t, pitch_t = v.lean_target
    b = v.body
    dest = v.destination()
    bearing, dist, alt_error = 0, 0, 0.0
    if dest is not None:
        dn, de = dest[0] - b.n_m, dest[1] - b.e_m
        dist = min(int(math.hypot(dn, de)), 65535)
        bearing = int(round(math.degrees(math.atan2(de, dn))))
        if dest[2] is not None:
            alt_error = b.d_m - dest[2]
    reported = v.nav_distance_bearing()
    if reported is not None:
        dist = min(int(reported[0]), 65535)
        bearing = max(-32768, min(32767, int(reported[1])))  # an int16 field
    nav_bearing = int(round(math.degrees(wrap_pi(v.yaw_target))))  # an int16 field
    return codec.nav_controller_output_encode(math.degrees(roll_t), math.degrees(pitch_t), nav_bearing, bearing,
                                              dist, alt_error, 0.0, 0.0)


# ArduCopter sends only a target's position (velocity, acceleration and yaw marked ignored).
POSITION_ONLY = (mav.POSITION_TARGET_TYPEMASK_VX_IGNORE | mav.POSITION_TARGET_TYPEMASK_VY_IGNORE
                 | mav.POSITION_TARGET_TYPEMASK_VZ_IGNORE | mav.POSITION_TARGET_TYPEMASK_AX_IGNORE
                 | mav.POSITION_TARGET_TYPEMASK_AY_IGNORE | mav.POSITION_TARGET_TYPEMASK_AZ_IGNORE
                 | mav.POSITION_TARGET_TYPEMASK_YAW_IGNORE | mav.POSITION_TARGET_TYPEMASK_YAW_RATE_IGNORE | 0xF000)


def position_target_global_int(v: SensorView, codec):
    """Where the mode flies to, above sea level; not sent when it flies to nowhere (as
    ArduCopter's, which sends it only when the mode has a waypoint)."""
    dest = v.destination()
    if dest is None:
        return None
    n, e, d = dest
    target = v.ned_to_global(n, e, v.body.d_m if d is None else d)
    if not (abs(target.lat_deg) <= 90 and abs(target.lon_deg) <= 180 and abs(target.alt_m) < 1e30):
        return None  # a target thousands of km away (a hostile setpoint) has no place on the globe
    return codec.position_target_global_int_encode(
        time_boot_ms(v), mav.MAV_FRAME_GLOBAL, POSITION_ONLY, deg_e7(target.lat_deg),
        deg_e7(target.lon_deg), target.alt_m, 0, 0, 0, 0, 0, 0, 0, 0)


def relay_status(v: SensorView, codec):
    """The relays present and on: asked for only (no stream carries it, measured)."""
    present, on = v.relay_masks()
    return codec.relay_status_encode(time_boot_ms(v), on, present)


BUILDERS = {
    mav.MAVLINK_MSG_ID_RELAY_STATUS: relay_status,
    mav.MAVLINK_MSG_ID_RAW_IMU: raw_imu,
    mav.MAVLINK_MSG_ID_SCALED_IMU2: scaled_imu2,
    mav.MAVLINK_MSG_ID_SCALED_IMU3: scaled_imu3,
    mav.MAVLINK_MSG_ID_SCALED_PRESSURE: scaled_pressure,
    mav.MAVLINK_MSG_ID_SCALED_PRESSURE2: scaled_pressure2,
    mav.MAVLINK_MSG_ID_AHRS: ahrs,
    mav.MAVLINK_MSG_ID_AHRS2: ahrs2,
    mav.MAVLINK_MSG_ID_SIMSTATE: simstate,
    mav.MAVLINK_MSG_ID_VIBRATION: vibration,
    mav.MAVLINK_MSG_ID_WIND: wind,
    mav.MAVLINK_MSG_ID_MEMINFO: meminfo,
    mav.MAVLINK_MSG_ID_POWER_STATUS: power_status,
    mav.MAVLINK_MSG_ID_RC_CHANNELS: rc_channels,
    mav.MAVLINK_MSG_ID_SERVO_OUTPUT_RAW: servo_output_raw,
    mav.MAVLINK_MSG_ID_ESC_TELEMETRY_1_TO_4: esc_telemetry_1_to_4,
    mav.MAVLINK_MSG_ID_NAV_CONTROLLER_OUTPUT: nav_controller_output,
    mav.MAVLINK_MSG_ID_POSITION_TARGET_GLOBAL_INT: position_target_global_int,
}

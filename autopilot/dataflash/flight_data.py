"""The flight data records: what each periodic log message holds, read from the vehicle through
the same typed view telemetry reads (views.StreamedView), and the state estimate's body, read
once for all the records of a tick. Each builder returns its message's
values after TimeUS (and after the instance number, for a message logged per instance, as IMU and
BARO are), scaled as the message's format characters want them (encoding.py).

Firefly keeps no rate-loop targets or rate-loop outputs, no acceleration targets and no
rangefinder or terrain height: those fields are NaN, as ArduPilot writes a value it does not have
(its quiet_nan). Desired positions and velocities are the current mode's destination where it
has one, else the vehicle's own state, as ArduCopter's position controller reports them at rest.
"""
from __future__ import annotations

import math

from firefly.sim.rigid_body import BodyState

from ..mavlink.sensor_messages import motor_pwm, rc_pwm
from ..views import StreamedView

NAN = float("nan")
DEG = 180.0 / math.pi
AEKF_EKF3 = 3  # the active estimator ArduCopter reports: EKF3
IMU_INSTANCES = 2  # as ArduCopter SITL logs: two IMUs (Firefly simulates one and logs it twice)
IMU_SAMPLE_HZ = 1000  # ArduCopter SITL's first IMU's gyro and accelerometer rates (its IMU record)
BARO_INSTANCES = 2  # likewise two barometers
GPS_HDOP = 80  # hundredths: the eph Firefly's GPS_RAW_INT reports
GPS_EPOCH_UNIX_S = 315_964_800  # 1980-01-06
GPS_LEAP_S = 18
WEEK_MS = 7 * 86_400_000
ISA_SEA_LEVEL_PA = 101_325.0
RC_CHANNELS = 14
TEMPERATURE_C = 25.0  # the IMU and battery temperatures Firefly does not model


def _heading_deg(rad: float) -> float:
    return math.degrees(rad) % 360.0


def _pressure_pa(alt_amsl_m: float) -> float:
    return ISA_SEA_LEVEL_PA * (1.0 - 2.25577e-5 * alt_amsl_m) ** 5.25588


def att(v: StreamedView, b: BodyState) -> tuple:
    roll, pitch, yaw = v.attitude
    des_roll, des_pitch = v.lean_target
    return (des_roll * DEG, roll * DEG, des_pitch * DEG, pitch * DEG, _heading_deg(v.yaw_target),
            _heading_deg(yaw), AEKF_EKF3)


def rate(v: StreamedView, b: BodyState) -> tuple:
    throttle = v.thrust_demand_n / v.thrust_max_n
    return (NAN, b.p_rad_s * DEG, NAN, NAN, b.q_rad_s * DEG, NAN, NAN, b.r_rad_s * DEG, NAN,
            NAN, NAN, throttle, throttle)


def pos(v: StreamedView, b: BodyState) -> tuple:
    p = v.position_global()
    home = v.home
    rel_home = p.alt_m - (home.alt_m if home is not None else v.origin.alt_m)
    return (round(p.lat_deg * 1e7), round(p.lon_deg * 1e7), p.alt_m, rel_home,
            p.alt_m - v.ekf_origin().alt_m)


def gps_week_time(unix_us: int) -> tuple[int, int]:
    """(milliseconds into the GPS week, GPS week) of a UTC time."""
    gps_ms = (unix_us // 1000) - (GPS_EPOCH_UNIX_S - GPS_LEAP_S) * 1000
    return gps_ms % WEEK_MS, gps_ms // WEEK_MS


def gps(v: StreamedView, b: BodyState) -> tuple:
    g = v.gps
    p = v.ned_to_global(g.n_m, g.e_m, g.d_m)
    speed = math.hypot(g.vn_m_s, g.ve_m_s)
    course = _heading_deg(math.atan2(g.ve_m_s, g.vn_m_s)) if speed > 0.2 else 0.0
    week_ms, week = gps_week_time(v.unix_time_us())
    return (0, g.fix_type, week_ms, week, g.satellites, GPS_HDOP,
            round(p.lat_deg * 1e7), round(p.lon_deg * 1e7), round(p.alt_m * 100), speed, course,
            g.vd_m_s, 0.0, 1)


def baro(v: StreamedView, b: BodyState) -> tuple:
    alt = v.baro_alt_m
    amsl = v.origin.alt_m + alt
    press = _pressure_pa(amsl)
    temp = round((15.0 - 0.0065 * amsl) * 100)
    ground_c = 15.0 - 0.0065 * v.origin.alt_m
    return (alt, amsl, press, temp, -b.vd_m_s, int(v.time_s * 1000) & 0xFFFFFFFF, 0.0, ground_c, 1, press)


def imu(v: StreamedView, b: BodyState) -> tuple:
    ax, ay, az = v.accel_body
    return (b.p_rad_s, b.q_rad_s, b.r_rad_s, ax, ay, az, 0, 0, TEMPERATURE_C, 1, 1, IMU_SAMPLE_HZ, IMU_SAMPLE_HZ)


def bat(v: StreamedView, b: BodyState) -> tuple:
    batt = v.battery
    remaining = max(0, min(100, round(v.battery_remaining * 100)))
    return (0, batt.voltage_v, batt.voltage_v, batt.current_a, batt.consumed_mah, NAN,
            round(TEMPERATURE_C * 100), 0.0, remaining, 1, 0)


def ctun(v: StreamedView, b: BodyState) -> tuple:
    throttle_in = v.pilot.throttle
    home_d = v.home_ned[2] if v.home_ned is not None else b.d_m
    alt = home_d - b.d_m
    target = v.destination()
    desired = alt if target is None or target[2] is None else home_d - target[2]
    return (throttle_in, 0.0, v.thrust_demand_n / v.thrust_max_n, v.params["MOT_THST_HOVER"],
            desired, alt, round(v.baro_alt_m * 100), NAN, NAN, NAN, 0, round(-b.vd_m_s * 100))


def _psc(v: StreamedView, b: BodyState, axis: int) -> tuple:
    """PSCN (axis 0), PSCE (1), PSCD (2): desired, target and actual position, velocity and
    acceleration on one axis of the local frame."""
    n, e = v.local_ne(b.n_m, b.e_m)
    here = (n, e, b.d_m)[axis]
    vel = (b.vn_m_s, b.ve_m_s, b.vd_m_s)[axis]
    target = v.destination()
    if target is not None and (axis < 2 or target[2] is not None):
        tn, te = v.local_ne(target[0], target[1])
        want = (tn, te, target[2])[axis]
    else:
        want = here
    return (want, want, here, NAN, NAN, vel, NAN, NAN, NAN)


def pscn(v: StreamedView, b: BodyState) -> tuple:
    return _psc(v, b, 0)


def psce(v: StreamedView, b: BodyState) -> tuple:
    return _psc(v, b, 1)


def pscd(v: StreamedView, b: BodyState) -> tuple:
    return _psc(v, b, 2)


def rcin(v: StreamedView, b: BodyState) -> tuple:
    chans = rc_pwm(v)[:RC_CHANNELS]
    return (*chans, *[0] * (RC_CHANNELS - len(chans)))


def optical_flow(v: StreamedView, b: BodyState) -> tuple:
    """OF: the flow sensor's last sample as AP_OpticalFlow logs it, its quality, flow and body rates."""
    r = v.optical_flow.reading
    return r.quality, r.flow_x, r.flow_y, r.body_x, r.body_y


def rcou(v: StreamedView, b: BodyState) -> tuple:
    return (*motor_pwm(v), *[0] * (RC_CHANNELS - 4))

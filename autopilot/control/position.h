/* C twin of position.py: position -> velocity (square-root shaping, slewed) -> acceleration ->
 * lean angles, and altitude -> climb rate -> vertical acceleration -> U1. NaN stands for None. */
#ifndef FIREFLY_POSITION_H
#define FIREFLY_POSITION_H

#include "pid.h"

#define GRAVITY_M_S2 9.80665
#define MEASURED_D_HZ 20.0 /* position.py's */

typedef struct {
    double mass, weight, thrust_max; /* from the airframe */
    double pos_xy_p, pos_z_p, accel_xy_max, lean_max, speed_up, speed_dn, accel_z_max, vel_fltd_hz;
    Pid vel_n, vel_e, vel_d;
    double vel_target_ne[2], vel_target_d;
} PositionController;

static double sqrt_controller(double error, double p, double accel_max)
{
    if (accel_max <= 0.0 || p <= 0.0)
        return error * p;
    double linear = accel_max / (p * p);
    if (fabs(error) <= linear)
        return error * p;
    return copysign(sqrt(2.0 * accel_max * (fabs(error) - linear / 2.0)), error);
}

static void position_reset(PositionController *pc, double vn, double ve, double vd)
{
    pc->vel_target_ne[0] = vn, pc->vel_target_ne[1] = ve;
    pc->vel_target_d = vd;
    pid_reset(&pc->vel_n), pid_reset(&pc->vel_e), pid_reset(&pc->vel_d);
}

static void lean_from_accel(const PositionController *pc, double an, double ae, double yaw, double lean[2])
{
    double a_max = GRAVITY_M_S2 * tan(pc->lean_max);
    double a = sqrt(an * an + ae * ae);
    if (a > a_max)
        an = an * a_max / a, ae = ae * a_max / a;
    double cy = cos(yaw), sy = sin(yaw);
    double a_fwd = an * cy + ae * sy;
    double a_right = -an * sy + ae * cy;
    double pitch = atan2(-a_fwd, GRAVITY_M_S2);
    lean[0] = atan2(a_right * cos(pitch), GRAVITY_M_S2);
    lean[1] = pitch;
}

/* (roll, pitch) targets; pos_t NaN = velocity control on vel_ff; accel_ff NaN = none (slewed
 * velocity target), else a shaped trajectory's acceleration, fed forward. */
static void position_horizontal(PositionController *pc, const double pos_t[2], const double vel_ff[2],
                                const double accel_ff[2], double speed_max, const double pos[2],
                                const double vel[2], double yaw, double dt, double lean[2])
{
    double vn_d = vel_ff[0], ve_d = vel_ff[1];
    if (!isnan(pos_t[0])) {
        double en = pos_t[0] - pos[0], ee = pos_t[1] - pos[1];
        double dist = sqrt(en * en + ee * ee);
        if (dist > 1e-6) {
            double v = sqrt_controller(dist, pc->pos_xy_p, pc->accel_xy_max);
            vn_d += v * en / dist;
            ve_d += v * ee / dist;
        }
    }
    double speed = sqrt(vn_d * vn_d + ve_d * ve_d);
    if (speed > speed_max && speed_max > 0.0)
        vn_d = vn_d * speed_max / speed, ve_d = ve_d * speed_max / speed;
    /* D on the error for a shaped trajectory, on the measurement for a slewed target (position.py) */
    double on_error = isnan(accel_ff[0]) ? 0.0 : 1.0;
    double d_hz = isnan(accel_ff[0]) ? MEASURED_D_HZ : pc->vel_fltd_hz;
    pid_set_d_on_error(&pc->vel_n, on_error, d_hz);
    pid_set_d_on_error(&pc->vel_e, on_error, d_hz);
    if (!isnan(accel_ff[0])) {
        pc->vel_target_ne[0] = vn_d, pc->vel_target_ne[1] = ve_d;
        double an = accel_ff[0] + pid_update(&pc->vel_n, vn_d, vel[0], dt);
        double ae = accel_ff[1] + pid_update(&pc->vel_e, ve_d, vel[1], dt);
        lean_from_accel(pc, an, ae, yaw, lean);
        return;
    }
    double dn = vn_d - pc->vel_target_ne[0], de = ve_d - pc->vel_target_ne[1];
    double change = sqrt(dn * dn + de * de);
    double step = pc->accel_xy_max * dt;
    if (change > step)
        dn = dn * step / change, de = de * step / change;
    pc->vel_target_ne[0] += dn;
    pc->vel_target_ne[1] += de;
    double an = dn / dt + pid_update(&pc->vel_n, pc->vel_target_ne[0], vel[0], dt);
    double ae = de / dt + pid_update(&pc->vel_e, pc->vel_target_ne[1], vel[1], dt);
    lean_from_accel(pc, an, ae, yaw, lean);
}

static double thrust_for(const PositionController *pc, double accel_d, double roll, double pitch)
{
    double tilt = py_max(cos(roll) * cos(pitch), 0.5);
    double u1 = pc->mass * (GRAVITY_M_S2 - accel_d) / tilt;
    return py_max(0.0, py_min(pc->thrust_max, u1));
}

/* Total thrust U1; pos_d_t NaN = climb-rate control on vel_d_ff, speed_dn NaN = WPNAV_SPEED_DN. */
static double position_vertical(PositionController *pc, double pos_d_t, double vel_d_ff, double pos_d,
                                double vel_d, double roll, double pitch, double dt, double speed_dn)
{
    double up = pc->speed_up;
    double dn = isnan(speed_dn) ? pc->speed_dn : speed_dn;
    double vd_t = vel_d_ff;
    if (!isnan(pos_d_t))
        vd_t += sqrt_controller(pos_d_t - pos_d, pc->pos_z_p, pc->accel_z_max);
    vd_t = py_max(-up, py_min(dn, vd_t));
    double step = pc->accel_z_max * 2.0 * dt; /* _slew(current, desired, limit, dt) */
    pc->vel_target_d = pc->vel_target_d + py_max(-step, py_min(step, vd_t - pc->vel_target_d));
    double accel_d = pid_update(&pc->vel_d, pc->vel_target_d, vel_d, dt);
    return thrust_for(pc, accel_d, roll, pitch);
}

static double thrust_from_stick(const PositionController *pc, double stick)
{
    double hover = pc->weight;
    if (stick <= 0.5)
        return 2.0 * stick * hover;
    return hover + (stick - 0.5) * 2.0 * (pc->thrust_max - hover);
}

#endif

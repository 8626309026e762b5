/* C twin of attitude.py: angle P -> Euler-rate targets -> body-rate targets -> rate PIDs ->
 * torques U2..U4. The cascade always gives a heading target (yaw_t is never None here). */
#ifndef FIREFLY_ATTITUDE_H
#define FIREFLY_ATTITUDE_H

#include "pid.h"

typedef struct {
    double roll_torque_max, pitch_torque_max, yaw_torque_max; /* from the airframe */
    double angle_p[3], rp_rate_max, yaw_rate_max;             /* from parameters */
    Pid rate[3];                                              /* roll, pitch, yaw */
} AttitudeController;

static inline double wrap_pi(double angle) { return py_mod(angle + PY_PI, 2.0 * PY_PI) - PY_PI; }

static void attitude_reset(AttitudeController *a)
{
    for (int i = 0; i < 3; i++)
        pid_reset(&a->rate[i]);
}

/* The rate loop alone: body-rate targets (p, q, r) [rad/s] -> torques (attitude.py rate_update). */
static void attitude_rate_update(AttitudeController *a, const double targets[3], const double rates[3], double dt,
                                 double torques[3])
{
    double out_r = pid_update(&a->rate[0], targets[0], rates[0], dt);
    double out_p = pid_update(&a->rate[1], targets[1], rates[1], dt);
    double out_y = pid_update(&a->rate[2], targets[2], rates[2], dt);
    torques[0] = out_r * a->roll_torque_max;
    torques[1] = out_p * a->pitch_torque_max;
    torques[2] = out_y * a->yaw_torque_max;
}

static void attitude_update(AttitudeController *a, double roll_t, double pitch_t, double yaw_t,
                            double yaw_rate_t, double roll, double pitch, double yaw,
                            const double rates[3], double dt, double torques[3])
{
    double rl = a->rp_rate_max;
    double roll_dot = py_max(-rl, py_min(rl, a->angle_p[0] * (roll_t - roll)));
    double pitch_dot = py_max(-rl, py_min(rl, a->angle_p[1] * (pitch_t - pitch)));
    double yaw_dot = yaw_rate_t;
    yaw_dot += a->angle_p[2] * wrap_pi(yaw_t - yaw);
    double yl = a->yaw_rate_max;
    yaw_dot = py_max(-yl, py_min(yl, yaw_dot));
    double sr = sin(roll), cr = cos(roll);
    double sp = sin(pitch), cp = cos(pitch);
    double targets[3] = {roll_dot - sp * yaw_dot, cr * pitch_dot + sr * cp * yaw_dot, -sr * pitch_dot + cr * cp * yaw_dot};
    attitude_rate_update(a, targets, rates, dt, torques);
}

#endif

/* C twin of pid.py: derivative on measurement or (d_on_error) on the error, low-pass filtered;
 * integrator limit, anti-windup on output saturation. Same expressions, same order. */
#ifndef FIREFLY_PID_H
#define FIREFLY_PID_H

#include "pyfloat.h"

typedef struct {
    double kp, ki, kd, imax, out_limit, d_filter_hz, d_on_error; /* gains, set from parameters */
    double integrator, last_measurement, d_filtered; /* last_measurement: the D input last time */
    int has_last; /* False while _last_measurement is None */
} Pid;

static void pid_reset(Pid *pid)
{
    pid->integrator = py_max(-pid->imax, py_min(pid->imax, 0.0));
    pid->has_last = 0;
    pid->d_filtered = 0.0;
}

static void pid_set_d_on_error(Pid *pid, double on_error, double d_filter_hz)
{
    pid->d_filter_hz = d_filter_hz;
    if (on_error != pid->d_on_error) {
        pid->d_on_error = on_error;
        pid->has_last = 0;
        pid->d_filtered = 0.0;
    }
}

static double pid_update(Pid *pid, double target, double measurement, double dt)
{
    double error = target - measurement, d_term;
    double d_input = pid->d_on_error == 0.0 ? -measurement : error;
    if (!pid->has_last || pid->kd == 0.0) {
        d_term = 0.0;
    } else {
        double raw = (d_input - pid->last_measurement) / dt;
        double alpha = dt / (dt + 1.0 / (2.0 * PY_PI * pid->d_filter_hz));
        pid->d_filtered += alpha * (raw - pid->d_filtered);
        d_term = pid->kd * pid->d_filtered;
    }
    pid->last_measurement = d_input;
    pid->has_last = 1;
    double unsat = pid->kp * error + pid->integrator + d_term;
    double out = py_max(-pid->out_limit, py_min(pid->out_limit, unsat));
    if (out == unsat || (unsat > out) != (error > 0.0))
        pid->integrator = py_max(-pid->imax, py_min(pid->imax, pid->integrator + pid->ki * error * dt));
    return out;
}

#endif

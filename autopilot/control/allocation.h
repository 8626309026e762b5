/* C twin of allocation.py (and of sim.rotors.unmix): (U1..U4) -> motor speed commands, keeping
 * roll and pitch first and giving yaw what is left when motors saturate. */
#ifndef FIREFLY_ALLOCATION_H
#define FIREFLY_ALLOCATION_H

#include "pyfloat.h"

typedef struct {
    double l, c, b, f_max, f_min;
    int saturated;
} Allocator;

static double min4(const double x[4]) { return py_min(py_min(py_min(x[0], x[1]), x[2]), x[3]); }
static double max4(const double x[4]) { return py_max(py_max(py_max(x[0], x[1]), x[2]), x[3]); }

static void unmix(double u1, double u2, double u3, double u4, double l, double c, double f[4])
{
    double base = 0.25 * u1;
    double roll = u2 / (2.0 * l);
    double pitch = u3 / (2.0 * l);
    double yaw = u4 / (4.0 * c);
    f[0] = base + pitch + yaw, f[1] = base + roll - yaw, f[2] = base - pitch + yaw, f[3] = base - roll - yaw;
}

static void allocator_forces(Allocator *al, double u1, double u2, double u3, double u4, double f[4])
{
    const double f_min = al->f_min, f_max = al->f_max;
    static const double signs[4] = {1.0, -1.0, 1.0, -1.0};
    unmix(u1, u2, u3, u4, al->l, al->c, f);
    if (min4(f) >= f_min && max4(f) <= f_max) { /* feasible: no priorities needed */
        al->saturated = 0;
        return;
    }
    double roll = u2 / (2.0 * al->l), pitch = u3 / (2.0 * al->l);
    double rp[4] = {pitch, roll, -pitch, -roll};
    double base = u1 * 0.25;
    double lo = min4(rp), hi = max4(rp);
    double span = hi - lo;
    double scale = 1.0;
    if (span > f_max - f_min) {
        scale = (f_max - f_min) / span;
        lo = lo * scale, hi = hi * scale;
    }
    base = py_min(py_max(base, f_min - lo), f_max - hi);
    double yaw = u4 / (4.0 * al->c);
    double room = INFINITY;
    for (int i = 0; i < 4; i++) {
        f[i] = base + scale * rp[i];
        room = py_min(room, signs[i] * yaw > 0 ? f_max - f[i] : f[i] - f_min);
    }
    double yaw_used = copysign(py_min(fabs(yaw), py_max(room, 0.0)), yaw);
    al->saturated = scale < 1.0 || yaw_used != yaw || base != u1 * 0.25;
    for (int i = 0; i < 4; i++)
        f[i] = f[i] + signs[i] * yaw_used;
}

static void allocator_omega_commands(Allocator *al, double u1, double u2, double u3, double u4, double omega[4])
{
    double f[4];
    allocator_forces(al, u1, u2, u3, u4, f);
    for (int i = 0; i < 4; i++)
        omega[i] = sqrt(py_max(f[i], 0.0) / al->b);
}

#endif

/* C twin of sim/battery.py (open_circuit_volts_per_cell, step_battery) and of the pack's power
 * draw in sim/vehicle.py: the same expressions in the same order, so the very same bits
 * (tests/unit/test_compiled_battery.py checks them against the Python). */
#ifndef FIREFLY_BATTERY_H
#define FIREFLY_BATTERY_H

#include "pyfloat.h"

/* sim.battery._OCV_CURVE: (state of charge, open-circuit volts per cell). */
#define OCV_POINTS 12
static const double OCV_SOC[OCV_POINTS] = {0.0, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0};
static const double OCV_VOLTS[OCV_POINTS] = {3.27, 3.61, 3.69, 3.73, 3.77, 3.79, 3.82, 3.87, 3.92, 3.98, 4.06, 4.20};

typedef struct {
    double power_per_omega_cubed; /* electrical watts per sum of rotor speed cubed */
    double cells, capacity_mah, r_internal_ohm, extra_current_a, dt;
} BatteryConstants;

static double open_circuit_volts_per_cell(double soc)
{
    soc = soc < 0.0 ? 0.0 : soc > 1.0 ? 1.0 : soc;
    /* bisect_left(_SOC_POINTS, soc, 1, _LAST_SEGMENT): the first segment whose upper end is >= soc */
    int i = 1;
    while (i < OCV_POINTS - 1 && OCV_SOC[i] < soc)
        i++;
    double s0 = OCV_SOC[i - 1], v0 = OCV_VOLTS[i - 1];
    double dv = OCV_VOLTS[i] - v0, ds = OCV_SOC[i] - s0;
    return v0 + dv * (soc - s0) / ds;
}

/* state: consumed mAh, current A, voltage V, updated in place for one battery step at these rotor speeds. */
static void battery_step(double state[3], const double omega[4], const BatteryConstants *k)
{
    const double *o = omega;
    double power = k->power_per_omega_cubed * (o[0] * o[0] * o[0] + o[1] * o[1] * o[1] + o[2] * o[2] * o[2] + o[3] * o[3] * o[3]);
    double soc = 1.0 - state[0] / k->capacity_mah;
    double ocv = k->cells * open_circuit_volts_per_cell(soc);
    double disc = ocv * ocv - 4.0 * k->r_internal_ohm * power;
    double current = disc > 0 ? (ocv - pow(disc, 0.5)) / (2.0 * k->r_internal_ohm) : ocv / (2 * k->r_internal_ohm);
    current += k->extra_current_a;
    state[0] = state[0] + current * k->dt / 3.6;
    state[1] = current;
    state[2] = py_max(ocv - current * k->r_internal_ohm, 0.0);
}

#endif

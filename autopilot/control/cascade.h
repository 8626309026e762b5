/* C twin of cascade.py: between two flight-mode updates, the position loop every ratio_pos
 * physics steps, the attitude and rate loops every ratio_att steps, the allocation, and the
 * physics step (sim/physics.h). All state lives in one struct; nothing is allocated per step. */
#ifndef FIREFLY_CASCADE_H
#define FIREFLY_CASCADE_H

#include "allocation.h"
#include "attitude.h"
#include "physics.h"
#include "position.h"

typedef struct { /* the Setpoint handed over by command(); NaN = None */
    int armed, landed;
    double lean[2], pos_ne[2], vel_ne[2], accel_ne[2], speed_xy, throttle, pos_d, vel_d, speed_dn, yaw, yaw_rate;
    double rates[3]; /* body-rate targets replacing the angle loop (ACRO, FLIP) */
} Command;

typedef struct {
    Physics physics;
    PhysicsConstants physics_k;
    PositionController position;
    AttitudeController attitude;
    Allocator allocator;
    Command cmd;
    double omega_idle, dt_pos, dt_att;
    long long ratio_pos, ratio_att;
    double lean_t[2], thrust_t, yaw_t, omega_cmd[4];
} Cascade;

static int wants_climb(const Command *cmd, double d_m) /* Setpoint.wants_climb */
{
    if (!isnan(cmd->throttle))
        return cmd->throttle > 0.05;
    if (!isnan(cmd->pos_d))
        return cmd->pos_d < d_m - 0.2 || cmd->vel_d < -0.05;
    return cmd->vel_d < -0.05;
}

static int ground_idle(const Cascade *c, double d_m)
{
    if (!c->cmd.armed)
        return 1;
    if (c->cmd.landed)
        return !wants_climb(&c->cmd, d_m);
    return 0;
}

static void cascade_reset_position(Cascade *c)
{
    const Body *b = &c->physics.body;
    position_reset(&c->position, b->vn, b->ve, b->vd);
}

static void cascade_reset(Cascade *c)
{
    const Body *b = &c->physics.body;
    double euler[3];
    attitude_reset(&c->attitude);
    cascade_reset_position(c);
    euler_from_quaternion(b->qw, b->qx, b->qy, b->qz, euler);
    c->yaw_t = euler[2];
}

static void position_step(Cascade *c, const double att[3])
{
    const Body *b = &c->physics.body;
    const Command *sp = &c->cmd;
    PositionController *pc = &c->position;
    double dt = c->dt_pos;
    if (ground_idle(c, b->d)) {
        attitude_reset(&c->attitude);
        position_reset(pc, b->vn, b->ve, b->vd);
        c->lean_t[0] = c->lean_t[1] = 0.0;
        c->thrust_t = 0.0;
        c->yaw_t = att[2];
        return;
    }
    if (!isnan(sp->lean[0])) {
        c->lean_t[0] = sp->lean[0], c->lean_t[1] = sp->lean[1];
    } else {
        double pos[2] = {b->n, b->e}, vel[2] = {b->vn, b->ve};
        position_horizontal(pc, sp->pos_ne, sp->vel_ne, sp->accel_ne, sp->speed_xy, pos, vel, att[2], dt, c->lean_t);
    }
    if (!isnan(sp->throttle))
        c->thrust_t = thrust_from_stick(pc, sp->throttle);
    else
        c->thrust_t = position_vertical(pc, sp->pos_d, sp->vel_d, b->d, b->vd, att[0], att[1], dt, sp->speed_dn);
    if (!isnan(sp->rates[0]))
        c->yaw_t = att[2];
    else if (!isnan(sp->yaw))
        c->yaw_t = sp->yaw;
    else
        c->yaw_t = wrap_pi(c->yaw_t + sp->yaw_rate * dt);
}

static void attitude_step(Cascade *c, const double att[3])
{
    const Body *b = &c->physics.body;
    if (ground_idle(c, b->d)) {
        double idle = c->cmd.armed ? c->omega_idle : 0.0;
        c->omega_cmd[0] = c->omega_cmd[1] = c->omega_cmd[2] = c->omega_cmd[3] = idle;
        return;
    }
    double rates[3] = {b->p, b->q, b->r}, u[3];
    if (!isnan(c->cmd.rates[0]))
        attitude_rate_update(&c->attitude, c->cmd.rates, rates, c->dt_att, u);
    else
        attitude_update(&c->attitude, c->lean_t[0], c->lean_t[1], c->yaw_t, 0.0, att[0], att[1], att[2],
                        rates, c->dt_att, u);
    allocator_omega_commands(&c->allocator, c->thrust_t, u[0], u[1], u[2], c->omega_cmd);
}

/* n physics steps, the first of which is the sim's step number `first_step`. */
static void cascade_run(Cascade *c, long long first_step, long long n)
{
    for (long long steps = first_step; steps < first_step + n; steps++) {
        int pos_due = steps % c->ratio_pos == 0, att_due = steps % c->ratio_att == 0;
        if (pos_due || att_due) {
            const Body *b = &c->physics.body;
            double att[3];
            euler_from_quaternion(b->qw, b->qx, b->qy, b->qz, att);
            if (pos_due)
                position_step(c, att);
            if (att_due)
                attitude_step(c, att);
        }
        physics_step(&c->physics, c->omega_cmd, &c->physics_k);
    }
}

#endif

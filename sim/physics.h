/* C twin of sim/physics.py make_fast_step (motors, rotor forces, mixer, rigid body) and of
 * sim/rigid_body.py apply_ground: the same expressions in the same order, over a state struct
 * that is updated in place. tests/unit/test_compiled_cascade.py checks they agree bit for bit. */
#ifndef FIREFLY_PHYSICS_H
#define FIREFLY_PHYSICS_H

#include "pyfloat.h"

typedef struct { /* sim.rigid_body.BodyState, field for field */
    double n, e, d, vn, ve, vd, qw, qx, qy, qz, p, q, r;
} Body;

typedef struct { /* sim.physics.PhysicsState */
    Body body;
    double omega[4];
    int on_ground;
} Physics;

typedef struct {
    /* sim.physics.fast_step_constants, read by these names (autopilot/control/by_name.h) */
    double m, ixx, iyy, izz, b, arm, c, k, kr, lag, w_max, g, half, dt;
    /* the sim's conditions, handed over by set_conditions() whenever they change */
    double wind[3];
    double speed_scale[4]; /* sim.rotors.step_motors: 1 = healthy, 0 = stopped */
} PhysicsConstants;

static void euler_from_quaternion(double qw, double qx, double qy, double qz, double out[3])
{
    out[0] = atan2(2 * (qw * qx + qy * qz), 1 - 2 * (qx * qx + qy * qy));
    double sinp = 2 * (qw * qy - qz * qx);
    out[1] = asin(py_max(-1.0, py_min(1.0, sinp)));
    out[2] = atan2(2 * (qw * qz + qx * qy), 1 - 2 * (qy * qy + qz * qz));
}

static void quaternion_from_euler(double roll, double pitch, double yaw, double q[4])
{
    double cr = cos(roll / 2), sr = sin(roll / 2);
    double cp = cos(pitch / 2), sp = sin(pitch / 2);
    double cy = cos(yaw / 2), sy = sin(yaw / 2);
    q[0] = cr * cp * cy + sr * sp * sy;
    q[1] = sr * cp * cy - cr * sp * sy;
    q[2] = cr * sp * cy + sr * cp * sy;
    q[3] = cr * cp * sy - sr * sp * cy;
}

/* Ground contact at d = 0 for a body at or below it; returns whether it rests on the ground. */
static int apply_ground(Body *s)
{
    const double ground_d_m = 0.0;
    if (s->d < ground_d_m)
        return 0;
    if (s->vd < 0.0) { /* climbing away: lift-off */
        s->d = ground_d_m;
        return 0;
    }
    double euler[3], q[4];
    euler_from_quaternion(s->qw, s->qx, s->qy, s->qz, euler);
    quaternion_from_euler(0.0, 0.0, euler[2], q);
    s->d = ground_d_m;
    s->vn = s->ve = s->vd = 0.0;
    s->qw = q[0], s->qx = q[1], s->qy = q[2], s->qz = q[3];
    s->p = s->q = s->r = 0.0;
    return 1;
}

static inline double motor_command(double c, double w_max)
{
    return c < 0.0 ? 0.0 : c > w_max ? w_max : c;
}

static void physics_step(Physics *st, const double cmd[4], const PhysicsConstants *K)
{
    const double m = K->m, ixx = K->ixx, iyy = K->iyy, izz = K->izz, b = K->b, arm = K->arm;
    const double c = K->c, k = K->k, kr = K->kr, lag = K->lag, w_max = K->w_max, g = K->g;
    const double half = K->half, dt = K->dt;
    const double *wind_ned = K->wind, *scale = K->speed_scale;
    Body *s = &st->body;
    double o1 = st->omega[0], o2 = st->omega[1], o3 = st->omega[2], o4 = st->omega[3];
    o1 += (motor_command(cmd[0], w_max) * scale[0] - o1) * lag;
    o2 += (motor_command(cmd[1], w_max) * scale[1] - o2) * lag;
    o3 += (motor_command(cmd[2], w_max) * scale[2] - o3) * lag;
    o4 += (motor_command(cmd[3], w_max) * scale[3] - o4) * lag;
    double f1 = b * o1 * o1, f2 = b * o2 * o2, f3 = b * o3 * o3, f4 = b * o4 * o4;
    double u1 = f1 + f2 + f3 + f4;
    double qw = s->qw, qx = s->qx, qy = s->qy, qz = s->qz, p = s->p, q = s->q, r = s->r;
    double r02 = 2.0 * (qx * qz + qw * qy);
    double r12 = 2.0 * (qy * qz - qw * qx);
    double r22 = 1.0 - 2.0 * (qx * qx + qy * qy);
    double vn = s->vn, ve = s->ve, vd = s->vd;
    vn += (-u1 * r02 - k * (vn - wind_ned[0])) / m * dt;
    ve += (-u1 * r12 - k * (ve - wind_ned[1])) / m * dt;
    vd += ((-u1 * r22 - k * (vd - wind_ned[2])) / m + g) * dt;
    double np = p + (arm * (f2 - f4) - (izz - iyy) * q * r - kr * p) / ixx * dt;
    double nq = q + (arm * (f1 - f3) - (ixx - izz) * r * p - kr * q) / iyy * dt;
    double nr = r + (c * (f1 - f2 + f3 - f4) - (iyy - ixx) * p * q - kr * r) / izz * dt;
    p = np, q = nq, r = nr;
    double nw = qw + half * (-qx * p - qy * q - qz * r);
    double nx = qx + half * (qw * p + qy * r - qz * q);
    double ny = qy + half * (qw * q - qx * r + qz * p);
    double nz = qz + half * (qw * r + qx * q - qy * p);
    double inv = 1.0 / sqrt(nw * nw + nx * nx + ny * ny + nz * nz);
    s->n = s->n + vn * dt, s->e = s->e + ve * dt, s->d = s->d + vd * dt;
    s->vn = vn, s->ve = ve, s->vd = vd;
    s->qw = nw * inv, s->qx = nx * inv, s->qy = ny * inv, s->qz = nz * inv;
    s->p = p, s->q = q, s->r = r;
    st->omega[0] = o1, st->omega[1] = o2, st->omega[2] = o3, st->omega[3] = o4;
    st->on_ground = s->d >= 0.0 ? apply_ground(s) : 0;
}

#endif

/* Python glue for the compiled cascade (cascade.h): one Loop object per vehicle holding the
 * physics and controller state in a C struct, and run_many() stepping several vehicles in one
 * call. The Python side is compiled.py; the numbers it hands over come from the Python
 * controllers, so parameters and airframe constants have one source. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include "by_name.h"
#include "cascade.h"
#include "pyvalues.h"

typedef struct {
    PyObject_HEAD
    Cascade c;
    PyObject *body_type, *state_type; /* sim.rigid_body.BodyState, sim.physics.PhysicsState */
} LoopObject;

static PyTypeObject LoopType;

static int initialised(LoopObject *self)
{
    if (self->body_type == NULL) { /* Loop.__new__ without __init__: its ratios are 0 */
        PyErr_SetString(PyExc_RuntimeError, "Loop used before __init__ succeeded");
        return 0;
    }
    return 1;
}

/* Loop(constants, ratio_pos, ratio_att, body_type, state_type); constants by name (by_name.h). */
static int Loop_init(LoopObject *self, PyObject *args, PyObject *kwds)
{
    PyObject *constants, *body_type, *state_type;
    long long ratio_pos, ratio_att;
    static char *kwlist[] = {"constants", "ratio_pos", "ratio_att", "body_type", "state_type", NULL};
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "OLLO!O!", kwlist, &constants, &ratio_pos, &ratio_att,
                                     &PyType_Type, &body_type, &PyType_Type, &state_type))
        return -1;
    if (ratio_pos < 1 || ratio_att < 1) {
        PyErr_SetString(PyExc_ValueError, "loop ratios must be at least 1");
        return -1;
    }
    if (!PyType_IsSubtype((PyTypeObject *)body_type, &PyTuple_Type) ||
        !PyType_IsSubtype((PyTypeObject *)state_type, &PyTuple_Type)) {
        PyErr_SetString(PyExc_TypeError, "body_type and state_type must be tuple types (NamedTuples)");
        return -1;
    }
    /* Built aside and copied in only when complete: a failed re-init leaves the loop as it was. */
    Cascade c;
    memset(&c, 0, sizeof c);
    if (read_named(constants, CONSTANTS, COUNT(CONSTANTS), &c, "constants") < 0)
        return -1;
    for (int i = 0; i < 4; i++) /* still air and healthy motors until set_conditions() says otherwise */
        c.physics_k.speed_scale[i] = 1.0;
    c.ratio_pos = ratio_pos, c.ratio_att = ratio_att;
    self->c = c;
    Py_INCREF(body_type);
    Py_XSETREF(self->body_type, body_type);
    Py_INCREF(state_type);
    Py_XSETREF(self->state_type, state_type);
    return 0;
}

static void Loop_dealloc(LoopObject *self)
{
    Py_XDECREF(self->body_type);
    Py_XDECREF(self->state_type);
    Py_TYPE(self)->tp_free((PyObject *)self);
}

static PyObject *Loop_configure(LoopObject *self, PyObject *gains)
{
    if (!initialised(self))
        return NULL;
    Cascade c = self->c; /* read aside: a refused configure leaves the gains as they were */
    if (read_named(gains, GAINS, COUNT(GAINS), &c, "gains") < 0)
        return NULL;
    self->c = c;
    Py_RETURN_NONE;
}

/* set_conditions(wind_ned, speed_scale): the sim's wind now and its motors' health (fault injection),
 * used from the next physics step on. */
static PyObject *Loop_set_conditions(LoopObject *self, PyObject *args)
{
    if (!initialised(self))
        return NULL;
    PyObject *wind, *scale;
    if (!PyArg_ParseTuple(args, "OO", &wind, &scale))
        return NULL;
    PhysicsConstants k = self->c.physics_k;
    double *wind_slots[3] = {&k.wind[0], &k.wind[1], &k.wind[2]};
    double *scale_slots[4] = {&k.speed_scale[0], &k.speed_scale[1], &k.speed_scale[2], &k.speed_scale[3]};
    if (read_doubles(wind, wind_slots, 3, "wind_ned") < 0 || read_doubles(scale, scale_slots, 4, "speed_scale") < 0)
        return NULL;
    self->c.physics_k = k;
    Py_RETURN_NONE;
}

static void body_slots(Body *b, double *s[13]) /* BodyState's field order */
{
    double *order[13] = {&b->n, &b->e, &b->d, &b->vn, &b->ve, &b->vd, &b->qw, &b->qx, &b->qy, &b->qz,
                         &b->p, &b->q, &b->r};
    memcpy(s, order, sizeof order);
}

/* load(PhysicsState): the sim's state, when something outside the cascade has set it. */
static PyObject *Loop_load(LoopObject *self, PyObject *state)
{
    if (!initialised(self))
        return NULL;
    Physics ph = self->c.physics;
    double *body[13], *omega[4] = {&ph.omega[0], &ph.omega[1], &ph.omega[2], &ph.omega[3]};
    body_slots(&ph.body, body);
    if (!PyTuple_Check(state) || PyTuple_GET_SIZE(state) != 3) {
        PyErr_SetString(PyExc_TypeError, "load: expected a PhysicsState");
        return NULL;
    }
    if (read_doubles(PyTuple_GET_ITEM(state, 0), body, 13, "load: body") < 0 ||
        read_doubles(PyTuple_GET_ITEM(state, 1), omega, 4, "load: omega_rad_s") < 0)
        return NULL;
    int on_ground = PyObject_IsTrue(PyTuple_GET_ITEM(state, 2));
    if (on_ground < 0)
        return NULL;
    ph.on_ground = on_ground;
    self->c.physics = ph;
    Py_RETURN_NONE;
}

/* state() -> PhysicsState: a snapshot for everything outside the cascade. */
static PyObject *Loop_state(LoopObject *self, PyObject *unused)
{
    if (!initialised(self))
        return NULL;
    if (!self->body_type) {
        PyErr_SetString(PyExc_RuntimeError, "Loop was not initialised");
        return NULL;
    }
    Physics *ph = &self->c.physics;
    double *body_x[13];
    body_slots(&ph->body, body_x);
    const double *omega_x[4] = {&ph->omega[0], &ph->omega[1], &ph->omega[2], &ph->omega[3]};
    PyObject *body = float_tuple((PyTypeObject *)self->body_type, (const double **)body_x, 13);
    PyObject *omega = body ? float_tuple(&PyTuple_Type, omega_x, 4) : NULL;
    PyTypeObject *st = (PyTypeObject *)self->state_type;
    PyObject *state = omega ? st->tp_alloc(st, 3) : NULL;
    if (!state) {
        Py_XDECREF(body);
        Py_XDECREF(omega);
        return NULL;
    }
    tuple_hash_unset(state);
    PyTuple_SET_ITEM(state, 0, body);
    PyTuple_SET_ITEM(state, 1, omega);
    PyTuple_SET_ITEM(state, 2, PyBool_FromLong(ph->on_ground));
    return state;
}

/* Setpoint attribute names, interned once. */
static PyObject *s_lean, *s_pos_ne, *s_vel_ne, *s_accel_ne, *s_throttle, *s_pos_d, *s_vel_d, *s_speed_dn, *s_yaw, *s_yaw_rate,
    *s_rates;

/* Read sp.<name> (None -> NaN) into n doubles. */
static int read_setpoint(PyObject *sp, PyObject *name, double *out, int n)
{
    PyObject *v = PyObject_GetAttr(sp, name);
    if (!v)
        return -1;
    int rc = 0;
    if (v == Py_None) {
        for (int i = 0; i < n; i++)
            out[i] = NAN;
    } else if (n == 1) {
        out[0] = PyFloat_AsDouble(v);
        rc = out[0] == -1.0 && PyErr_Occurred() ? -1 : 0;
    } else {
        double *slots[3] = {&out[0], &out[1], n > 2 ? &out[2] : NULL};
        rc = read_doubles(v, slots, n, PyUnicode_AsUTF8(name));
    }
    Py_DECREF(v);
    return rc;
}

/* command(setpoint, armed, landed, speed_xy) */
static PyObject *Loop_command(LoopObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    if (!initialised(self))
        return NULL;
    if (nargs != 4) {
        PyErr_SetString(PyExc_TypeError, "command(setpoint, armed, landed, speed_xy)");
        return NULL;
    }
    Command cmd;
    PyObject *sp = args[0];
    cmd.armed = PyObject_IsTrue(args[1]);
    cmd.landed = PyObject_IsTrue(args[2]);
    cmd.speed_xy = PyFloat_AsDouble(args[3]);
    if (cmd.armed < 0 || cmd.landed < 0 || (cmd.speed_xy == -1.0 && PyErr_Occurred()) ||
        read_setpoint(sp, s_lean, cmd.lean, 2) < 0 || read_setpoint(sp, s_pos_ne, cmd.pos_ne, 2) < 0 ||
        read_setpoint(sp, s_vel_ne, cmd.vel_ne, 2) < 0 || read_setpoint(sp, s_accel_ne, cmd.accel_ne, 2) < 0 ||
        read_setpoint(sp, s_throttle, &cmd.throttle, 1) < 0 ||
        read_setpoint(sp, s_pos_d, &cmd.pos_d, 1) < 0 || read_setpoint(sp, s_vel_d, &cmd.vel_d, 1) < 0 ||
        read_setpoint(sp, s_speed_dn, &cmd.speed_dn, 1) < 0 || read_setpoint(sp, s_yaw, &cmd.yaw, 1) < 0 ||
        read_setpoint(sp, s_yaw_rate, &cmd.yaw_rate, 1) < 0 || read_setpoint(sp, s_rates, cmd.rates, 3) < 0)
        return NULL;
    self->c.cmd = cmd;
    Py_RETURN_NONE;
}

static int parse_run(PyObject *const *args, Py_ssize_t nargs, long long *first, long long *n)
{
    if (nargs != 2) {
        PyErr_SetString(PyExc_TypeError, "expected (first_step, n)");
        return -1;
    }
    *first = PyLong_AsLongLong(args[0]);
    *n = PyLong_AsLongLong(args[1]);
    return PyErr_Occurred() ? -1 : 0;
}

/* run(first_step, n): n physics steps with the cascade; the first is the sim's step `first_step`. */
static PyObject *Loop_run(LoopObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    long long first, n;
    if (!initialised(self) || parse_run(args, nargs, &first, &n) < 0)
        return NULL;
    cascade_run(&self->c, first, n);
    Py_RETURN_NONE;
}

/* run_physics(n, omega_cmd): n physics steps at fixed motor commands, no control (the bench's
 * split of the step cost between physics and control). */
static PyObject *Loop_run_physics(LoopObject *self, PyObject *args)
{
    if (!initialised(self))
        return NULL;
    long long n;
    double cmd[4];
    if (!PyArg_ParseTuple(args, "L(dddd)", &n, &cmd[0], &cmd[1], &cmd[2], &cmd[3]))
        return NULL;
    for (long long i = 0; i < n; i++)
        physics_step(&self->c.physics, cmd, &self->c.physics_k);
    Py_RETURN_NONE;
}

static PyObject *Loop_reset(LoopObject *self, PyObject *unused)
{
    if (!initialised(self))
        return NULL;
    cascade_reset(&self->c);
    Py_RETURN_NONE;
}

static PyObject *Loop_reset_position(LoopObject *self, PyObject *unused)
{
    if (!initialised(self))
        return NULL;
    cascade_reset_position(&self->c);
    Py_RETURN_NONE;
}

static PyObject *Loop_get_thrust_t(LoopObject *self, void *closure) { return PyFloat_FromDouble(self->c.thrust_t); }
static PyObject *Loop_get_yaw_t(LoopObject *self, void *closure) { return PyFloat_FromDouble(self->c.yaw_t); }

static PyObject *Loop_get_lean_t(LoopObject *self, void *closure)
{
    const double *x[2] = {&self->c.lean_t[0], &self->c.lean_t[1]};
    return float_tuple(&PyTuple_Type, x, 2);
}

static PyObject *Loop_get_omega_cmd(LoopObject *self, void *closure)
{
    const double *x[4] = {&self->c.omega_cmd[0], &self->c.omega_cmd[1], &self->c.omega_cmd[2], &self->c.omega_cmd[3]};
    return float_tuple(&PyTuple_Type, x, 4);
}

static PyMethodDef Loop_methods[] = {
    {"configure", (PyCFunction)Loop_configure, METH_O, "configure(gains): controller gains by name (by_name.h)"},
    {"load", (PyCFunction)Loop_load, METH_O, "load(PhysicsState)"},
    {"set_conditions", (PyCFunction)Loop_set_conditions, METH_VARARGS, "set_conditions(wind_ned, speed_scale)"},
    {"state", (PyCFunction)Loop_state, METH_NOARGS, "state() -> PhysicsState"},
    {"command", (PyCFunction)(void (*)(void))Loop_command, METH_FASTCALL, "command(setpoint, armed, landed, speed_xy)"},
    {"run", (PyCFunction)(void (*)(void))Loop_run, METH_FASTCALL, "run(first_step, n)"},
    {"run_physics", (PyCFunction)Loop_run_physics, METH_VARARGS, "run_physics(n, omega_cmd)"},
    {"reset", (PyCFunction)Loop_reset, METH_NOARGS, "forget controller history, hold the heading"},
    {"reset_position", (PyCFunction)Loop_reset_position, METH_NOARGS, "bumpless position-loop hand-over"},
    {NULL},
};

static PyGetSetDef Loop_getset[] = {
    {"thrust_t", (getter)Loop_get_thrust_t, NULL, "U1 demand [N]", NULL},
    {"yaw_t", (getter)Loop_get_yaw_t, NULL, "heading target [rad]", NULL},
    {"lean_t", (getter)Loop_get_lean_t, NULL, "(roll, pitch) targets [rad]", NULL},
    {"omega_cmd", (getter)Loop_get_omega_cmd, NULL, "motor speed commands [rad/s]", NULL},
    {NULL},
};

static PyTypeObject LoopType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "firefly.autopilot.control._cascade.Loop",
    .tp_basicsize = sizeof(LoopObject),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "One vehicle's physics and control cascade, stepped in C.",
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)Loop_init,
    .tp_dealloc = (destructor)Loop_dealloc,
    .tp_methods = Loop_methods,
    .tp_getset = Loop_getset,
};

/* run_many(loops, first_step, n): every loop n steps, in one call (vehicles batched). */
static PyObject *run_many(PyObject *module, PyObject *const *args, Py_ssize_t nargs)
{
    long long first, n;
    if (nargs != 3 || parse_run(args + 1, 2, &first, &n) < 0) {
        if (!PyErr_Occurred())
            PyErr_SetString(PyExc_TypeError, "run_many(loops, first_step, n)");
        return NULL;
    }
    PyObject *fast = PySequence_Fast(args[0], "run_many: loops must be a sequence");
    if (!fast)
        return NULL;
    Py_ssize_t count = PySequence_Fast_GET_SIZE(fast);
    PyObject **items = PySequence_Fast_ITEMS(fast);
    for (Py_ssize_t i = 0; i < count; i++) {
        if (PyObject_TypeCheck(items[i], &LoopType) && !initialised((LoopObject *)items[i])) {
            Py_DECREF(fast);
            return NULL;
        }
        if (!PyObject_TypeCheck(items[i], &LoopType)) {
            Py_DECREF(fast);
            PyErr_SetString(PyExc_TypeError, "run_many: every item must be a Loop");
            return NULL;
        }
    }
    for (Py_ssize_t i = 0; i < count; i++)
        cascade_run(&((LoopObject *)items[i])->c, first, n);
    Py_DECREF(fast);
    Py_RETURN_NONE;
}

static PyMethodDef module_methods[] = {
    {"run_many", (PyCFunction)(void (*)(void))run_many, METH_FASTCALL, "run_many(loops, first_step, n)"},
    {NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_cascade", "Firefly's compiled control cascade.", -1,
                                    module_methods};

PyMODINIT_FUNC PyInit__cascade(void)
{
    PyObject **names[] = {&s_lean, &s_pos_ne, &s_vel_ne, &s_accel_ne, &s_throttle, &s_pos_d, &s_vel_d, &s_speed_dn, &s_yaw, &s_yaw_rate,
                          &s_rates};
    const char *text[] = {"lean", "pos_ne", "vel_ne", "accel_ne", "throttle", "pos_d", "vel_d", "speed_dn", "yaw", "yaw_rate",
                          "rates"};
    for (size_t i = 0; i < sizeof names / sizeof *names; i++)
        if (!(*names[i] = PyUnicode_InternFromString(text[i])))
            return NULL;
    if (PyType_Ready(&LoopType) < 0)
        return NULL;
    PyObject *m = PyModule_Create(&module);
    if (!m)
        return NULL;
    Py_INCREF(&LoopType);
    if (PyModule_AddObject(m, "Loop", (PyObject *)&LoopType) < 0) {
        Py_DECREF(&LoopType);
        Py_DECREF(m);
        return NULL;
    }
    return m;
}

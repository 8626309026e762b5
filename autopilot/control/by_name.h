/* The numbers compiled.py hands to the loop, read by name: the constants once (Loop()), the
 * gains on every configure(). Each comes as a dict of parts, each part a dict of numbers:
 *     {"physics": {"m": 1.5, "ixx": ...}, "allocator": {"l": ..., ...}, ...}
 * A missing part or number, or one these tables do not know (a misspelling on either side), is a
 * KeyError that names it, so the Python side and the C structs cannot drift apart unnoticed.
 * This runs when a vehicle is configured, never per step. */
#ifndef FIREFLY_BY_NAME_H
#define FIREFLY_BY_NAME_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <stddef.h>
#include <string.h>

#include "cascade.h"

typedef struct {
    const char *part, *name;
    size_t offset; /* of the double it fills, in Cascade */
} Named;

/* Where a field has a name of its own, that name is the key: one spelling for both. */
#define PHYSICS(f) {"physics", #f, offsetof(Cascade, physics_k.f)}
#define ATTITUDE(f) {"attitude", #f, offsetof(Cascade, attitude.f)}
#define POSITION(f) {"position", #f, offsetof(Cascade, position.f)}
#define ALLOCATOR(f) {"allocator", #f, offsetof(Cascade, allocator.f)}
#define CASCADE(f) {"cascade", #f, offsetof(Cascade, f)}
#define PID_GAINS(part, pid)                                                                      \
    {part, "kp", offsetof(Cascade, pid.kp)}, {part, "ki", offsetof(Cascade, pid.ki)},             \
    {part, "kd", offsetof(Cascade, pid.kd)}, {part, "imax", offsetof(Cascade, pid.imax)},         \
    {part, "out_limit", offsetof(Cascade, pid.out_limit)},                                        \
    {part, "d_filter_hz", offsetof(Cascade, pid.d_filter_hz)},                                    \
    {part, "d_on_error", offsetof(Cascade, pid.d_on_error)}

/* Loop(constants): sim.physics.fast_step_constants, then what the controllers take from the airframe. */
static const Named CONSTANTS[] = {
    PHYSICS(m), PHYSICS(ixx), PHYSICS(iyy), PHYSICS(izz), PHYSICS(b), PHYSICS(arm), PHYSICS(c),
    PHYSICS(k), PHYSICS(kr), PHYSICS(lag), PHYSICS(w_max), PHYSICS(g), PHYSICS(half), PHYSICS(dt),
    ATTITUDE(roll_torque_max), ATTITUDE(pitch_torque_max), ATTITUDE(yaw_torque_max),
    POSITION(mass), POSITION(weight), POSITION(thrust_max),
    ALLOCATOR(l), ALLOCATOR(c), ALLOCATOR(b), ALLOCATOR(f_max), ALLOCATOR(f_min),
    CASCADE(omega_idle), CASCADE(dt_pos), CASCADE(dt_att),
};

/* configure(gains): everything the controllers derive from parameters. */
static const Named GAINS[] = {
    {"attitude", "angle_p_roll", offsetof(Cascade, attitude.angle_p[0])},
    {"attitude", "angle_p_pitch", offsetof(Cascade, attitude.angle_p[1])},
    {"attitude", "angle_p_yaw", offsetof(Cascade, attitude.angle_p[2])},
    ATTITUDE(rp_rate_max), ATTITUDE(yaw_rate_max),
    POSITION(pos_xy_p), POSITION(pos_z_p), POSITION(accel_xy_max), POSITION(lean_max),
    POSITION(speed_up), POSITION(speed_dn), POSITION(accel_z_max), POSITION(vel_fltd_hz),
    PID_GAINS("rate_roll", attitude.rate[0]), PID_GAINS("rate_pitch", attitude.rate[1]),
    PID_GAINS("rate_yaw", attitude.rate[2]), PID_GAINS("vel_n", position.vel_n),
    PID_GAINS("vel_e", position.vel_e), PID_GAINS("vel_d", position.vel_d),
};

#define COUNT(table) (sizeof table / sizeof *table)

static int knows(const Named *table, size_t n, const char *part, const char *name)
{
    for (size_t i = 0; i < n; i++)
        if (!strcmp(table[i].part, part) && (name == NULL || !strcmp(table[i].name, name)))
            return 1;
    return 0;
}

/* A key as text, or NULL with a TypeError if it is not a str. */
static const char *key_text(PyObject *key, const char *what)
{
    if (!PyUnicode_Check(key)) {
        PyErr_Format(PyExc_TypeError, "%s: keys must be str, got %.100R", what, key);
        return NULL;
    }
    return PyUnicode_AsUTF8(key);
}

/* Refuse any part or number the table does not know. Only dict iteration and string compares
 * here: no Python code runs that could change the dicts while they are walked. */
static int refuse_unknown(PyObject *numbers, const Named *table, size_t n, const char *what)
{
    Py_ssize_t i = 0, j;
    PyObject *part_key, *part, *key, *value;
    while (PyDict_Next(numbers, &i, &part_key, &part)) {
        const char *part_name = key_text(part_key, what), *name;
        if (!part_name)
            return -1;
        if (!knows(table, n, part_name, NULL)) {
            PyErr_Format(PyExc_KeyError, "%s: unknown part '%s'", what, part_name);
            return -1;
        }
        if (!PyDict_Check(part)) {
            PyErr_Format(PyExc_TypeError, "%s['%s']: expected a dict, got %.100s", what, part_name,
                         Py_TYPE(part)->tp_name);
            return -1;
        }
        for (j = 0; PyDict_Next(part, &j, &key, &value);) {
            if (!(name = key_text(key, what)))
                return -1;
            if (!knows(table, n, part_name, name)) {
                PyErr_Format(PyExc_KeyError, "%s: unknown '%s.%s'", what, part_name, name);
                return -1;
            }
        }
    }
    return 0;
}

/* numbers[entry.part][entry.name] as a double. The part and the number are held while the number
 * converts: its __float__ may change the dicts. */
static int read_number(PyObject *numbers, const Named *entry, const char *what, double *x)
{
    PyObject *part = PyDict_GetItemString(numbers, entry->part);
    if (!part) {
        PyErr_Format(PyExc_KeyError, "%s: missing part '%s'", what, entry->part);
        return -1;
    }
    if (!PyDict_Check(part)) {
        PyErr_Format(PyExc_TypeError, "%s['%s']: expected a dict", what, entry->part);
        return -1;
    }
    Py_INCREF(part);
    PyObject *value = PyDict_GetItemString(part, entry->name);
    Py_XINCREF(value);
    Py_DECREF(part);
    if (!value) {
        PyErr_Format(PyExc_KeyError, "%s: missing '%s.%s'", what, entry->part, entry->name);
        return -1;
    }
    *x = PyFloat_AsDouble(value);
    Py_DECREF(value);
    return *x == -1.0 && PyErr_Occurred() ? -1 : 0;
}

/* Every number of `table` from `numbers` into *c; on an error *c is left partly filled, so callers
 * read into a copy and keep it only on success. */
static int read_named(PyObject *numbers, const Named *table, size_t n, Cascade *c, const char *what)
{
    if (!PyDict_Check(numbers)) {
        PyErr_Format(PyExc_TypeError, "%s: expected a dict of parts, got %.100s", what, Py_TYPE(numbers)->tp_name);
        return -1;
    }
    if (refuse_unknown(numbers, table, n, what) < 0)
        return -1;
    for (size_t i = 0; i < n; i++) {
        double x;
        if (read_number(numbers, &table[i], what, &x) < 0)
            return -1;
        memcpy((char *)c + table[i].offset, &x, sizeof x);
    }
    return 0;
}

#endif

/* Python objects to and from C doubles, for the glue in _cascade.c: sequences of floats read into
 * named slots, and tuples (or namedtuples) of floats built from them. */
#ifndef FIREFLY_PYVALUES_H
#define FIREFLY_PYVALUES_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>

/* The n numbers of `seq` into *out[0..n-1]; `what` names them in errors. */
static int read_doubles(PyObject *seq, double *out[], Py_ssize_t n, const char *what)
{
    /* A tuple copy: a list could change size under us while __float__ of its items runs. */
    PyObject *fast = PySequence_Tuple(seq);
    if (!fast)
        return -1;
    if (PyTuple_GET_SIZE(fast) != n) {
        PyErr_Format(PyExc_ValueError, "%s: expected %zd numbers, got %zd", what, n, PyTuple_GET_SIZE(fast));
        Py_DECREF(fast);
        return -1;
    }
    for (Py_ssize_t i = 0; i < n; i++) {
        double x = PyFloat_AsDouble(PyTuple_GET_ITEM(fast, i));
        if (x == -1.0 && PyErr_Occurred()) {
            Py_DECREF(fast);
            return -1;
        }
        *out[i] = x;
    }
    Py_DECREF(fast);
    return 0;
}

/* For a tuple subtype's object made by tp_alloc: from Python 3.14 a tuple caches its hash, -1
 * until computed, which tuple's own constructors set and tp_alloc's zeroed memory does not. */
static inline void tuple_hash_unset(PyObject *t)
{
#if PY_VERSION_HEX >= 0x030E0000
    ((PyTupleObject *)t)->ob_hash = -1;
#else
    (void)t;
#endif
}

/* A tuple of `type` (a namedtuple class, or tuple) holding n floats. */
static PyObject *float_tuple(PyTypeObject *type, const double *x[], Py_ssize_t n)
{
    PyObject *t = type == &PyTuple_Type ? PyTuple_New(n) : type->tp_alloc(type, n);
    if (!t)
        return NULL;
    if (type != &PyTuple_Type)
        tuple_hash_unset(t);
    for (Py_ssize_t i = 0; i < n; i++) {
        PyObject *f = PyFloat_FromDouble(*x[i]);
        if (!f) {
            Py_DECREF(t);
            return NULL;
        }
        PyTuple_SET_ITEM(t, i, f);
    }
    return t;
}

#endif

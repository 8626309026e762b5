/* Python glue for battery.h: step(state, omega, constants) -> the BatteryState one battery step
 * later, built as the state's own type (a NamedTuple), so sim/vehicle.py calls it in place of the
 * Python reference at 100 Hz per vehicle without a wrapper. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include "battery.h"

static int read_doubles(PyObject *seq, double *out, Py_ssize_t n, const char *what)
{
    if (!PyTuple_Check(seq) || PyTuple_GET_SIZE(seq) != n) {
        PyErr_Format(PyExc_TypeError, "step: %s must be a tuple of %zd numbers", what, n);
        return -1;
    }
    for (Py_ssize_t i = 0; i < n; i++) {
        out[i] = PyFloat_AsDouble(PyTuple_GET_ITEM(seq, i));
        if (out[i] == -1.0 && PyErr_Occurred())
            return -1;
    }
    return 0;
}

/* step(state, omega, constants): state (consumed_mah, current_a, voltage_v) as a tuple type,
 * omega the four rotor speeds, constants (power_per_omega_cubed, cells, capacity_mah,
 * r_internal_ohm, extra_current_a, dt). */
static PyObject *step(PyObject *module, PyObject *const *args, Py_ssize_t nargs)
{
    if (nargs != 3) {
        PyErr_SetString(PyExc_TypeError, "step(state, omega, constants)");
        return NULL;
    }
    double state[3], omega[4], k[6];
    if (!PyTuple_Check(args[0]) || Py_TYPE(args[0]) == &PyTuple_Type) {
        PyErr_SetString(PyExc_TypeError, "step: state must be a BatteryState");
        return NULL;
    }
    if (read_doubles(args[0], state, 3, "state") < 0 || read_doubles(args[1], omega, 4, "omega") < 0 ||
        read_doubles(args[2], k, 6, "constants") < 0)
        return NULL;
    BatteryConstants c = {k[0], k[1], k[2], k[3], k[4], k[5]};
    battery_step(state, omega, &c);
    /* tuple.__new__(type(state), values): the state's own NamedTuple type, made as Python makes
     * it (tuple subtypes need their construction, e.g. a cached hash, set up by tuple itself) */
    PyObject *values = Py_BuildValue("(ddd)", state[0], state[1], state[2]);
    if (!values)
        return NULL;
    PyObject *ctor_args = PyTuple_Pack(1, values);
    Py_DECREF(values);
    if (!ctor_args)
        return NULL;
    PyObject *out = PyTuple_Type.tp_new(Py_TYPE(args[0]), ctor_args, NULL);
    Py_DECREF(ctor_args);
    return out;
}

static PyMethodDef module_methods[] = {
    {"step", (PyCFunction)(void (*)(void))step, METH_FASTCALL, "step(state, omega, constants) -> state one battery step later"},
    {NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_battery", "Firefly's compiled battery step.", -1,
                                    module_methods};

PyMODINIT_FUNC PyInit__battery(void) { return PyModule_Create(&module); }

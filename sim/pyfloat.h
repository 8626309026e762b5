/* Python's float semantics where C's differ, so that a C twin of a Python function computes the
 * very same bits: min() and max() keep the first argument on ties and NaN, % takes the sign of
 * the divisor. Everything else (+ - * /, sqrt, sin, atan2 ...) is IEEE double and the same libm
 * in both, provided the C is compiled without FP contraction or fast-math (see setup.py). */
#ifndef FIREFLY_PYFLOAT_H
#define FIREFLY_PYFLOAT_H

#include <math.h>

#define PY_PI 3.141592653589793 /* math.pi */

static inline double py_min(double a, double b) { return b < a ? b : a; }
static inline double py_max(double a, double b) { return b > a ? b : a; }

/* max(lo, min(hi, x)): the clamp idiom of the Python code, argument order included. */
static inline double py_clamp(double lo, double hi, double x) { return py_max(lo, py_min(hi, x)); }

/* x % w for floats (CPython's float_rem). */
static inline double py_mod(double x, double w)
{
    double mod = fmod(x, w);
    if (mod) {
        if ((w < 0) != (mod < 0))
            mod += w;
    } else {
        mod = copysign(0.0, w);
    }
    return mod;
}

#endif

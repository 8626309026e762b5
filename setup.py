"""Builds the compiled control cascade (autopilot/control/_cascade.c), battery step
(sim/_battery.c) and MAVLink frame (autopilot/mavlink/_frames.c) at `pip install`.

Everything else is declared in pyproject.toml. The extensions are optional: if they cannot be built,
the install still succeeds and vehicles fly the Python references (autopilot/control/cascade.py,
sim/battery.py, autopilot/mavlink/fast_pack.py).
Not in CI (CI=true): there a failed build fails the install, loudly, where otherwise the tests
of the compiled twin would only be skipped.
The flags keep IEEE double semantics exactly as CPython's floats have them, so the C twin
computes the very same bits: no FP contraction into fused multiply-adds, no fast-math, and no
builtin replacement of libm calls (gcc would fuse sin and cos into sincos).
"""
import os

from setuptools import Extension, setup

# The arithmetic (twins of the Python modules) and the glue _cascade.c includes; one translation unit.
HEADERS = ["sim/pyfloat.h", "sim/physics.h", "autopilot/control/pid.h", "autopilot/control/attitude.h",
           "autopilot/control/position.h", "autopilot/control/allocation.h", "autopilot/control/cascade.h",
           "autopilot/control/by_name.h", "autopilot/control/pyvalues.h"]
FLAGS = ["-O2", "-ffp-contract=off", "-fno-fast-math", "-fno-builtin"]
BUILD_REQUIRED = os.environ.get("CI", "").lower() == "true"  # as firefly.autopilot.control.compiled.required()

setup(ext_modules=[Extension(
    "firefly.autopilot.control._cascade",
    sources=["autopilot/control/_cascade.c"],
    depends=HEADERS,
    include_dirs=["sim", "autopilot/control"],
    extra_compile_args=FLAGS,
    optional=not BUILD_REQUIRED,
), Extension(
    "firefly.sim._battery",
    sources=["sim/_battery.c"],
    depends=["sim/pyfloat.h", "sim/battery.h"],
    include_dirs=["sim"],
    extra_compile_args=FLAGS,
    optional=not BUILD_REQUIRED,
), Extension(
    "firefly.autopilot.mavlink._frames",
    sources=["autopilot/mavlink/_frames.c"],
    extra_compile_args=FLAGS,
    optional=not BUILD_REQUIRED,
)])

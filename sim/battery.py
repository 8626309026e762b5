"""Battery: a LiPo pack whose voltage sags with current and whose capacity drains.

Open-circuit voltage per cell falls from 4.2 V (full) to 3.3 V (empty) along a typical LiPo
discharge curve; terminal voltage = cells * OCV(soc) - I * R_internal.
"""
from __future__ import annotations

import math
from bisect import bisect_left
from collections.abc import Callable
from functools import partial
from typing import NamedTuple

# (state of charge, open-circuit volts per cell): a typical LiPo discharge curve.
_OCV_CURVE = ((0.0, 3.27), (0.05, 3.61), (0.1, 3.69), (0.2, 3.73), (0.3, 3.77), (0.4, 3.79),
              (0.5, 3.82), (0.6, 3.87), (0.7, 3.92), (0.8, 3.98), (0.9, 4.06), (1.0, 4.20))


class BatteryState(NamedTuple):
    consumed_mah: float = 0.0
    current_a: float = 0.0
    voltage_v: float = 0.0


# Builds the NamedTuple without its Python-level __new__: the pack steps for every vehicle at 100 Hz.
_new_state = partial(tuple.__new__, BatteryState)
_SOC_POINTS = tuple(soc for soc, _ in _OCV_CURVE)
_OCV_POINTS = tuple(volts for _, volts in _OCV_CURVE)
# Per segment ending at point i: (s0, v0, v1 - v0, s1 - s0), so the interpolation below does the
# same float operations as the textbook formula without re-reading the curve (it runs for every
# vehicle at 100 Hz).
_SEGMENTS = ((math.nan,) * 4,) + tuple((s0, v0, v1 - v0, s1 - s0)  # [0]: no segment ends at the first point
                                       for (s0, v0), (s1, v1) in zip(_OCV_CURVE, _OCV_CURVE[1:]))
_LAST_SEGMENT = len(_SOC_POINTS) - 1


def open_circuit_volts_per_cell(soc: float) -> float:
    """Linear interpolation in _OCV_CURVE, on the first segment whose upper end is >= soc:
    v0 + (v1 - v0) * (soc - s0) / (s1 - s0)."""
    soc = 0.0 if soc < 0.0 else 1.0 if soc > 1.0 else soc
    s0, v0, dv, ds = _SEGMENTS[bisect_left(_SOC_POINTS, soc, 1, _LAST_SEGMENT)]
    return v0 + dv * (soc - s0) / ds


def soc_at_open_circuit_volts(volts_per_cell: float) -> float:
    """The state of charge at which a cell rests at this voltage (the inverse of the curve,
    clamped to empty and full)."""
    if volts_per_cell <= _OCV_POINTS[0]:
        return 0.0
    if volts_per_cell >= _OCV_POINTS[-1]:
        return 1.0
    i = bisect_left(_OCV_POINTS, volts_per_cell, 1, len(_OCV_POINTS) - 1)
    (s0, v0), (s1, v1) = _OCV_CURVE[i - 1], _OCV_CURVE[i]
    return s0 + (s1 - s0) * (volts_per_cell - v0) / (v1 - v0)


def step_battery(state: BatteryState, power_w: float, cells: int, capacity_mah: float,
                 r_internal_ohm: float, extra_current_a: float, dt: float) -> BatteryState:
    soc = 1.0 - state.consumed_mah / capacity_mah
    ocv = cells * open_circuit_volts_per_cell(soc)
    # Solve P = (ocv - I R) I for the smaller root; fall back to the sag limit when P is too high.
    disc = ocv * ocv - 4.0 * r_internal_ohm * power_w
    current = (ocv - disc ** 0.5) / (2.0 * r_internal_ohm) if disc > 0 else ocv / (2 * r_internal_ohm)
    current += extra_current_a
    consumed = state.consumed_mah + current * dt / 3.6
    return _new_state((consumed, current, max(ocv - current * r_internal_ohm, 0.0)))


def step_battery_at(state: BatteryState, omega: tuple, constants: tuple) -> BatteryState:
    """One battery step at these rotor speeds: electrical power = sum of k F^1.5 / efficiency
    with F = b w^2, i.e. a constant times the sum of w^3. constants: (that constant, cells,
    capacity_mah, r_internal_ohm, extra_current_a, dt). The Python reference of the compiled
    twin (battery.h) that STEP_AT is when it was built."""
    k, cells, capacity_mah, r_internal_ohm, extra_current_a, dt = constants
    o1, o2, o3, o4 = omega
    power = k * (o1 * o1 * o1 + o2 * o2 * o2 + o3 * o3 * o3 + o4 * o4 * o4)
    return step_battery(state, power, cells, capacity_mah, r_internal_ohm, extra_current_a, dt)


def _compiled_step() -> Callable[[BatteryState, tuple, tuple], BatteryState] | None:
    """The compiled twin (sim/_battery.c), built by pip install where a C compiler is found."""
    try:
        from ._battery import step
    except ImportError:
        return None
    return step


compiled_step_battery_at = _compiled_step()
# What the simulator steps the pack with: the same bits either way, the compiled one 4x faster.
STEP_AT = compiled_step_battery_at or step_battery_at


def remaining_fraction(state: BatteryState, capacity_mah: float) -> float:
    return min(max(1.0 - state.consumed_mah / capacity_mah, 0.0), 1.0)

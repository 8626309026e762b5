"""What a valid vehicle looks like, for the property tests, the fuzz and the soak."""
from __future__ import annotations

import math

from firefly.autopilot.modes import MODE_BY_NUMBER
from firefly.autopilot.params import PARAM_TABLE, SET_UNCHECKED_BY_COMMANDS


def terminal_speed_m_s(airframe) -> float:
    """A speed the airframe cannot reach: full thrust and its weight together against its linear
    drag (the sim's terminal speed). A pilot holding full stick in STABILIZE may well fly at 60 m/s
    with the default airframe's light drag (the million-step walk found it); faster than this
    only a broken integration flies."""
    if airframe.linear_drag_n_per_m_s <= 0:
        return math.inf
    return (4.0 * airframe.max_rotor_thrust_n + airframe.weight_n) / airframe.linear_drag_n_per_m_s


def vehicle_problems(v, session=None) -> list[str]:
    """Every way the vehicle (and its session) is not in a valid state; empty when it is."""
    problems = []
    if not all(math.isfinite(x) for x in v.body):
        problems.append(f"estimate not finite: {v.body}")
    b = v.sim.state.body  # the physical truth: the estimate may legitimately drift (SIM_BARO_DRIFT)
    if not all(math.isfinite(x) for x in b):
        problems.append(f"state not finite: {b}")
        return problems
    if not all(math.isfinite(w) for w in v.sim.state.omega_rad_s):
        problems.append(f"motor speeds not finite: {v.sim.state.omega_rad_s}")
    if abs(b.qw ** 2 + b.qx ** 2 + b.qy ** 2 + b.qz ** 2 - 1.0) > 1e-6:
        problems.append("attitude quaternion not normalised")
    if b.d_m > 0.01 + max(0.0, v.home_ned[2] if v.home_ned else 0.0):
        problems.append(f"below ground: d = {b.d_m}")
    if math.sqrt(b.vn_m_s ** 2 + b.ve_m_s ** 2 + b.vd_m_s ** 2) >= terminal_speed_m_s(v.config.sim.airframe):
        problems.append(f"absurd speed: {b}")
    if v.mode.number not in MODE_BY_NUMBER or v.modes[v.mode.number] is not v.mode:
        problems.append(f"mode {v.mode!r} not in the mode table")
    for spec in PARAM_TABLE:
        if spec.name in SET_UNCHECKED_BY_COMMANDS:
            continue
        value = v.params[spec.name]
        if not (math.isfinite(value) and spec.low <= value <= spec.high):
            problems.append(f"parameter {spec.name} = {value} outside {spec.low}..{spec.high}")
    if session is not None and session.counters.get("handler_errors", 0):
        problems.append(f"handler raised: {session.last_handler_error}")
    return problems

"""step_cost_us: wall microseconds per simulated physics step, for one vehicle and per vehicle when
many vehicles are stepped together. Each figure is a summary of several timed runs.

One vehicle, hovering at 10 m in GUIDED (the cascade fully at work):
- physics: the compiled physics step alone, at fixed motor commands;
- cascade: compiled physics + control (position, attitude, rate loops, allocation) per step, run in
  chunks of 4 steps as the vehicle runs it, so control = cascade - physics;
- vehicle: Vehicle.run_until, i.e. everything of the headless vehicle per physics step (the cascade
  plus the Python at 100 Hz: flight mode, land detector, sensors, battery, state snapshot);
- the same vehicle figure and the physics step in the Python reference, for comparison.
Batched: N hovering vehicles whose cascades run in one C call (run_many), per vehicle and step,
against the same N cascades called one by one from Python, and N whole vehicles stepped in turn.
"""
from __future__ import annotations

import time
from typing import Callable

from firefly.autopilot.control import _cascade
from firefly.autopilot.vehicle import Vehicle, VehicleConfig
from report import summary

CHUNK = 4  # physics steps per cascade run in a vehicle at 400 Hz (one flight-mode period)


def hovering(compiled: bool = True) -> Vehicle:
    v = Vehicle(VehicleConfig(compiled=compiled))
    v.run_until(0.5)
    v.set_mode(4)
    v.arm()
    v.takeoff(10.0)
    v.run_until(10.0)
    return v


def per_step_us(setup: Callable[[], object], run: Callable[[object], int], runs: int) -> dict:
    """For each run: subject = setup() (not timed), then run(subject) timed, which returns how many
    (vehicle-)steps it took. Microseconds per step, summarised over the runs."""
    values = []
    for _ in range(runs):
        subject = setup()
        t0 = time.perf_counter()
        steps = run(subject)
        values.append((time.perf_counter() - t0) / steps * 1e6)
    return summary(values)


def single(runs: int, steps: int = 40_000) -> dict:
    calls = steps // CHUNK

    def physics(v: Vehicle) -> int:
        loop = v.cascade.loop
        cmd = loop.omega_cmd
        for _ in range(calls):
            loop.run_physics(CHUNK, cmd)
        return calls * CHUNK

    def cascade(v: Vehicle) -> int:
        loop, first = v.cascade.loop, v.sim.steps
        for k in range(calls):
            loop.run(first + k * CHUNK, CHUNK)
        return calls * CHUNK

    def vehicle(v: Vehicle) -> int:
        s0 = v.sim.steps
        v.run_until(v.time_s + steps * v.sim.dt)
        return v.sim.steps - s0

    def python_physics(v: Vehicle) -> int:
        cmd = v.cascade.omega_cmd
        for _ in range(steps):
            v.sim.step(cmd)
        return steps

    def reference() -> Vehicle:
        return hovering(compiled=False)

    out = {"physics_step_us": per_step_us(hovering, physics, runs),
           "cascade_step_us": per_step_us(hovering, cascade, runs),
           "vehicle_step_us": per_step_us(hovering, vehicle, runs),
           "python_reference_physics_step_us": per_step_us(reference, python_physics, runs),
           "python_reference_vehicle_step_us": per_step_us(reference, vehicle, runs)}
    out["control_step_us"] = out["cascade_step_us"]["median"] - out["physics_step_us"]["median"]
    return out


def batched(counts: list[int], runs: int, vehicle_steps: int = 400_000) -> dict:
    out = {}
    for n in counts:
        vehicles = [hovering() for _ in range(n)]
        loops = [v.cascade.loop for v in vehicles]
        calls = max(1, vehicle_steps // (n * CHUNK))

        def together(first: int) -> int:
            for k in range(calls):
                _cascade.run_many(loops, first + k * CHUNK, CHUNK)
            return calls * CHUNK * n

        def one_by_one(first: int) -> int:
            for k in range(calls):
                step = first + k * CHUNK
                for loop in loops:
                    loop.run(step, CHUNK)
            return calls * CHUNK * n

        def whole_vehicles(t: float) -> int:
            for k in range(1, calls + 1):
                for v in vehicles:
                    v.run_until(t + k * CHUNK * v.sim.dt)
            return calls * CHUNK * n

        first = vehicles[0].sim.steps
        out[str(n)] = {"run_many_us": per_step_us(lambda: first, together, runs),
                       "one_call_each_us": per_step_us(lambda: first, one_by_one, runs),
                       "whole_vehicles_us": per_step_us(lambda: vehicles[0].time_s, whole_vehicles, runs)}
    return out

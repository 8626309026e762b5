"""The compiled battery step (sim/_battery.c, battery.h) and the Python reference (sim/battery.py)
compute the very same bits: over random packs and rotor speeds, on every segment of the discharge
curve and past both of its ends, when the power asked is more than the pack can give, and over
a whole flight of a vehicle, compared at every battery step."""
from __future__ import annotations

import math
import random

import pytest

import firefly.sim.vehicle
from firefly.autopilot.control import compiled
from firefly.autopilot.vehicle import Vehicle, VehicleConfig
from firefly.sim.battery import STEP_AT, BatteryState, compiled_step_battery_at, step_battery_at

if compiled.required() and compiled_step_battery_at is None:  # CI builds it or fails the install
    pytest.fail("CI=true but the compiled battery step (sim._battery) is not built; "
                "see the compile errors of `pip install` (setup.py)", pytrace=False)
pytestmark = pytest.mark.skipif(compiled_step_battery_at is None, reason="compiled battery step not built")

CONSTANTS = (3.1e-7, 4, 5000.0, 0.06, 0.5, 0.01)  # W per (rad/s)^3, cells, mAh, ohm, A, s


def both(state, omega, constants=CONSTANTS):
    return step_battery_at(state, omega, constants), compiled_step_battery_at(state, omega, constants)


def bits(state) -> tuple:
    """Each field's exact bits: 0.0 and -0.0 differ, a NaN equals a NaN."""
    return tuple(x.hex() for x in state)


def same(python, c) -> bool:
    """The same bits, the same type, and so the same hash (a NaN hashes by identity: not compared)."""
    hashes_comparable = not any(math.isnan(x) for x in python)
    return (bits(python) == bits(c) and type(c) is type(python)
            and (hash(c) == hash(python) or not hashes_comparable))


def test_the_simulator_steps_the_pack_with_the_compiled_step_when_built():
    assert STEP_AT is compiled_step_battery_at


def test_random_packs_and_rotor_speeds_give_the_same_bits_and_a_battery_state():
    rng = random.Random(7)
    for _ in range(20_000):
        state = BatteryState(rng.uniform(-500.0, 7000.0), rng.uniform(0.0, 60.0), rng.uniform(0.0, 26.0))
        omega = tuple(rng.uniform(0.0, 2500.0) for _ in range(4))
        constants = (rng.choice((1e-9, 3.1e-7, 2e-6)), rng.choice((3, 4, 6)), rng.choice((1000.0, 5000.0)),
                     rng.choice((0.01, 0.06, 0.3)), rng.uniform(0.0, 2.0), rng.choice((0.0025, 0.01)))
        python, c = both(state, omega, constants)
        assert same(python, c), (state, omega, constants)


@pytest.mark.parametrize("consumed_mah", [-100.0, 0.0, 250.0, 500.0, 1000.0, 2499.9, 2500.0, 4500.0, 4999.0,
                                          5000.0, 6000.0])
def test_every_segment_of_the_curve_and_past_both_ends(consumed_mah):
    python, c = both(BatteryState(consumed_mah, 0.0, 0.0), (800.0, 810.0, 790.0, 805.0))
    assert same(python, c)


def test_more_power_than_the_pack_can_give_takes_the_sag_limit_in_both():
    python, c = both(BatteryState(100.0, 0.0, 0.0), (1e5, 1e5, 1e5, 1e5))
    assert same(python, c)
    # ocv / 2R plus the avionics: about 139 A, the terminal voltage about half the 16.7 V at rest
    assert 130.0 < c.current_a < 150.0 and 7.0 < c.voltage_v < 9.0 and math.isfinite(c.consumed_mah)


@pytest.mark.parametrize("state, omega", [
    (BatteryState(math.nan, 0.0, 0.0), (800.0,) * 4),        # a NaN charge: the curve's first segment
    (BatteryState(10.0, 0.0, 0.0), (math.nan, 1.0, 1.0, 1.0)),  # a NaN rotor: the sag limit branch
    (BatteryState(-0.0, -0.0, -0.0), (0.0, -0.0, 0.0, 0.0)),   # signed zeros kept
    (BatteryState(math.inf, 0.0, 0.0), (800.0,) * 4),
])
def test_nan_infinite_and_signed_zero_inputs_give_the_same_bits(state, omega):
    python, c = both(state, omega)
    assert same(python, c)


def test_bad_arguments_are_refused_not_a_crash():
    with pytest.raises(TypeError):
        compiled_step_battery_at(BatteryState(), (1.0, 2.0, 3.0), CONSTANTS)  # three rotors
    with pytest.raises(TypeError):
        compiled_step_battery_at(BatteryState(), (1.0,) * 4, CONSTANTS[:5])
    with pytest.raises(TypeError):
        compiled_step_battery_at(BatteryState(), (1.0,) * 4)
    with pytest.raises(TypeError):
        compiled_step_battery_at((0.0, 0.0, 0.0), (1.0,) * 4, CONSTANTS)  # a plain tuple: no BatteryState


def test_a_whole_flight_drains_the_pack_the_same_with_either_step(monkeypatch):
    def fly(step) -> list:
        monkeypatch.setattr(firefly.sim.vehicle, "STEP_AT", step)
        v = Vehicle(VehicleConfig())
        states = []
        v.run_until(0.5)
        v.set_mode(4)
        v.arm()
        v.takeoff(15.0)
        while v.time_s < 25.0:
            v.run_until(v.time_s + 0.01)
            states.append(v.sim.battery)
        return states
    python, c = fly(step_battery_at), fly(compiled_step_battery_at)
    assert [bits(s) for s in python] == [bits(s) for s in c]
    assert python[-1].consumed_mah > python[0].consumed_mah and max(s.current_a for s in python) > 5.0

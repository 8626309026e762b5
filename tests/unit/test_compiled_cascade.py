"""The compiled cascade (C) and the readable Python reference compute the very same bits: the
physics step alone over random motor commands, and whole vehicles flown through every part of
the cascade (ground idle, takeoff, far gotos, yaw, velocity control, manual throttle and lean,
saturating gains, landing) and through injected faults (weak and failed motors, turbulence, a
changing wind, a drifting barometer) — compared at every physics step, exactly."""
from __future__ import annotations

import dataclasses
import os
import random
import subprocess
import sys
from pathlib import Path

import pytest

from firefly.autopilot.control import compiled
from firefly.autopilot.control.cascade import Cascade
from firefly.autopilot.mission import MissionItem
from firefly.autopilot.modes import Auto, Guided, Land, ModeNumber, Stabilize
from firefly.autopilot.params import SPEC_BY_NAME
from firefly.autopilot.rates import LoopRates
from firefly.autopilot.results import Result
from firefly.autopilot.vehicle import Vehicle, VehicleConfig
from firefly.sim.physics import initial_state, make_fast_step
from firefly.sim.rigid_body import BodyState
from firefly.sim.vehicle import SimConfig, SimVehicle
from firefly.sim.wind import SteadyWind

if compiled.required() and not compiled.available():  # in CI the whole run stops here, once, with the cause
    pytest.fail(f"CI=true but the compiled cascade is not built ({compiled.why_missing()}); "
                "see the compile errors of `pip install` (setup.py)", pytrace=False)
needs_extension = pytest.mark.skipif(not compiled.available(), reason="compiled cascade not built")


def twins(**config) -> tuple[Vehicle, Vehicle]:
    """The same vehicle twice: compiled cascade, Python reference."""
    a = Vehicle(VehicleConfig(compiled=True, **config))
    b = Vehicle(VehicleConfig(compiled=False, **config))
    assert isinstance(a.cascade, compiled.CompiledCascade)
    assert type(b.cascade) is Cascade
    return a, b


def taking_off(a: Vehicle, b: Vehicle, alt_m: float) -> None:
    """Both twins, half a second in: GUIDED, armed, told to take off to alt_m."""
    for v in (a, b):
        v.run_until(0.5)
        v.set_mode(Guided.number)
        v.arm()
        v.takeoff(alt_m)


def assert_same(a: Vehicle, b: Vehicle) -> None:
    assert a.sim.steps == b.sim.steps
    assert a.sim.state == b.sim.state  # every float, exactly
    assert a.cascade.thrust_t == b.cascade.thrust_t
    assert a.cascade.lean_t == b.cascade.lean_t
    assert a.cascade.yaw_t == b.cascade.yaw_t
    assert a.cascade.omega_cmd == b.cascade.omega_cmd


def lockstep(a: Vehicle, b: Vehicle, seconds: float) -> int:
    """Advance both one physics step at a time, comparing after every step. Returns how many
    steps the reference's allocator saturated (so a test can show it went there)."""
    saturated = 0
    for _ in range(round(seconds / a.sim.dt)):
        a.step()
        b.step()
        assert_same(a, b)
        saturated += b.cascade.allocator.saturated
    return saturated


def both(a: Vehicle, b: Vehicle, action) -> None:
    assert action(a) == action(b)


@needs_extension
def test_physics_step_twin_agrees_bit_for_bit_over_random_commands():
    rng = random.Random(11)
    sim = SimVehicle(SimConfig(wind=SteadyWind(4.0, 30.0)))
    sim.state = initial_state()._replace(body=BodyState(d_m=-20.0, qw=0.96, qx=0.2, qy=-0.1, qz=0.17), on_ground=False)
    loop = compiled.make_cascade(sim, Vehicle(VehicleConfig()).params, LoopRates()).loop
    fast = make_fast_step(sim.airframe, sim.dt)
    state = sim.state
    for i in range(4000):  # 10 s: random commands (some out of range), then a fall to the ground
        cmd = tuple(rng.uniform(-50, 700) for _ in range(4)) if i < 2000 else (0.0, 0.0, 0.0, 0.0)
        state = fast(state, cmd, sim.wind_ned)
        loop.run_physics(1, cmd)
        assert loop.state() == state
    assert state.on_ground


@needs_extension
def test_physics_step_twin_applies_the_same_motor_health_and_wind():
    rng = random.Random(12)
    sim = SimVehicle(SimConfig())
    sim.state = initial_state()._replace(body=BodyState(d_m=-30.0), on_ground=False)
    loop = compiled.make_cascade(sim, Vehicle(VehicleConfig()).params, LoopRates()).loop
    fast = make_fast_step(sim.airframe, sim.dt)
    state = sim.state
    for i in range(2000):
        if i % 100 == 0:  # new conditions every quarter second: a wind and four motor speed scales
            wind = tuple(rng.uniform(-8, 8) for _ in range(3))
            scale = tuple(rng.choice((1.0, 0.0, rng.random())) for _ in range(4))
            loop.set_conditions(wind, scale)
        cmd = tuple(rng.uniform(0, 650) for _ in range(4))
        state = fast(state, cmd, wind, scale)
        loop.run_physics(1, cmd)
        assert loop.state() == state


@needs_extension
def test_faults_fly_bit_identical_compiled_and_in_python():
    a, b = twins(sim=SimConfig(wind=SteadyWind(3.0, 90.0), seed=4))
    for v in (a, b):
        v.run_until(0.5)
    for action in (lambda v: v.set_mode(Guided.number), lambda v: v.arm(), lambda v: v.takeoff(10.0)):
        both(a, b, action)
    lockstep(a, b, 6.0)
    for name, value in (("SIM_WIND_TURB", 2.5), ("SIM_WIND_TC", 1.0), ("SIM_WIND_SPD", 8.0),
                        ("SIM_ENGINE_MUL", 0.77), ("SIM_ENGINE_FAIL", 8), ("SIM_BARO_DRIFT", 0.4)):
        both(a, b, lambda v: v.params.set(name, value))
    both(a, b, lambda v: v.guided_goto(20.0, 5.0, -12.0))
    lockstep(a, b, 6.0)
    both(a, b, lambda v: v.params.set("SIM_ENGINE_MUL", 0.0))  # the motor fails outright
    lockstep(a, b, 3.0)
    assert a.sim.wind_ned != SteadyWind(8.0, 90.0).velocity_ned()  # turbulence was really on
    assert a.sim.state.omega_rad_s[2] < 1.0  # and motor 3 really stopped


@needs_extension
def test_guided_flight_is_bit_identical_compiled_and_in_python():
    a, b = twins(sim=SimConfig(wind=SteadyWind(5.0, 200.0)), home_yaw_deg=30.0)
    lockstep(a, b, 0.6)  # disarmed: props stopped, controllers idle
    for action in (lambda v: v.set_mode(Guided.number), lambda v: v.arm()):
        both(a, b, action)
    lockstep(a, b, 0.5)  # armed on the ground: idle props
    both(a, b, lambda v: v.takeoff(12.0))
    lockstep(a, b, 8.0)
    both(a, b, lambda v: v.guided_goto(60.0, -40.0, -20.0, yaw=2.5))  # speed limited, yaw across pi
    lockstep(a, b, 6.0)
    both(a, b, lambda v: v.guided_velocity(-3.0, 2.0, -1.0))
    lockstep(a, b, 2.0)
    both(a, b, lambda v: v.set_yaw(170.0, relative=True, direction=-1))
    for name, value in (("ATC_RAT_RLL_P", 0.5), ("ATC_RAT_PIT_P", 0.5), ("ATC_RAT_YAW_P", 2.0)):
        both(a, b, lambda v: v.params.set(name, value))  # harsh gains, re-read by both
    both(a, b, lambda v: v.guided_goto(0.0, 0.0, -5.0))
    lockstep(a, b, 4.0)
    for name in ("ATC_RAT_RLL_P", "ATC_RAT_PIT_P", "ATC_RAT_YAW_P"):
        both(a, b, lambda v: v.params.set(name, SPEC_BY_NAME[name].default))
    both(a, b, lambda v: v.set_mode(Land.number))
    lockstep(a, b, 40.0)
    assert not a.armed and a.body.d_m == 0.0  # it flew the whole way down and disarmed


@needs_extension
def test_waypoint_mission_with_feed_forward_is_bit_identical_compiled_and_in_python():
    """AUTO's waypoint legs hand the cascade an acceleration feed-forward (Setpoint.accel_ne)."""
    a, b = twins(sim=SimConfig(wind=SteadyWind(3.0, 100.0)))
    lockstep(a, b, 0.5)
    for v in (a, b):
        items = [MissionItem(22, 3, z=8.0)]
        for n, e in ((25.0, 0.0), (25.0, 25.0), (0.0, 25.0)):
            g = v.ned_to_global(n, e, 0.0)
            items.append(MissionItem(16, 3, 0, 0, 0, 0, round(g.lat_deg * 1e7), round(g.lon_deg * 1e7), 8.0))
        v.mission.replace(0, items)
    for action in (lambda v: v.set_mode(Guided.number), lambda v: v.arm(), lambda v: v.set_mode(Auto.number),
                   lambda v: v.mission_start()):
        both(a, b, action)
    lockstep(a, b, 30.0)
    assert a.mission_progress.reached[:3] == [1, 2, 3]  # it flew the legs and a blended corner


@needs_extension
def test_manual_flight_is_bit_identical_compiled_and_in_python():
    a, b = twins()
    lockstep(a, b, 0.5)
    both(a, b, lambda v: v.set_mode(Stabilize.number))
    both(a, b, lambda v: v.arm())
    saturated = 0
    for roll, pitch, yaw, throttle, seconds in ((0.0, 0.0, 0.0, 0.9, 2.0), (1.0, -1.0, 0.5, 0.6, 1.5),
                                                (-0.7, 0.3, -1.0, 1.0, 1.0), (0.0, 0.0, 0.0, 0.3, 2.0)):
        for v in (a, b):
            v.rc.hold_sticks(roll, pitch, yaw, throttle, v.time_s)
        saturated += lockstep(a, b, seconds)
    assert a.body.d_m < -1.0  # it really flew
    assert saturated > 0  # full throttle with lean: the allocator's priorities were used


@needs_extension
def test_a_state_set_from_outside_is_where_the_compiled_cascade_goes_on_from():
    a, b = twins()
    taking_off(a, b, 5.0)
    for v in (a, b):
        v.run_until(3.0)
        v.sim.state = v.sim.state._replace(body=v.body._replace(n_m=7.0, vn_m_s=1.5))
    lockstep(a, b, 2.0)


@needs_extension
@pytest.mark.parametrize("rates", [LoopRates(800, 400, 100, 200), LoopRates(200, 200, 100)])
def test_other_loop_rates_agree_too(rates):
    sim = dataclasses.replace(SimConfig(), physics_rate_hz=rates.physics_hz)
    a, b = twins(sim=sim, rates=rates)
    for v in (a, b):
        v.run_until(0.5)
        v.set_mode(Guided.number)
        v.arm()
        v.takeoff(8.0)
    lockstep(a, b, 6.0)
    both(a, b, lambda v: v.guided_goto(15.0, 10.0, -8.0))
    lockstep(a, b, 4.0)


@needs_extension
def test_run_until_in_chunks_flies_the_same_as_single_steps():
    chunked, single = Vehicle(VehicleConfig()), Vehicle(VehicleConfig())
    for v in (chunked, single):
        v.run_until(0.5)
        v.set_mode(Guided.number)
        v.arm()
        v.takeoff(10.0)
    chunked.run_until(9.0037)  # not a multiple of any loop period
    while single.time_s < 9.0037 - 1e-9:
        single.step()
    assert chunked.sim.steps == single.sim.steps
    assert chunked.sim.state == single.sim.state
    assert chunked.sim.battery == single.sim.battery


def test_without_the_extension_vehicles_fly_the_reference_after_one_warning(monkeypatch, capsys):
    monkeypatch.setattr(compiled, "_cascade", None)
    monkeypatch.setattr(compiled, "_why_missing", "No module named 'firefly.autopilot.control._cascade'")
    monkeypatch.setattr(compiled, "_warned", False)
    vehicles = [Vehicle(VehicleConfig()) for _ in range(3)]
    assert all(type(v.cascade) is Cascade for v in vehicles)
    warning = capsys.readouterr().err.splitlines()
    assert len(warning) == 1 and "flying the Python reference" in warning[0]
    v = vehicles[0]
    v.run_until(0.5)
    v.set_mode(Guided.number)
    v.arm()
    v.takeoff(5.0)
    v.run_until(8.0)
    assert v.body.d_m == pytest.approx(-5.0, abs=0.3)


def compiled_twin() -> compiled.CompiledCascade:
    cascade = Vehicle(VehicleConfig()).cascade
    assert isinstance(cascade, compiled.CompiledCascade)
    return cascade


@needs_extension
def test_every_constant_and_gain_is_handed_over_by_a_name_the_loop_knows():
    from firefly.autopilot.control import _cascade
    from firefly.sim.physics import PhysicsState
    twin = compiled_twin()

    def new_loop(constants):
        return _cascade.Loop(constants, 1, 1, BodyState, PhysicsState)

    def without(numbers, part, name):
        numbers[part] = {k: v for k, v in numbers[part].items() if k != name}
        return numbers

    def renamed(numbers, part, name, new_name):
        numbers[part][new_name] = numbers[part].pop(name)
        return numbers

    with pytest.raises(KeyError, match=r"missing 'physics\.lag'"):
        new_loop(without(twin.constants(), "physics", "lag"))
    with pytest.raises(KeyError, match=r"unknown 'allocator\.fmax'"):
        new_loop(renamed(twin.constants(), "allocator", "f_max", "fmax"))
    with pytest.raises(KeyError, match=r"missing part 'cascade'"):
        new_loop({part: v for part, v in twin.constants().items() if part != "cascade"})
    with pytest.raises(KeyError, match=r"unknown part 'rate_roll'"):  # the gains' parts are not constants
        new_loop({**twin.constants(), "rate_roll": twin.gains()["rate_roll"]})
    with pytest.raises(TypeError):
        new_loop({**twin.constants(), "physics": list(twin.constants()["physics"].values())})  # by position
    with pytest.raises(TypeError):
        new_loop({**twin.constants(), "position": {**twin.constants()["position"], "mass": "1.5"}})
    with pytest.raises(KeyError, match=r"missing 'vel_d\.kd'"):
        twin.loop.configure(without(twin.gains(), "vel_d", "kd"))
    with pytest.raises(KeyError, match=r"unknown 'attitude\.angle_p'"):
        twin.loop.configure({**twin.gains(), "attitude": {**twin.gains()["attitude"], "angle_p": 4.5}})


@needs_extension
def test_a_refused_configure_leaves_the_gains_as_they_were():
    a, b = twins()
    taking_off(a, b, 6.0)
    gains = a.cascade.gains()
    gains["rate_roll"]["kp"] = 9.0  # read before the misspelled number is found
    gains["vel_e"]["k_i"] = gains["vel_e"].pop("ki")
    with pytest.raises(KeyError, match="vel_e.k_i"):
        a.cascade.loop.configure(gains)
    lockstep(a, b, 3.0)  # still flying the reference's gains, bit for bit


@needs_extension
def test_misusing_the_loop_object_raises_instead_of_crashing():
    from firefly.autopilot.control import _cascade
    from firefly.sim.physics import PhysicsState
    loop = _cascade.Loop
    with pytest.raises(RuntimeError):
        loop.__new__(loop).run(0, 1)  # never initialised: its loop ratios are 0
    with pytest.raises(RuntimeError):
        loop.__new__(loop).state()
    with pytest.raises(RuntimeError):
        _cascade.run_many([loop.__new__(loop)], 0, 1)
    with pytest.raises(TypeError):
        loop(compiled_twin().constants(), 1, 1, dict, dict)  # state() would fill these as tuples

    class Clearing:
        """A number whose conversion empties the containers it was read from (not a float
        subclass: C reads those without calling __float__)."""
        def __float__(self):
            for container in emptied:
                container.clear()
            return 1.0
    constants = compiled_twin().constants()
    constants["physics"]["m"] = Clearing()
    emptied = [constants["physics"], constants]
    with pytest.raises(KeyError):  # the numbers after it are gone: refused, no crash
        loop(constants, 1, 1, BodyState, PhysicsState)
    wind = [Clearing()] * 3
    emptied = [wind]
    assert compiled_twin().loop.set_conditions(wind, [1.0] * 4) is None  # read from a copy: no crash


def test_in_ci_a_missing_extension_stops_the_test_run_once_naming_the_cause():
    this = Path(__file__)
    # The extension made unimportable in a child pytest; with CI=true it must not just skip.
    child = ("import sys, pytest; sys.modules['firefly.autopilot.control._cascade'] = None; "
             f"sys.exit(pytest.main(['-q', '-p', 'no:cacheprovider', {str(this)!r}, "
             f"'--deselect', {str(this) + '::' + sys._getframe().f_code.co_name!r}]))")
    run = subprocess.run([sys.executable, "-c", child], cwd=this.parents[2], capture_output=True, text=True,
                         env={**os.environ, "CI": "true"}, timeout=120)
    out = run.stdout + run.stderr
    assert run.returncode != 0, out
    assert "CI=true but the compiled cascade is not built" in out, out
    assert "None in sys.modules" in out  # the import error itself, not just that it failed
    assert "1 error" in out and "Interrupted" in out, out  # one error, and nothing ran after it
    assert "passed" not in out and "skipped" not in out, out


@needs_extension
def test_autotune_twitches_are_bit_identical_compiled_and_in_python():
    """AUTOTUNE's trial gains (rate D on the error while FLTT is 0) reach the loop by name too."""
    a, b = twins()
    taking_off(a, b, 5.0)
    lockstep(a, b, 8.0)
    for v in (a, b):
        v.rc.hold_sticks(0.0, 0.0, 0.0, 0.5, v.time_s)
    both(a, b, lambda v: v.set_mode(ModeNumber.ALT_HOLD))
    lockstep(a, b, 0.5)
    assert a.set_mode(ModeNumber.AUTOTUNE) == b.set_mode(ModeNumber.AUTOTUNE) == Result.ACCEPTED
    twitching = 0
    for _ in range(300):
        lockstep(a, b, 0.01)
        twitching += b.cascade.attitude_ctl.rate_pids[0].d_on_error == 1.0
    assert twitching > 0  # the trial set was flown, not only the parameters' own

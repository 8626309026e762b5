"""Rigid-body physics, motors, ground contact, battery and wind: checked against the equations."""
from __future__ import annotations

import dataclasses
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from firefly.sim.airframe import GRAVITY_M_S2, Airframe
from firefly.sim.battery import (BatteryState, open_circuit_volts_per_cell, remaining_fraction,
                         step_battery)
from firefly.sim.physics import PhysicsState, initial_state, step
from firefly.sim.rigid_body import (BodyState, apply_ground, euler_from_quaternion, quaternion_from_euler,
                            step_body)
from firefly.sim.rotors import mix_forces, motor_lag_factor, rotor_forces, step_motors
from firefly.sim.sensors import Gps, NoiseConfig
from firefly.sim.wind import SteadyWind

AF = Airframe()
DT = 1.0 / 400.0
LAG = motor_lag_factor(AF, DT)
NO_WIND = (0.0, 0.0, 0.0)


def run(state: PhysicsState, omega_cmd, seconds: float, airframe: Airframe = AF, dt: float = DT,
        record=None) -> PhysicsState:
    lag = motor_lag_factor(airframe, dt)
    for _ in range(int(round(seconds / dt))):
        state = step(state, omega_cmd, airframe, NO_WIND, dt, lag)
        if record is not None:
            record.append(state)
    return state


def airborne(d_m: float, omega: float = 0.0, **body) -> PhysicsState:
    return PhysicsState(BodyState(d_m=d_m, **body), (omega,) * 4, False)


def quat_norm(b: BodyState) -> float:
    return math.sqrt(b.qw ** 2 + b.qx ** 2 + b.qy ** 2 + b.qz ** 2)


def rotate_body_to_ned(b: BodyState, v: tuple) -> tuple:
    w, x, y, z = b.qw, b.qx, b.qy, b.qz
    r = ((1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)),
         (2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)),
         (2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)))
    return tuple(sum(r[i][j] * v[j] for j in range(3)) for i in range(3))


# ----- hover equilibrium ---------------------------------------------------------------------
def test_hover_omega_gives_exactly_the_weight():
    omega = AF.hover_omega_rad_s
    u = mix_forces(rotor_forces((omega,) * 4, AF.thrust_coeff_b), AF.arm_length_m, AF.torque_ratio_c)
    assert abs(u[0] - AF.mass_kg * GRAVITY_M_S2) <= 1e-9
    assert u[1:] == (0.0, 0.0, 0.0)


def test_hover_equilibrium_holds_altitude_for_one_second():
    omega = AF.hover_omega_rad_s
    trace = []
    final = run(airborne(-10.0, omega), (omega,) * 4, 1.0, record=trace)
    assert max(abs(s.body.vd_m_s) for s in trace) < 1e-9
    assert abs(final.body.d_m + 10.0) < 1e-9
    assert not any(s.on_ground for s in trace)
    roll, pitch, _ = euler_from_quaternion(final.body.qw, final.body.qx, final.body.qy, final.body.qz)
    assert abs(roll) < 1e-12 and abs(pitch) < 1e-12


# ----- free fall ---------------------------------------------------------------------------------
def test_free_fall_without_drag_follows_g_t():
    af = dataclasses.replace(AF, linear_drag_n_per_m_s=0.0)
    t = 2.0
    final = run(airborne(-1000.0), (0.0,) * 4, t, airframe=af)
    assert final.body.vd_m_s == pytest.approx(GRAVITY_M_S2 * t, rel=1e-9)
    # Semi-implicit Euler drops g*t*dt/2 further than g t^2 / 2; allow one g*t*dt.
    drop = final.body.d_m + 1000.0
    assert abs(drop - 0.5 * GRAVITY_M_S2 * t * t) <= GRAVITY_M_S2 * t * DT
    assert final.body.vn_m_s == 0.0 and final.body.ve_m_s == 0.0


def test_free_fall_with_linear_drag_matches_exponential_approach_to_terminal_speed():
    t = 3.0
    k, m = AF.linear_drag_n_per_m_s, AF.mass_kg
    final = run(airborne(-1000.0), (0.0,) * 4, t)
    expected = (m * GRAVITY_M_S2 / k) * (1.0 - math.exp(-k * t / m))
    assert final.body.vd_m_s < GRAVITY_M_S2 * t
    assert final.body.vd_m_s == pytest.approx(expected, rel=2e-3)


# ----- ground contact ------------------------------------------------------------------------
def test_drop_from_5m_never_penetrates_and_ends_level_at_rest():
    yaw = 1.0
    qw, qx, qy, qz = quaternion_from_euler(0.3, -0.2, yaw)
    start = airborne(-5.0, qw=qw, qx=qx, qy=qy, qz=qz, p_rad_s=0.5, q_rad_s=-0.4, r_rad_s=0.0)
    trace = []
    final = run(start, (0.0,) * 4, 3.0, record=trace)
    assert max(s.body.d_m for s in trace) <= 0.0
    assert any(s.on_ground for s in trace)
    b = final.body
    assert final.on_ground
    assert b.d_m == 0.0
    assert (b.vn_m_s, b.ve_m_s, b.vd_m_s) == (0.0, 0.0, 0.0)
    assert (b.p_rad_s, b.q_rad_s, b.r_rad_s) == (0.0, 0.0, 0.0)
    roll, pitch, final_yaw = euler_from_quaternion(b.qw, b.qx, b.qy, b.qz)
    assert abs(roll) < 1e-12 and abs(pitch) < 1e-12
    # The ground levels the body about its own heading; heading at touchdown is kept.
    touchdown = next(s for s in trace if s.on_ground)
    _, _, yaw_td = euler_from_quaternion(touchdown.body.qw, touchdown.body.qx, touchdown.body.qy,
                                         touchdown.body.qz)
    assert final_yaw == pytest.approx(yaw_td, abs=1e-9)


def test_resting_vehicle_with_zero_thrust_stays_on_the_ground():
    trace = []
    final = run(initial_state(yaw_rad=0.5), (0.0,) * 4, 1.0, record=trace)
    assert all(s.on_ground and s.body.d_m == 0.0 for s in trace)
    assert final.body.vd_m_s == 0.0


def test_thrust_below_weight_does_not_lift_off():
    omega = AF.hover_omega_rad_s * math.sqrt(0.95)  # 95 % of the weight
    trace = []
    run(initial_state(), (omega,) * 4, 1.0, record=trace)
    assert all(s.on_ground and s.body.d_m == 0.0 for s in trace)


def test_thrust_above_weight_lifts_off():
    omega = AF.hover_omega_rad_s * math.sqrt(1.2)  # thrust = 1.2 * weight
    final = run(initial_state(), (omega,) * 4, 1.0)
    assert not final.on_ground
    assert final.body.vd_m_s < 0.0
    # Net force 0.2 W against linear drag: climb(t) = (F/k)(t - (m/k)(1 - exp(-k t / m))).
    # The motors spin up from rest (tau = 30 ms), which delays the climb by well under 0.2 s.
    f, k, m = 0.2 * AF.weight_n, AF.linear_drag_n_per_m_s, AF.mass_kg

    def climb(t):
        return (f / k) * (t - (m / k) * (1.0 - math.exp(-k * t / m)))

    assert climb(0.8) <= -final.body.d_m <= climb(1.0)


def test_apply_ground_leaves_airborne_and_climbing_bodies_moving():
    above = BodyState(d_m=-0.01, vd_m_s=1.0)
    assert apply_ground(above) == (above, False)
    climbing = BodyState(d_m=0.001, vd_m_s=-0.5, vn_m_s=0.2)
    corrected, contact = apply_ground(climbing)
    assert not contact and corrected.d_m == 0.0
    assert corrected.vd_m_s == -0.5 and corrected.vn_m_s == 0.2


# ----- thrust and torque directions ------------------------------------------------------------
@pytest.mark.parametrize("roll,pitch,yaw,axis,sign", [
    (0.0, -0.2, 0.0, 0, +1),          # nose down, heading north: accelerate north
    (0.0, 0.2, 0.0, 0, -1),           # nose up: accelerate south
    (0.2, 0.0, 0.0, 1, +1),           # right wing down, heading north: accelerate east
    (0.0, -0.2, math.pi / 2, 1, +1),  # nose down, heading east: accelerate east
])
def test_tilted_thrust_accelerates_toward_the_low_side(roll, pitch, yaw, axis, sign):
    qw, qx, qy, qz = quaternion_from_euler(roll, pitch, yaw)
    s = BodyState(d_m=-10.0, qw=qw, qx=qx, qy=qy, qz=qz)
    u1 = AF.weight_n
    out = step_body(s, (u1, 0.0, 0.0, 0.0), AF, NO_WIND, DT)
    v = (out.vn_m_s, out.ve_m_s)
    tilt = math.acos(math.cos(roll) * math.cos(pitch))
    expected = u1 * math.sin(tilt) / AF.mass_kg * DT
    assert sign * v[axis] == pytest.approx(expected, rel=1e-6)
    assert abs(v[1 - axis]) < 1e-12


@pytest.mark.parametrize("motor,rate_index,sign", [
    (0, 1, +1),  # front motor faster: nose up, q > 0
    (2, 1, -1),  # back motor faster: nose down
    (1, 0, +1),  # left motor faster: roll right, p > 0
    (3, 0, -1),  # right motor faster: roll left
])
def test_one_faster_motor_tilts_the_body_the_right_way(motor, rate_index, sign):
    omega = [AF.hover_omega_rad_s] * 4
    omega[motor] *= 1.05
    final = run(airborne(-10.0, AF.hover_omega_rad_s), tuple(omega), 0.05)
    rates = (final.body.p_rad_s, final.body.q_rad_s, final.body.r_rad_s)
    assert sign * rates[rate_index] > 1e-3
    other_tilt = rates[1 - rate_index]
    # Yaw picks up the single motor's reaction torque; the other tilt axis only sees the
    # second-order gyroscopic coupling of the two rates.
    assert abs(other_tilt) < 0.01 * abs(rates[rate_index])


def test_yaw_torque_follows_u4_sign():
    h = AF.hover_omega_rad_s
    final = run(airborne(-10.0, h), (h * 1.02, h * 0.98, h * 1.02, h * 0.98), 0.1)
    assert final.body.r_rad_s > 1e-3
    assert abs(final.body.p_rad_s) < 1e-12 and abs(final.body.q_rad_s) < 1e-12


# ----- full rigid-body rotation ------------------------------------------------------------------
def test_gyroscopic_coupling_spin_plus_roll_gives_pitch_acceleration():
    af = dataclasses.replace(AF, angular_drag_nm_per_rad_s=0.0)
    assert af.ixx_kg_m2 != af.izz_kg_m2
    p, r = 1.0, 10.0
    s = BodyState(d_m=-10.0, p_rad_s=p, r_rad_s=r)
    out = step_body(s, (af.weight_n, 0.0, 0.0, 0.0), af, NO_WIND, DT)
    # Euler's equation: Iyy q_dot = (Izz - Ixx) r p.
    expected_q_dot = (af.izz_kg_m2 - af.ixx_kg_m2) * r * p / af.iyy_kg_m2
    assert out.q_rad_s / DT == pytest.approx(expected_q_dot, rel=1e-12)
    assert out.q_rad_s != 0.0


def test_no_gyroscopic_pitch_when_ixx_equals_izz():
    af = dataclasses.replace(AF, angular_drag_nm_per_rad_s=0.0, izz_kg_m2=AF.ixx_kg_m2)
    s = BodyState(d_m=-10.0, p_rad_s=1.0, r_rad_s=10.0)
    out = step_body(s, (af.weight_n, 0.0, 0.0, 0.0), af, NO_WIND, DT)
    assert out.q_rad_s == 0.0


def test_torque_free_tumbling_conserves_inertial_angular_momentum_and_energy():
    af = dataclasses.replace(AF, angular_drag_nm_per_rad_s=0.0, ixx_kg_m2=0.03, iyy_kg_m2=0.05)
    inertia = (af.ixx_kg_m2, af.iyy_kg_m2, af.izz_kg_m2)
    dt = 1e-4
    s = BodyState(d_m=-1000.0, p_rad_s=1.0, q_rad_s=0.5, r_rad_s=3.0)

    def momentum(b):
        return rotate_body_to_ned(b, tuple(i * w for i, w in zip(inertia, (b.p_rad_s, b.q_rad_s,
                                                                            b.r_rad_s))))

    def energy(b):
        return 0.5 * sum(i * w * w for i, w in zip(inertia, (b.p_rad_s, b.q_rad_s, b.r_rad_s)))

    l0, e0 = momentum(s), energy(s)
    for _ in range(10000):  # one second
        s = step_body(s, (0.0, 0.0, 0.0, 0.0), af, NO_WIND, dt)
    l1, e1 = momentum(s), energy(s)
    l_mag = math.sqrt(sum(x * x for x in l0))
    # First-order integrator: the drift is O(dt) per second; 1e-4 s steps keep it well under 1 %.
    assert math.dist(l0, l1) < 0.01 * l_mag
    assert e1 == pytest.approx(e0, rel=0.01)
    # The body really did tumble (otherwise the test proves nothing).
    assert abs(s.p_rad_s - 1.0) > 0.05 or abs(s.q_rad_s - 0.5) > 0.05


@settings(max_examples=30, deadline=None)
@given(st.tuples(*[st.floats(-20.0, 20.0)] * 3), st.tuples(*[st.floats(-0.5, 0.5)] * 3))
def test_quaternion_stays_unit_norm(rates, torques):
    s = BodyState(d_m=-1000.0, p_rad_s=rates[0], q_rad_s=rates[1], r_rad_s=rates[2])
    for _ in range(400):
        s = step_body(s, (AF.weight_n, *torques), AF, NO_WIND, DT)
        assert abs(quat_norm(s) - 1.0) < 1e-12


@pytest.mark.parametrize("roll,pitch,yaw", [(0.0, 0.0, 0.0), (0.3, -0.2, 1.0), (-1.0, 0.7, -3.0),
                                            (0.1, 1.4, 2.5)])
def test_euler_quaternion_round_trip(roll, pitch, yaw):
    q = quaternion_from_euler(roll, pitch, yaw)
    assert math.sqrt(sum(x * x for x in q)) == pytest.approx(1.0, abs=1e-12)
    assert euler_from_quaternion(*q) == pytest.approx((roll, pitch, yaw), abs=1e-9)


# ----- motors -----------------------------------------------------------------------------------
def test_motor_lag_is_the_exact_first_order_response():
    n = int(round(AF.motor_time_constant_s / DT))
    omega = (0.0,) * 4
    for _ in range(n):
        omega = step_motors(omega, (500.0,) * 4, LAG, AF.omega_max_rad_s)
    expected = 500.0 * (1.0 - math.exp(-n * DT / AF.motor_time_constant_s))
    assert omega == pytest.approx((expected,) * 4, rel=1e-12)


def test_motor_commands_are_saturated_to_zero_and_omega_max():
    omega = (300.0,) * 4
    for _ in range(4000):
        omega = step_motors(omega, (-50.0, 1e6, 0.0, AF.omega_max_rad_s), LAG, AF.omega_max_rad_s)
    assert omega[0] == pytest.approx(0.0, abs=1e-9)
    assert omega[1] == pytest.approx(AF.omega_max_rad_s, rel=1e-12)
    assert max(omega) <= AF.omega_max_rad_s
    assert min(omega) >= 0.0


def test_airframe_validate_accepts_default_and_rejects_nonsense():
    AF.validate()
    with pytest.raises(ValueError, match="mass_kg"):
        dataclasses.replace(AF, mass_kg=-1.0).validate()
    with pytest.raises(ValueError, match="omega_max_rad_s"):
        dataclasses.replace(AF, omega_max_rad_s=100.0).validate()  # cannot lift itself


@pytest.mark.parametrize("field,value", [("linear_drag_n_per_m_s", -1.0),
                                         ("angular_drag_nm_per_rad_s", -0.01),
                                         ("omega_idle_rad_s", 700.0)])
def test_airframe_validate_rejects_unphysical_drag_and_idle(field, value):
    with pytest.raises(ValueError, match=field):
        dataclasses.replace(AF, **{field: value}).validate()


# ----- battery and wind -------------------------------------------------------------------------
def test_open_circuit_voltage_is_monotonic_between_empty_and_full():
    assert open_circuit_volts_per_cell(1.0) == pytest.approx(4.2)
    assert open_circuit_volts_per_cell(0.0) < 3.4
    values = [open_circuit_volts_per_cell(i / 100) for i in range(101)]
    assert all(b > a for a, b in zip(values, values[1:]))


def test_battery_counts_one_amp_hour_as_1000_mah():
    state = BatteryState(0.0, 0.0, 16.8)
    for _ in range(3600):
        state = step_battery(state, 0.0, 4, 5000.0, 0.06, 1.0, 1.0)
    assert state.consumed_mah == pytest.approx(1000.0, rel=1e-9)
    assert remaining_fraction(state, 5000.0) == pytest.approx(0.8, rel=1e-9)


def test_battery_terminal_power_balance_and_sag():
    state = BatteryState(0.0, 0.0, 16.8)
    light = step_battery(state, 50.0, 4, 5000.0, 0.06, 0.0, 0.01)
    heavy = step_battery(state, 400.0, 4, 5000.0, 0.06, 0.0, 0.01)
    assert light.voltage_v * light.current_a == pytest.approx(50.0, rel=1e-9)
    assert heavy.voltage_v * heavy.current_a == pytest.approx(400.0, rel=1e-9)
    assert heavy.voltage_v < light.voltage_v < 4 * 4.2


def test_wind_from_north_blows_south_and_drags_the_vehicle_south():
    wind = SteadyWind(5.0, 0.0).velocity_ned()
    assert wind == pytest.approx((-5.0, 0.0, 0.0), abs=1e-12)
    assert SteadyWind(5.0, 90.0).velocity_ned() == pytest.approx((0.0, -5.0, 0.0), abs=1e-12)
    s = BodyState(d_m=-10.0)
    out = step_body(s, (AF.weight_n, 0.0, 0.0, 0.0), AF, wind, DT)
    assert out.vn_m_s == pytest.approx(-AF.linear_drag_n_per_m_s * 5.0 / AF.mass_kg * DT, rel=1e-9)


def test_sensors_with_the_same_seed_read_the_same_noise():
    body = BodyState(d_m=-10.0)
    a, b, c = Gps(7, NoiseConfig()), Gps(7, NoiseConfig()), Gps(8, NoiseConfig())
    ra = [a.read(body) for _ in range(5)]
    assert ra == [b.read(body) for _ in range(5)]
    assert ra != [c.read(body) for _ in range(5)]
    assert all(r.fix_type == 3 for r in ra)


def test_fast_step_agrees_with_the_reference_step():
    """The inlined hot path and the readable composition of motors, mixer and rigid body agree."""
    import random

    from firefly.sim.physics import make_fast_step
    from firefly.sim.rotors import motor_lag_factor
    rng = random.Random(5)
    dt = 1 / 400
    fast = make_fast_step(AF, dt)
    lag = motor_lag_factor(AF, dt)
    s_ref = s_fast = initial_state()._replace(body=BodyState(d_m=-20.0), on_ground=False)
    for i in range(4000):  # 10 s of random motor commands, through the air and down to the ground
        cmd = tuple(rng.uniform(0, 700) for _ in range(4)) if i < 2000 else (0.0, 0.0, 0.0, 0.0)
        wind = (1.0, -2.0, 0.1)
        scale = (1.0, 0.8, 1.0, 0.3) if i % 1000 < 500 else (1.0, 1.0, 1.0, 1.0)  # weak motors at times
        s_ref = step(s_ref, cmd, AF, wind, dt, lag, scale)
        s_fast = fast(s_fast, cmd, wind, scale)
        for a, b in zip(s_ref.body + s_ref.omega_rad_s, s_fast.body + s_fast.omega_rad_s):
            assert a == pytest.approx(b, rel=1e-9, abs=1e-9)
        assert s_ref.on_ground == s_fast.on_ground
    assert s_fast.on_ground  # the drop ended on the ground

"""The paper's mixer (eq. 2), its inverse, and the saturating thrust allocator."""
from __future__ import annotations

import math

import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from firefly.autopilot.control.allocation import Allocator
from firefly.sim.airframe import Airframe
from firefly.sim.rotors import mix_forces, unmix

AF = Airframe()
L, C = AF.arm_length_m, AF.torque_ratio_c
ALLOC = Allocator(AF)
F_MIN, F_MAX = ALLOC.f_min, ALLOC.f_max
TOL = 1e-9

finite = dict(allow_nan=False, allow_infinity=False)


def close(a, b, tol=TOL):
    return all(math.isclose(x, y, rel_tol=tol, abs_tol=tol) for x, y in zip(a, b))


# ----- mixer -------------------------------------------------------------------------------------
@settings(max_examples=300)
@given(st.floats(-100, 100, **finite), st.floats(-10, 10, **finite), st.floats(-10, 10, **finite),
       st.floats(-1, 1, **finite), st.floats(0.05, 1.0, **finite), st.floats(1e-3, 0.1, **finite))
def test_unmix_then_mix_is_identity(u1, u2, u3, u4, l, c):
    assert close(mix_forces(unmix(u1, u2, u3, u4, l, c), l, c), (u1, u2, u3, u4))


@settings(max_examples=300)
@given(st.tuples(*[st.floats(-50, 50, **finite)] * 4), st.floats(0.05, 1.0, **finite),
       st.floats(1e-3, 0.1, **finite))
def test_mix_then_unmix_is_identity(forces, l, c):
    assert close(unmix(*mix_forces(forces, l, c), l, c), forces)


def test_mixer_matches_the_papers_formulas():
    f1, f2, f3, f4 = 1.0, 2.5, 4.0, 7.0
    u1, u2, u3, u4 = mix_forces((f1, f2, f3, f4), L, C)
    assert u1 == pytest.approx(f1 + f2 + f3 + f4)
    assert u2 == pytest.approx(L * (f2 - f4))
    assert u3 == pytest.approx(L * (f1 - f3))
    assert u4 == pytest.approx(C * (f1 - f2 + f3 - f4))


def test_mixer_torques_equal_r_cross_f_for_the_plus_frame():
    """Motors at +x (1), -y (2), -x (3), +y (4) in FRD, thrust along body -z."""
    positions = ((L, 0.0, 0.0), (0.0, -L, 0.0), (-L, 0.0, 0.0), (0.0, L, 0.0))
    forces = (3.0, 1.0, 2.0, 5.0)
    torque = [0.0, 0.0, 0.0]
    for (rx, ry, rz), f in zip(positions, forces):
        fx, fy, fz = 0.0, 0.0, -f
        torque[0] += ry * fz - rz * fy
        torque[1] += rz * fx - rx * fz
    _, u2, u3, _ = mix_forces(forces, L, C)
    assert (u2, u3) == pytest.approx((torque[0], torque[1]))


def test_torque_ratio_is_drag_over_thrust_coefficient():
    assert C == pytest.approx(AF.drag_coeff_d / AF.thrust_coeff_b)


# ----- allocator ---------------------------------------------------------------------------------
u1_s = st.floats(0.0, 4.5 * F_MAX, **finite)
u2_s = st.floats(-3 * L * F_MAX, 3 * L * F_MAX, **finite)
u4_s = st.floats(-3 * C * F_MAX, 3 * C * F_MAX, **finite)


@settings(max_examples=500)
@given(u1_s, u2_s, u2_s, u4_s)
def test_allocator_forces_always_within_motor_limits(u1, u2, u3, u4):
    forces = ALLOC.forces(u1, u2, u3, u4)
    assert all(F_MIN - TOL <= f <= F_MAX + TOL for f in forces)


# Demands drawn mostly inside the motors' range: from the wide strategies above, most draws do
# not fit, and Hypothesis's health check fails the test at random for filtering too many out.
u1_fits = st.floats(1.0 * F_MAX, 3.0 * F_MAX, **finite)
u2_fits = st.floats(-0.5 * L * F_MAX, 0.5 * L * F_MAX, **finite)


@settings(max_examples=500)
@given(u1_fits, u2_fits, u2_fits)
def test_allocator_is_exact_without_yaw_whenever_the_demand_fits(u1, u2, u3):
    exact = unmix(u1, u2, u3, 0.0, L, C)
    # Fits with a margin of round-off: a demand exactly at a motor limit may read as just past it.
    assume(all(F_MIN + TOL <= f <= F_MAX - TOL for f in exact))
    forces = ALLOC.forces(u1, u2, u3, 0.0)
    assert close(forces, exact)
    assert not ALLOC.saturated


@settings(max_examples=500)
@given(u1_s, u2_s, u2_s, u4_s)
def test_allocator_keeps_roll_and_pitch_exact_when_they_fit(u1, u2, u3, u4):
    # Roll/pitch fit when the differential they need (2|roll|, 2|pitch|) fits the motor range.
    assume(max(abs(u2), abs(u3)) / L <= 0.999 * (F_MAX - F_MIN))
    _, out2, out3, out4 = mix_forces(ALLOC.forces(u1, u2, u3, u4), L, C)
    assert out2 == pytest.approx(u2, abs=1e-9)
    assert out3 == pytest.approx(u3, abs=1e-9)
    # Yaw is only ever reduced, never reversed or amplified.
    assert abs(out4) <= abs(u4) + 1e-9
    assert out4 * u4 >= -1e-12  # zero allowed (to round-off) when there is no room at all


def test_allocator_sacrifices_yaw_first_when_saturated():
    u1, u2, u3 = AF.weight_n, 0.3, -0.2
    u4 = 2.5 * C * F_MAX  # far more yaw than the motors can give
    forces = ALLOC.forces(u1, u2, u3, u4)
    out = mix_forces(forces, L, C)
    assert ALLOC.saturated
    assert out[0] == pytest.approx(u1, rel=1e-12)
    assert out[1] == pytest.approx(u2, rel=1e-12)
    assert out[2] == pytest.approx(u3, rel=1e-12)
    assert 0.0 < out[3] < u4
    # Yaw got all there was: some motor sits on a limit.
    assert any(math.isclose(f, F_MAX, abs_tol=1e-9) or math.isclose(f, F_MIN, abs_tol=1e-9)
               for f in forces)


def test_allocator_shifts_thrust_to_keep_attitude_at_full_throttle():
    u1, u2 = 4.0 * F_MAX, 0.5  # full thrust plus a roll demand
    out = mix_forces(ALLOC.forces(u1, u2, 0.0, 0.0), L, C)
    assert ALLOC.saturated
    assert out[1] == pytest.approx(u2, rel=1e-12)
    assert out[0] < u1


def test_allocator_scales_roll_pitch_keeping_direction_when_infeasible():
    u2, u3 = 4.0 * L * F_MAX, -2.0 * L * F_MAX  # more than any split can give
    forces = ALLOC.forces(AF.weight_n, u2, u3, 0.0)
    _, out2, out3, _ = mix_forces(forces, L, C)
    assert ALLOC.saturated
    assert out2 / out3 == pytest.approx(u2 / u3, rel=1e-9)
    assert 0.0 < out2 < u2
    assert max(forces) == pytest.approx(F_MAX) and min(forces) == pytest.approx(F_MIN)


def test_omega_commands_give_the_allocated_forces():
    forces = ALLOC.forces(AF.weight_n, 0.1, -0.05, 0.01)
    omegas = ALLOC.omega_commands(AF.weight_n, 0.1, -0.05, 0.01)
    assert [AF.thrust_coeff_b * w * w for w in omegas] == pytest.approx(list(forces), rel=1e-12)
    assert all(w <= AF.omega_max_rad_s + 1e-9 for w in omegas)


def test_allocator_is_exact_whenever_the_exact_inverse_fits():
    # Low collective, strong pitch and yaw: unmix gives (4.8, 0.2, 0.8, 0.2) N, all within
    # [f_min, f_max], so the allocator has no reason to change anything.
    u = (6.0, 0.0, 2.0 * L * 2.0, 4.0 * C * 1.3)
    exact = unmix(*u, L, C)
    assert all(F_MIN <= f <= F_MAX for f in exact)
    assert close(ALLOC.forces(*u), exact)

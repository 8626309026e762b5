"""Flight modes: setpoints from a stand-in context, and short flights through the real vehicle."""
from __future__ import annotations

import math
from types import SimpleNamespace

import pytest

from firefly.autopilot.modes import AltHold, Brake, Guided, Land, Loiter, PosHold, Rtl, Setpoint, Stabilize
from firefly.autopilot.modes.base import stick_deadzone
from firefly.autopilot.modes.guided import VELOCITY_TIMEOUT_S
from firefly.autopilot.modes.land import descent_rate_m_s
from firefly.autopilot.modes.manual import pilot_climb_rate
from firefly.autopilot.params import ParamStore
from firefly.autopilot.pilot import PilotInput
from firefly.autopilot.results import Result
from firefly.sim.rigid_body import BodyState

from ._util import altitude, fly_until, hovering_vehicle, throttle_at_mid


def ctx(d_m=0.0, landed=False, armed=True, pilot=None, params=None, **body):
    disarms = []
    c = SimpleNamespace(body=BodyState(d_m=d_m, **body), params=params or ParamStore(),
                        home_ned=(0.0, 0.0, 0.0), landed=landed, landed_at_s=0.0, armed=armed, time_s=0.0,
                        attitude=(0.0, 0.0, 0.0), pilot=pilot or PilotInput(throttle=0.5),
                        nav_speed_m_s=10.0, disarms=disarms)
    c.disarm = lambda reason="": disarms.append(reason)
    c.notify = lambda *a: None
    c.has_position = lambda: True
    c.require_home = lambda: c.home_ned
    c.height_ref_d = 0.0
    c.precland_kind = 0  # no precision landing
    c.enabled_fences = 0  # no fence on
    c.avoid_velocity = lambda vel, accel, dt: vel  # no fence
    c.avoid_climb = lambda climb, dt: climb
    c.avoid_lean = lambda lean: lean
    c.destination_within_fence = lambda n, e, d: True
    return c


# ----- pure helpers -------------------------------------------------------------------------------
def test_setpoint_wants_climb():
    sp = Setpoint()
    assert not sp.wants_climb(0.0)
    sp.pos_d = -1.0
    assert sp.wants_climb(0.0)
    sp.pos_d = -0.1  # within 20 cm: not a climb
    assert not sp.wants_climb(0.0)
    sp.pos_d = None
    sp.vel_d = -0.5
    assert sp.wants_climb(0.0)
    sp.throttle = 0.0  # manual throttle decides
    assert not sp.wants_climb(0.0)
    sp.throttle = 0.3
    assert sp.wants_climb(0.0)


def test_stick_deadzone_is_zero_inside_continuous_outside_and_full_at_the_end():
    assert stick_deadzone(0.04) == 0.0
    assert stick_deadzone(0.05 + 1e-9) == pytest.approx(0.0, abs=1e-6)
    assert stick_deadzone(1.0) == 1.0 and stick_deadzone(-1.0) == -1.0
    assert stick_deadzone(0.5) == pytest.approx(-stick_deadzone(-0.5))


@pytest.mark.parametrize("speed, stop_m", [(2.0, 2.0), (5.0, 0.5 * 2.5 + 25.0 / 5.0)])
def test_guided_taking_over_at_speed_holds_the_stopping_point_ahead(speed, stop_m):
    """Not the point where the mode changed: ArduCopter's GUIDED stops ahead and stays there.
    P = 1/s, accel 2.5 m/s/s: v/P below 2.5 m/s, accel/(2P^2) + v^2/(2 accel) above."""
    c = ctx(d_m=-10.0, n_m=3.0, vn_m_s=speed * 0.6, ve_m_s=speed * 0.8)
    mode = Guided()
    mode.enter(c)
    (n, e), d = mode.target_ne, mode.target_d
    assert n == pytest.approx(3.0 + 0.6 * stop_m) and e == pytest.approx(0.8 * stop_m) and d == -10.0
    still = ctx(d_m=-10.0, n_m=3.0)
    mode.enter(still)
    assert mode.target_ne == (3.0, 0.0)


def test_land_descent_is_fast_high_and_slow_low():
    params = ParamStore()
    high = ctx(d_m=-(params["LAND_ALT_LOW"] / 100.0 + 5.0), params=params)
    low = ctx(d_m=-2.0, params=params)
    assert descent_rate_m_s(high) == params["WPNAV_SPEED_DN"] / 100.0
    assert descent_rate_m_s(low) == params["LAND_SPEED"] / 100.0
    params.set("LAND_SPEED_HIGH", 200)
    assert descent_rate_m_s(high) == 2.0


def test_pilot_climb_rate_from_throttle_stick():
    params = ParamStore()
    up = params["PILOT_SPEED_UP"] / 100.0
    assert pilot_climb_rate(ctx(pilot=PilotInput(throttle=0.5))) == 0.0
    assert pilot_climb_rate(ctx(pilot=PilotInput(throttle=0.53))) == 0.0  # dead zone
    assert pilot_climb_rate(ctx(pilot=PilotInput(throttle=1.0))) == pytest.approx(up)
    # PILOT_SPEED_DN = 0 means "same as up".
    assert pilot_climb_rate(ctx(pilot=PilotInput(throttle=0.0))) == pytest.approx(-up)


def test_land_mode_setpoint_holds_position_and_descends():
    mode = Land()
    c = ctx(d_m=-5.0, n_m=3.0, e_m=4.0)
    assert mode.enter(c) is None
    sp = Setpoint()
    mode.update(c, sp, 0.01)
    assert sp.pos_ne == (3.0, 4.0)
    assert sp.pos_d is None and sp.vel_d > 0.0
    assert mode.landed_state_hint(c) == "LANDING"
    c.landed, c.landed_at_s, c.time_s = True, 20.0, 20.0
    mode.update(c, sp, 0.01)
    assert c.disarms == [], "the motors first spool down to ground idle (MOT_SPOOL_TIME)"
    c.time_s = 20.0 + c.params["MOT_SPOOL_TIME"] - 0.01
    mode.update(c, sp, 0.01)
    assert c.disarms == []
    c.time_s = 20.0 + c.params["MOT_SPOOL_TIME"]
    mode.update(c, sp, 0.01)
    assert c.disarms == ["landed"]


def test_guided_velocity_setpoint_times_out_to_a_stop():
    """As ArduCopter's GUID_TIMEOUT: the velocity becomes zero (the vehicle slows down where it is
    going, at WPNAV_ACCEL, rather than turning back to a point)."""
    mode = Guided()
    c = ctx(d_m=-5.0)
    mode.enter(c)
    mode.set_velocity(c, 2.0, 0.0, 0.0)
    sp = Setpoint()
    mode.update(c, sp, 0.01)
    assert sp.vel_ne == (2.0, 0.0) and sp.pos_ne is None
    c.time_s = VELOCITY_TIMEOUT_S + 0.1
    c.body = BodyState(n_m=7.0, e_m=1.0, d_m=-5.0)
    mode.update(c, sp, 0.01)
    assert sp.pos_ne is None and 0.0 < sp.vel_ne[0] < 2.0 and sp.vel_d == 0.0
    for _ in range(400):  # within WPNAV_ACCEL and the jerk limit, still in 4 s
        mode.update(c, sp, 0.01)
    assert sp.vel_ne == (0.0, 0.0)


def test_guided_on_the_ground_without_takeoff_stays_put():
    mode = Guided()
    c = ctx(d_m=0.0, landed=True)
    mode.enter(c)
    mode.goto(c, 10.0, 0.0, -5.0)
    sp = Setpoint()
    mode.update(c, sp, 0.01)
    assert not sp.wants_climb(0.0)


def test_stabilize_lean_follows_sticks():
    mode = Stabilize()
    params = ParamStore()
    lean_max = math.radians(params["ANGLE_MAX"] / 100.0)
    c = ctx(pilot=PilotInput(roll=0.5, pitch=1.0, throttle=0.7), params=params)
    sp = Setpoint()
    mode.update(c, sp, 0.01)
    assert sp.lean == pytest.approx((0.5 * lean_max, -lean_max))  # stick forward: nose down
    assert sp.throttle == 0.7


# ----- flights through the vehicle ------------------------------------------------------------------
def test_rtl_from_low_altitude_climbs_before_returning():
    v = hovering_vehicle(5.0)
    v.guided_goto(20.0, 0.0, None)
    assert fly_until(v, lambda x: abs(x.body.n_m - 20.0) < 0.5 and abs(x.body.vn_m_s) < 0.2, 30.0)
    rtl_alt = v.params["RTL_ALT"] / 100.0
    assert v.set_mode(Rtl.number) == Result.ACCEPTED
    # While still below RTL_ALT - 1 m it has not started home.
    while altitude(v) < rtl_alt - 1.0:
        v.run_until(v.time_s + 0.05)
        assert v.body.n_m > 19.0
    assert fly_until(v, lambda x: x.body.n_m < 2.0, 30.0)
    assert altitude(v) == pytest.approx(rtl_alt, abs=0.5)


def test_rtl_from_above_rtl_alt_keeps_its_altitude():
    v = hovering_vehicle(20.0)
    v.guided_goto(15.0, 0.0, None)
    assert fly_until(v, lambda x: abs(x.body.n_m - 15.0) < 0.5, 30.0)
    v.set_mode(Rtl.number)
    assert fly_until(v, lambda x: x.body.n_m < 1.0, 30.0)
    assert altitude(v) == pytest.approx(20.0, abs=0.5)


def test_brake_stops_a_moving_vehicle_and_holds():
    v = hovering_vehicle(10.0)
    v.guided_velocity(5.0, 0.0, 0.0)
    v.run_until(v.time_s + 2.5)
    assert v.body.vn_m_s > 3.0
    assert v.set_mode(Brake.number) == Result.ACCEPTED
    assert fly_until(v, lambda x: math.hypot(x.body.vn_m_s, x.body.ve_m_s) < 0.1, 10.0)
    n_stop = v.body.n_m
    v.run_until(v.time_s + 3.0)
    assert abs(v.body.n_m - n_stop) < 0.5
    assert abs(altitude(v) - 10.0) < 0.5


def test_loiter_holds_then_flies_forward_with_the_stick():
    v = throttle_at_mid(hovering_vehicle(10.0))
    v.set_mode(Loiter.number)
    n0 = v.body.n_m
    v.run_until(v.time_s + 2.0)
    assert abs(v.body.n_m - n0) < 0.3
    for _ in range(30):  # 3 s of full forward stick, refreshed like a joystick would
        v.rc.hold_sticks(0.0, 1.0, 0.0, 0.5, v.time_s)
        v.run_until(v.time_s + 0.1)
    assert v.body.n_m > n0 + 5.0
    assert abs(v.body.e_m) < 1.0
    assert abs(altitude(v) - 10.0) < 1.0


def test_poshold_brakes_then_holds_and_leans_with_the_stick():
    v = throttle_at_mid(hovering_vehicle(10.0))
    v.guided_velocity(5.0, 0.0, 0.0)
    v.run_until(v.time_s + 2.5)
    assert v.body.vn_m_s > 3.0
    assert v.set_mode(PosHold.number) == Result.ACCEPTED
    assert fly_until(v, lambda x: math.hypot(x.body.vn_m_s, x.body.ve_m_s) < 0.1, 10.0)
    n_stop = v.body.n_m
    v.run_until(v.time_s + 3.0)
    assert abs(v.body.n_m - n_stop) < 0.5
    assert abs(altitude(v) - 10.0) < 0.5
    for _ in range(20):  # 2 s of right roll stick: a lean, not a velocity demand
        v.rc.hold_sticks(1.0, 0.0, 0.0, 0.5, v.time_s)
        v.run_until(v.time_s + 0.1)
    assert math.degrees(v.attitude[0]) > 10.0
    assert v.body.e_m > 2.0
    assert abs(altitude(v) - 10.0) < 1.0


def test_alt_hold_holds_altitude_with_centred_stick():
    v = throttle_at_mid(hovering_vehicle(8.0))
    v.set_mode(AltHold.number)
    v.run_until(v.time_s + 5.0)
    assert abs(altitude(v) - 8.0) < 0.3


@pytest.mark.parametrize("centred", ["CENTRED", "CENTRED_MANUAL"])
@pytest.mark.parametrize("angle_max, yaw_rate", [(1000, 1), (3000, 202.5), (8000, 500)])
def test_centred_sticks_give_the_very_setpoint_the_stick_expressions_give(centred, angle_max, yaw_rate):
    """Without pilot input the lean and yaw rate are constants (no parameter is read): the same
    bits, signed zeros included, as the sticks' expressions give for a copy of the centred input."""
    import dataclasses

    from firefly.autopilot import pilot as pilot_module
    from firefly.autopilot.modes.manual import pilot_lean_and_yaw
    params = ParamStore()
    params.set("ANGLE_MAX", angle_max)
    params.set("PILOT_Y_RATE", yaw_rate)
    centred_input = getattr(pilot_module, centred)
    fast, slow = Setpoint(), Setpoint()
    class Unread:  # the centred sticks must not read a parameter
        def __getitem__(self, name):
            raise AssertionError(f"{name} read for centred sticks")
    pilot_lean_and_yaw(SimpleNamespace(params=Unread()), fast, centred_input)
    pilot_lean_and_yaw(ctx(params=params), slow, dataclasses.replace(centred_input))  # not the constant
    bits = lambda values: [math.copysign(1.0, v) for v in values] + list(values)  # noqa: E731
    assert bits(fast.lean) == bits(slow.lean) and fast.lean == (0.0, -0.0)
    assert bits([fast.yaw_rate]) == bits([slow.yaw_rate]) and fast.yaw is slow.yaw is None

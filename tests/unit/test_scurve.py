"""The S-curve leg and the waypoint navigator: kinematic limits, continuity, arrival at rest,
and corners blended on the inside as ArduCopter flies them."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.control.scurve import SCurve, peak_speed
from firefly.autopilot.control.wpnav import NavLimits, WaypointNav
from firefly.autopilot.params import ParamStore

DT = 0.01


def leg(origin=(0.0, 0.0, -10.0), destination=(40.0, 0.0, -10.0), speed=5.0, accel=2.5, jerk=1.0,
        up=2.5, down=1.5, accel_z=1.0) -> SCurve:
    return SCurve(origin, destination, speed, up, down, accel, accel_z, jerk)


def samples(curve: SCurve, dt: float = 0.001):
    n = int(curve.duration / dt) + 2
    return [(i * dt, *curve.along(i * dt)) for i in range(n)]


@pytest.mark.parametrize("length,speed,accel,jerk", [
    (40.0, 5.0, 2.5, 1.0),     # accel limited by jerk: no constant-acceleration phase
    (100.0, 10.0, 1.0, 5.0),   # all seven phases
    (3.0, 5.0, 2.5, 1.0),      # too short to reach the cruise speed
    (0.05, 5.0, 2.5, 20.0),    # tiny
])
def test_profile_is_continuous_within_limits_and_ends_at_rest(length, speed, accel, jerk):
    c = leg(destination=(length, 0.0, -10.0), speed=speed, accel=accel, jerk=jerk)
    pts = samples(c)
    dt = pts[1][0]
    for (t0, s0, v0, a0), (t1, s1, v1, a1) in zip(pts, pts[1:]):
        assert v0 <= c.speed_max + 1e-9 and abs(a0) <= accel + 1e-9
        assert abs(a1 - a0) <= jerk * dt + 1e-9                    # jerk bound, acceleration continuous
        assert abs(v1 - v0 - (a0 + a1) / 2 * dt) <= jerk * dt * dt  # velocity is the integral of acceleration
        assert abs(s1 - s0 - (v0 + v1) / 2 * dt) <= accel * dt * dt  # position that of velocity
        assert s1 >= s0 - 1e-12                                     # never backs up
    assert c.along(c.duration) == (pytest.approx(length), 0.0, 0.0)
    s_end, v_end, a_end = c.along(c.duration - 1e-4)
    assert s_end == pytest.approx(length, abs=1e-6) and abs(v_end) < 1e-3 and abs(a_end) < 1e-2


def test_a_long_leg_cruises_at_the_speed_limit_and_a_short_one_peaks_lower():
    long, short = leg(), leg(destination=(3.0, 0.0, -10.0))
    assert long.peak == 5.0
    assert max(v for _, _, v, _ in samples(long)) == pytest.approx(5.0)
    assert short.peak == pytest.approx(peak_speed(3.0, 5.0, 2.5, 1.0)) and short.peak < 5.0
    assert max(v for _, _, v, _ in samples(short)) == pytest.approx(short.peak, rel=1e-3)


def test_a_climbing_leg_keeps_its_vertical_speed_within_wpnav_speed_up():
    c = leg(destination=(10.0, 0.0, -40.0))  # mostly up
    for t, _, v, a in samples(c, 0.01):
        _, vel, acc = c.target(t)
        assert -vel[2] <= 2.5 + 1e-9 and math.hypot(vel[0], vel[1]) <= 5.0 + 1e-9
        assert abs(acc[2]) <= 1.0 + 1e-9


def test_a_zero_length_leg_is_over_at_once():
    c = leg(destination=(0.0, 0.0, -10.0))
    assert c.duration == 0.0 and c.target(1.0)[0] == (0.0, 0.0, -10.0)


# ----- the navigator ------------------------------------------------------------------------------

def limits(speed_cms=500.0, **params) -> NavLimits:
    store = ParamStore()
    store.set("WPNAV_SPEED", speed_cms)
    for name, value in params.items():
        store.set(name, value)
    return NavLimits(store)


def perfect_follower(nav: WaypointNav, steps: int, on_tick=None) -> int:
    """Tick the navigator with a vehicle that is exactly on its target; returns the ticks run
    until reached (or `steps`)."""
    for i in range(steps):
        if nav.update(DT, nav.pos, nav.vel):
            return i
        if on_tick is not None:
            on_tick(nav)
    return steps


SQUARE = [(40.0, 0.0, -10.0), (40.0, 40.0, -10.0), (0.0, 40.0, -10.0), (0.0, 0.0, -10.0)]


def test_corners_are_blended_inside_and_the_targets_stay_continuous():
    nav = WaypointNav(limits(), (0.0, 0.0, -10.0))
    track = []
    previous = [nav.pos, nav.vel, nav.accel]

    def record(n):
        track.append(n.pos)
        for k in range(3):  # no jump in the target between ticks, also across a change of leg
            assert abs(n.pos[k] - previous[0][k]) <= 5.0 * DT * 1.01
            assert abs(n.vel[k] - previous[1][k]) <= 5.0 * DT * 1.01  # within the corner acceleration
        previous[:] = [n.pos, n.vel, n.accel]

    for i, corner in enumerate(SQUARE):
        following = SQUARE[i + 1] if i + 1 < len(SQUARE) else None
        nav.set_destination(corner, following)
        assert perfect_follower(nav, 3000, record) < 3000
    for corner in SQUARE[:3]:
        closest = min(math.hypot(p[0] - corner[0], p[1] - corner[1]) for p in track)
        # Cut, within the waypoint radius (checked for the turn started a tick earlier).
        assert 0.5 < closest < limits().radius * 1.01
    assert all(-0.01 <= p[0] <= 40.01 and -0.01 <= p[1] <= 40.01 for p in track)  # never outside the square


def test_a_waypoint_without_a_successor_is_reached_at_rest_within_the_radius():
    nav = WaypointNav(limits(), (0.0, 0.0, -10.0))
    nav.set_destination((20.0, 0.0, -10.0))
    # A vehicle stuck at the origin never reaches it, however long the leg's clock runs.
    for _ in range(3000):
        assert not nav.update(DT, (0.0, 0.0, -10.0), (0.0, 0.0, 0.0))
    nav2 = WaypointNav(limits(), (0.0, 0.0, -10.0))
    nav2.set_destination((20.0, 0.0, -10.0))
    perfect_follower(nav2, 3000)
    assert nav2.reached and nav2.pos == pytest.approx((20.0, 0.0, -10.0)) and nav2.vel == (0.0, 0.0, 0.0)


def test_the_clock_slows_while_the_vehicle_lags_behind():
    nav = WaypointNav(limits(), (0.0, 0.0, -10.0))
    nav.set_destination((40.0, 0.0, -10.0))
    for _ in range(500):  # the vehicle does not move: the target must not run away to the end
        nav.update(DT, (0.0, 0.0, -10.0), (0.0, 0.0, 0.0))
    assert nav.pos[0] < 10.0


def test_a_new_destination_mid_leg_starts_from_where_the_vehicle_can_stop():
    """ArduCopter's stopping point: from the vehicle's position and velocity (not the target's),
    by the square-root controller's distance: past the speed accel/P it is accel/(2P^2) +
    v^2/(2 accel); below it a whole second of travel, v/P."""
    nav = WaypointNav(limits(), (0.0, 0.0, -10.0))
    nav.set_destination((40.0, 0.0, -10.0))
    perfect_follower(nav, 600)
    speed = nav.vel[0]
    assert speed > 4.0
    vehicle_pos, vehicle_vel = (nav.pos[0] - 1.0, 0.5, -10.0), (speed, 0.0, 0.0)
    nav.update(DT, vehicle_pos, vehicle_vel)
    nav.set_destination((40.0, 30.0, -10.0))
    stop = vehicle_pos[0] + 2.5 / 2 + speed * speed / (2 * 2.5)
    nav.update(DT, vehicle_pos, vehicle_vel)
    assert nav.pos[0] == pytest.approx(stop) and nav.pos[1] == pytest.approx(0.5, abs=0.01)  # from rest there


def test_a_slow_vehicle_stops_a_second_of_travel_ahead_and_within_the_vertical_caps():
    nav = WaypointNav(limits(), (0.0, 0.0, -10.0), velocity=(1.0, 0.0, -4.0))  # 1 m/s on, climbing 4 m/s
    nav.set_destination((0.0, 20.0, -10.0))
    nav.update(DT, (0.0, 0.0, -10.0), (1.0, 0.0, -4.0))
    assert nav.pos[0] == pytest.approx(1.0 / 1.0)            # v / PSC_POSXY_P
    assert nav.pos[2] == pytest.approx(-10.0 - 3.0)          # climbing: at most 3 m higher

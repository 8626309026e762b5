"""MAV_CMD_EXTERNAL_POSITION_ESTIMATE: a client's position for a dead-reckoning EKF, answered in
each state as ArduCopter SITL answers it (parity area extnav, probes external_position_estimate*),
the estimate's jump and the point held with it, and what a returning GPS does."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.c_casts import as_uint32
from firefly.autopilot.estimate import AIDING_STOPS_S, GPS_GLITCH_RESET_S, POSITION_FUSED_RECENTLY_S
from firefly.autopilot.mavlink.dialect import mavlink as mav
from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.mavlink.session import Session
from firefly.autopilot.modes import ModeNumber
from firefly.autopilot.results import Result

from ..fuzz.checks import vehicle_problems
from ._util import client_codec, fly_until, hovering_vehicle, ready_vehicle, wire
from .test_external_nav import EXTNAV, speak, texts

CMD = mav.MAV_CMD_EXTERNAL_POSITION_ESTIMATE
EARTH_R = 6378137.0


def lat_lon_e7(v, n: float, e: float) -> tuple[int, int]:
    """The point n, e metres from the vehicle's origin (the sim's frame), in degrees e7."""
    o = v.origin
    return (round((o.lat_deg + math.degrees(n / EARTH_R)) * 1e7),
            round((o.lon_deg + math.degrees(e / (EARTH_R * math.cos(math.radians(o.lat_deg))))) * 1e7))


def told(session, v, n: float = 0.0, e: float = 0.0, *, p1: float | None = None, p2: float = 0.0, p3: float = 1.0,
         frame: int = mav.MAV_FRAME_GLOBAL_INT, z: float = math.nan, xy: tuple[int, int] | None = None) -> list[int]:
    """COMMAND_INT 43003 for the point n, e (or x, y as given); every ACK it got."""
    x, y = xy if xy is not None else lat_lon_e7(v, n, e)
    p1 = v.time_s if p1 is None else p1  # the sender's clock: no two sends alike (no retry replayed)
    msg = client_codec().command_int_encode(1, 1, frame, CMD, 0, 0, p1, p2, p3, 0.0, x, y, z)
    return [m.result for m in session.receive(wire(msg), v.time_s, 0.0) if m.get_type() == "COMMAND_ACK"]


def truth(v) -> tuple[float, float]:
    b = v.estimate.sim.state.body
    return b.n_m, b.e_m


def believed_less_true(v) -> tuple[float, float]:
    t = truth(v)
    return v.body.n_m - t[0], v.body.e_m - t[1]


def lose_gps(v, for_s: float) -> float:
    v.params.set("SIM_GPS1_ENABLE", 0)
    lost = v.time_s
    v.run_until(lost + for_s)
    return lost


def test_command_long_is_unsupported_and_a_frame_or_an_altitude_denied_in_any_state():
    v = ready_vehicle()
    session = Session(v, new_codec(1))
    lose_gps(v, 3.0)  # a state in which the point would be taken
    long = client_codec().command_long_encode(1, 1, CMD, 0, v.time_s, 0, 1, 0, -35.36, 149.16, math.nan)
    assert [m.result for m in session.receive(wire(long), v.time_s, 0.0)] == [mav.MAV_RESULT_UNSUPPORTED]
    for frame in (mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT, mav.MAV_FRAME_LOCAL_NED):
        assert told(session, v, 20.0, frame=frame) == [mav.MAV_RESULT_DENIED]
    for z in (0.0, 584.0, math.inf):
        assert told(session, v, 20.0, z=z) == [mav.MAV_RESULT_DENIED]
    assert v.estimate.position_offset_ne is None and texts(v) == []
    assert told(session, v, 20.0, frame=mav.MAV_FRAME_GLOBAL) == [mav.MAV_RESULT_ACCEPTED]  # GLOBAL as GLOBAL_INT


def test_refused_while_the_gps_is_in_use_and_for_a_second_after_it_goes():
    v = ready_vehicle()
    session = Session(v, new_codec(1))
    assert told(session, v, 20.0) == [mav.MAV_RESULT_FAILED]
    lost = lose_gps(v, POSITION_FUSED_RECENTLY_S - 0.2)
    assert told(session, v, 20.0) == [mav.MAV_RESULT_FAILED]
    v.run_until(lost + POSITION_FUSED_RECENTLY_S + 0.2)
    assert told(session, v, 20.0) == [mav.MAV_RESULT_ACCEPTED]


def test_taken_while_dead_reckoning_the_estimate_jumps_at_once_and_nothing_is_said():
    v = ready_vehicle()
    session = Session(v, new_codec(1))
    lose_gps(v, 2.0)
    texts(v)
    true_before = truth(v)
    assert told(session, v, true_before[0] + 20.0, true_before[1] - 5.0) == [mav.MAV_RESULT_ACCEPTED]
    assert believed_less_true(v) == pytest.approx((20.0, -5.0), abs=0.01)
    assert truth(v) == true_before and texts(v) == []
    v.run_until(v.time_s + 3.0)  # held while dead-reckoning: it does not decay back
    assert believed_less_true(v) == pytest.approx((20.0, -5.0), abs=0.01)


def test_refused_once_the_ekf_stops_aiding_and_without_a_gps_at_all():
    v = ready_vehicle()
    session = Session(v, new_codec(1))
    lost = lose_gps(v, AIDING_STOPS_S - 0.5)
    assert told(session, v, 20.0) == [mav.MAV_RESULT_ACCEPTED]  # the EKF failsafe's time has passed: still taken
    v.run_until(lost + AIDING_STOPS_S + 0.5)
    assert told(session, v, 0.0) == [mav.MAV_RESULT_FAILED]
    blind = ready_vehicle({"GPS1_TYPE": 0})
    session = Session(blind, new_codec(1))
    blind.run_until(5.0)
    assert told(session, blind, 20.0) == [mav.MAV_RESULT_FAILED]  # no origin, no position
    assert blind.set_gps_global_origin(-35.3632621, 149.1652374, 584.0)
    blind.run_until(blind.time_s + 2.0)
    assert told(session, blind, 20.0) == [mav.MAV_RESULT_FAILED]  # an origin, still no position source
    assert blind.home_ned is None  # ArduCopter sets no home without a position either


def test_in_a_hover_the_point_held_moves_with_the_estimate_and_the_vehicle_stays():
    v = hovering_vehicle()
    session = Session(v, new_codec(1))
    lose_gps(v, 2.0)
    here = truth(v)
    assert told(session, v, here[0] + 20.0, here[1]) == [mav.MAV_RESULT_ACCEPTED]
    v.run_until(v.time_s + 4.0)
    assert math.dist(truth(v), here) < 0.2 and believed_less_true(v)[0] == pytest.approx(20.0, abs=0.01)
    assert v.mode.number == ModeNumber.GUIDED


def test_a_gps_back_far_from_a_told_position_is_a_glitch_then_the_estimate_resets_to_it():
    v = hovering_vehicle()
    session = Session(v, new_codec(1))
    lost = lose_gps(v, 2.0)
    here = truth(v)
    assert told(session, v, here[0] + 20.0, here[1]) == [mav.MAV_RESULT_ACCEPTED]  # 1 m accurate
    texts(v)
    v.params.set("SIM_GPS1_ENABLE", 1)
    v.run_until(lost + GPS_GLITCH_RESET_S - 0.5)
    assert believed_less_true(v)[0] == pytest.approx(20.0, abs=0.01) and v.gps_glitching
    assert told(session, v, here[0]) == [mav.MAV_RESULT_ACCEPTED]  # the fix is not fused: still dead-reckoning
    assert told(session, v, here[0] + 20.0) == [mav.MAV_RESULT_ACCEPTED]
    v.run_until(lost + GPS_GLITCH_RESET_S + 0.5)
    assert believed_less_true(v) == pytest.approx((0.0, 0.0), abs=0.01)
    v.run_until(v.time_s + 3.0)
    assert math.dist(truth(v), here) < 0.2  # reset: the point held followed it
    assert told(session, v, here[0] + 20.0) == [mav.MAV_RESULT_FAILED]  # the GPS in use again
    assert texts(v) == ["GPS Glitch or Compass error"]  # EKF3 calls it well after 10 s of good fixes
    v.run_until(lost + GPS_GLITCH_RESET_S + 10.6)
    assert texts(v) == ["Glitch cleared"] and not v.gps_glitching


@pytest.mark.parametrize(("north_m", "accuracy_m", "flies"), [(20.0, 30.0, False), (8.0, 1.0, True), (20.0, 5.0, True)])
def test_a_gps_back_is_reset_to_or_fused_by_the_told_accuracy(north_m, accuracy_m, flies):
    """Measured: 30 m accurate, the EKF resets to the fix at once (the vehicle stays); within its
    gate the fix is fused instead, and the vehicle flies to the point it held, the told error."""
    v = hovering_vehicle()
    session = Session(v, new_codec(1))
    lose_gps(v, 2.0)
    here = truth(v)
    assert told(session, v, here[0] + north_m, here[1], p3=accuracy_m) == [mav.MAV_RESULT_ACCEPTED]
    v.params.set("SIM_GPS1_ENABLE", 1)
    v.run_until(v.time_s + 0.3)
    assert believed_less_true(v) == pytest.approx((0.0, 0.0), abs=0.01) and not v.gps_glitching
    fly_until(v, lambda x: False, 10.0)
    assert abs(truth(v)[0] - here[0] - (north_m if flies else 0.0)) < 0.5


def test_a_gps_back_after_the_position_was_lost_is_taken_at_once():
    v = hovering_vehicle()
    session = Session(v, new_codec(1))
    lost = lose_gps(v, 2.0)
    assert told(session, v, *[x + d for x, d in zip(truth(v), (20.0, 0.0))]) == [mav.MAV_RESULT_ACCEPTED]
    assert fly_until(v, lambda x: x.mode.number == ModeNumber.LAND, 10.0)  # the EKF failsafe all the same
    assert v.time_s - lost == pytest.approx(8.0, abs=0.5)
    v.params.set("SIM_GPS1_ENABLE", 1)
    v.run_until(v.time_s + 0.3)
    assert believed_less_true(v) == pytest.approx((0.0, 0.0), abs=0.01) and not v.gps_glitching


def test_the_processing_time_moves_the_point_on_by_the_velocity_for_at_most_5_s():
    v = hovering_vehicle()
    session = Session(v, new_codec(1))
    assert v.guided_velocity(2.0, 0.0, 0.0) == Result.ACCEPTED
    v.run_until(v.time_s + 5.0)
    lose_gps(v, 2.0)
    for p2, age_s in ((0.0, 0.0), (1.5, 1.5), (10.0, 5.0), (-1.0, 0.0), (math.nan, 0.0), (math.inf, 0.0), (1e10, 0.0)):
        here, speed = truth(v), v.estimate.sim.state.body.vn_m_s
        assert told(session, v, here[0], here[1], p2=p2) == [mav.MAV_RESULT_ACCEPTED]
        assert believed_less_true(v)[0] == pytest.approx(speed * age_s, abs=0.01), p2
        v.run_until(v.time_s + 0.1)


def test_as_uint32_is_x86s_cast():
    assert as_uint32(1500.0) == 1500 and as_uint32(-1000.0) == 2**32 - 1000
    assert as_uint32(1e13) == int(1e13) % 2**32 and as_uint32(math.nan) == 0 and as_uint32(1e30) == 0


def test_hostile_values_get_one_answer_and_leave_the_estimate_finite():
    v = hovering_vehicle()
    session = Session(v, new_codec(1))
    lose_gps(v, 2.0)
    hostile = (math.nan, math.inf, -math.inf, 1e38, -1e38, 0.0)
    for p in hostile:
        for which in ("p1", "p2", "p3"):
            assert len(told(session, v, *truth(v), **{which: p})) == 1
    assert all(math.isfinite(x) for x in believed_less_true(v))
    off_globe = ((950_000_000, 0), (0, 2_000_000_000), (2**31 - 1, 2**31 - 1), (-(2**31 - 1), -(2**31 - 1)))
    before = believed_less_true(v)
    for xy in off_globe:  # ArduCopter takes these and goes astray by thousands of km; Firefly stays
        assert told(session, v, xy=xy) == [mav.MAV_RESULT_ACCEPTED]
        assert believed_less_true(v) == before
    assert told(session, v, xy=(0, 0)) == [mav.MAV_RESULT_ACCEPTED]  # 0, 0 is a place, thousands of km away
    assert math.hypot(*believed_less_true(v)) > 1e6
    session.poll(v.time_s, 0.0)  # telemetry of a vehicle that far off still goes out
    v.run_until(v.time_s + 1.0)
    assert v.mode.number == ModeNumber.GUIDED and not vehicle_problems(v, session)


def test_on_external_navigation_it_is_taken_only_once_the_poses_stop():
    v = ready_vehicle(EXTNAV)
    session = Session(v, new_codec(1))
    speak(v, v.time_s + 1.0)
    assert told(session, v, 20.0) == [mav.MAV_RESULT_FAILED]  # no origin
    v.set_gps_global_origin(-35.3632621, 149.1652374, 584.0)
    speak(v, v.time_s + 1.0)
    assert told(session, v, 20.0) == [mav.MAV_RESULT_FAILED]  # the poses are fused
    v.run_until(v.time_s + 1.5)
    assert told(session, v, truth(v)[0] + 20.0, truth(v)[1]) == [mav.MAV_RESULT_ACCEPTED]
    assert believed_less_true(v)[0] == pytest.approx(20.0, abs=0.01)
    speak(v, v.time_s + 2.0)  # the poses again: held off by the gate (measured: 19.9 m after 2 s)
    assert believed_less_true(v)[0] == pytest.approx(20.0, abs=0.01)
    speak(v, v.time_s + 8.0)  # then taken (measured: 0 after 10 s)
    assert believed_less_true(v)[0] == pytest.approx(0.0, abs=0.01)
